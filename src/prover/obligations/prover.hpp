// SPDX-License-Identifier: GPL-3.0-or-later
// prover.hpp -- internal to src/prover/obligations/: the Prover behind verify() (obligations.hpp).
//
// Contract: one Prover decides the obligations of one Model, each in its own file
// (src/prover/obligations/<obligation>.cpp, which opens with the lemma of proofs/README.md it relies
// on); verify.cpp runs them in kObligationIds order and does the bookkeeping. What several
// obligations share lives here: the fan's decision and S's domain (computed once; a limit
// exceeded is remembered and rethrown to every obligation that needs them), P1's outcome
// (reused by nonexpansive-lemma), the limits and the progress callback. A refutation is
// re-validated with `ensure` before it is returned.
#pragma once

#include "exact/copositivity.hpp"
#include "prover/fan.hpp"
#include "base/json.hpp"
#include "prover/obligations.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace impactcert::detail {

// Internal consistency: a refutation whose witness does not witness is a bug in impactcert.
void ensure(bool ok, const char* what);

bool nonnegative(const Vector& v);

// The outcome of one obligation before bookkeeping.
struct Outcome {
    bool proved = true;
    std::size_t checks = 0;
    std::string method;
    Json counterexample;
    Json data = Json::object();
    std::string limit; // a shard's slice that stopped at a limit: undecided, keeping its evidence
};

Outcome refute(Outcome o, Json witness);

// A copositivity decision as the certificate's evidence (schema: proofs/README.md).
Json certificate_json(const CopositivityResult& r);

// The verified symmetries: for each declared symmetry the permutation sigma of the pieces
// (P C_i = C_sigma(i)), and the least piece of each orbit of the group they generate, ascending.
struct SymmetryData {
    std::vector<std::vector<std::size_t>> sigma;
    std::vector<std::size_t> representatives;
    bool orthant_preserving = false; // every P' is a non-negative monomial matrix
};

class Prover {
  public:
    Prover(const Model& m, const Limits& limits, const Progress& progress, const std::vector<std::string>* only,
           const ResultSink* sink = nullptr)
        : m_(m), c_(m.contacts()), pieces_(m.pieces()), limits_(limits), progress_(progress), only_(only),
          sink_(sink) {}

    VerifyReport run();

  private:
    const Model& m_;
    std::size_t c_;
    const std::vector<Piece>& pieces_;
    const Limits& limits_;
    const Progress& progress_;
    const std::vector<std::string>* only_;
    const ResultSink* sink_; // when given, each result goes there as soon as it is decided
    std::optional<FanResult> fan_;
    std::optional<LimitExceeded> fan_limit_; // the fan's decision exceeded a limit
    std::optional<Outcome> p1_;
    struct Discontinuity {
        std::size_t a, b;
        Vector ray;
    };
    std::optional<Discontinuity> p1_discontinuity_; // P1 refuted: its pieces and ray
    std::optional<LimitExceeded> p1_limit_;
    std::optional<DomainResult> domain_;
    std::optional<Outcome> symmetries_;
    std::optional<SymmetryData> symmetry_data_;

    void report_progress(const std::string& id, std::size_t done, std::size_t total) const {
        if (progress_)
            progress_(id, std::to_string(done) + "/" + std::to_string(total));
    }

    const std::string& name(std::size_t p) const { return pieces_[p].name; }

    Json names_of(const std::vector<std::size_t>& ps) const {
        Json out = Json::array();
        for (auto p : ps)
            out.push_back(name(p));
        return out;
    }

    Outcome dispatch(const std::string& id); // verify.cpp

    // fan.cpp: the fan, and S's domain for the obligations about the function S.
    const FanResult& fan_result();
    const DomainResult& domain();
    Outcome fan();
    std::optional<Json> domain_witness();

    // p1.cpp
    Json p1_witness(std::size_t i, std::size_t j, const Vector& x);
    Outcome p1();
    Outcome p1_shared_rays();
    Outcome p1_intersections(bool across_walls);

    Outcome p2();             // p2.cpp
    Outcome p3();             // p3.cpp
    Outcome kinematic();      // kinematic.cpp
    Outcome kinetic();        // kinetic.cpp (with friction: the friction cone)
    Outcome coulomb();        // coulomb.cpp (laws with friction)
    Outcome polygon_forms(Outcome o); // coulomb.cpp: friction polygons (Lemma P)
    bool in_friction_cone(const Vector& impulse) const; // kinetic.cpp
    Outcome energetic();      // energetic.cpp
    Outcome identities();     // identities.cpp
    Outcome single_impacts(); // single_impacts.cpp

    // symmetries.cpp: the obligation, and what the others take from it. symmetry() is null
    // unless the law declares symmetries and they are proved; orbit_representatives() is then
    // one piece per orbit, else every piece.
    Outcome decide_symmetries();
    const Outcome& symmetries_outcome();
    const SymmetryData* symmetry();
    std::vector<std::size_t> orbit_representatives();
    std::string by_symmetries(); // the note on a method reduced by the symmetries, or ""
    // P3 and kinematic: one piece per orbit when moreover every P' maps the orthant onto itself.
    std::vector<std::size_t> orthant_representatives();

    // nonexpansive.cpp (pair_witness is also the lemma's witness)
    Json pair_witness(std::size_t i, std::size_t j, const Vector& gamma_a, const Vector& gamma_b);
    Matrix pair_form(std::size_t i, std::size_t j) const;
    std::string method_summary(const std::size_t (&by_method)[4]);
    Outcome nonexpansive();
    Json discontinuity_pair(const Discontinuity& d); // the interior pair near P1's ray

    Outcome nonexpansive_lemma(); // nonexpansive_lemma.cpp
    Outcome outcomes();           // outcomes.cpp
};

} // namespace impactcert::detail
