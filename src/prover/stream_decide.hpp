// SPDX-License-Identifier: GPL-3.0-or-later
// stream_decide.hpp -- internal to stream_verify.cpp and stream_fan.cpp: the decisions of
// verify --stream over an Expansion (stream.hpp, stream_store.hpp; proofs/README.md, "Streamed
// laws"). Streamed::run() decides every obligation, each pass in its own member: the fan and the
// outcomes' pieces in stream_fan.cpp (membership), the others in stream_verify.cpp.
#pragma once

#include "prover/obligations.hpp"
#include "prover/stream_store.hpp"

#include <chrono>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace impactcert::stream {

inline constexpr const char* kRerun = " (verify without --stream decides it, memory permitting)";
inline constexpr std::size_t kMaxOrbits = 64;

struct Decision {
    Verdict verdict = Verdict::proved;
    std::size_t checks = 0;
    std::string method;
    Json counterexample;
    std::string limit;
    std::chrono::nanoseconds elapsed{0}; // of the pass that decided it (shared passes: the first obligation)
};

inline Decision undecided(Decision d, const std::string& why) {
    d.verdict = Verdict::undecided;
    d.limit = why + kRerun;
    return d;
}

inline Decision refuted(Decision d, Json witness) {
    d.verdict = Verdict::refuted;
    d.counterexample = std::move(witness);
    return d;
}

inline void ensure(bool ok, const char* what) {
    if (!ok)
        throw std::logic_error(std::string("internal witness check failed (--stream): ") + what);
}

class Streamed {
  public:
    Streamed(Expansion& ex, const Limits& limits, const Progress& progress)
        : ex_(ex), c_(ex.c), n_(ex.store.size()), limits_(limits), progress_(progress) {}

    std::map<std::string, Decision> run();

  private:
    Expansion& ex_;
    std::size_t c_, n_;
    const Limits& limits_;
    const Progress& progress_;
    std::map<std::string, Decision> d_;

    void report(const char* id, std::size_t done) const {
        if (progress_ && done % 65536 == 0)
            progress_(id, std::to_string(done) + "/" + std::to_string(n_));
    }
    bool proved(const char* id) const { return d_.at(id).verdict == Verdict::proved; }

    Law side_law() const {
        Law s;
        s.name = ex_.law.name;
        s.masses = ex_.law.masses;
        s.M = ex_.law.M;
        s.W = ex_.law.W;
        return s;
    }
    // verify() on a model of the given pieces, for the obligations in `ids`.
    VerifyReport side_verify(Law law, const std::vector<std::string>& ids) const {
        Limits l = limits_;
        l.evidence = false;
        const Model m(std::move(law), limits_.max_pieces, limits_.max_memory_mb);
        return verify(m, l, {}, &ids);
    }
    // A per-piece check failed on piece p: verify()'s own witness, on the one-piece model.
    Json piece_witness(u32 p, const std::string& id) const {
        Law one = side_law();
        one.pieces.push_back(ex_.decl(p));
        const VerifyReport r = side_verify(std::move(one), {id});
        ensure(r.at(id).verdict == Verdict::refuted, "the one-piece model refutes what the stream refuted");
        return r.at(id).counterexample;
    }
    Json pair_witness(u32 a, u32 b, const Matrix& Qa, const Matrix& Qb, const Vector& ga, const Vector& gb) const;
    bool in_interior(u32 p, const Vector& x) const {
        const auto s = solve(ex_.R(p), x);
        return s && std::all_of(s->begin(), s->end(), [](const Rational& v) { return sign_of(v) == Sign::positive; });
    }

    void symmetries();
    void membership(); // fan and outcomes
    void by_rays();    // P1, P3, kinematic, kinetic
    void by_listed();  // P2, energetic, identities, single-impacts
    void nonexpansive();
    void nonexpansive_lemma();

    // membership's findings, for the outcomes
    std::vector<u32> outcome_piece_; // first piece containing gamma-, kNone if none
};

} // namespace impactcert::stream
