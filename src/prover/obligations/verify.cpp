// SPDX-License-Identifier: GPL-3.0-or-later
// verify() and the bookkeeping around the obligations: each obligation in kObligationIds order,
// claimed or not, skipped when not requested or nothing is declared for it, undecided when its
// decision would exceed a limit (LimitExceeded), and timed. The obligations themselves are in
// the other files of this folder, one per obligation, each with the lemma of proofs/README.md
// that makes its finite check a proof.
#include "prover/obligations/prover.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace impactcert {

const char* to_string(Verdict v) {
    switch (v) {
    case Verdict::proved: return "proved";
    case Verdict::refuted: return "refuted";
    case Verdict::skipped: return "skipped";
    case Verdict::undecided: return "undecided";
    }
    return "?";
}

bool VerifyReport::passed() const {
    return std::all_of(obligations.begin(), obligations.end(), [](const ObligationResult& o) {
        return !o.claimed || o.verdict == Verdict::proved;
    });
}

const char* VerifyReport::verdict() const {
    bool undecided = false;
    for (const auto& o : obligations) {
        if (!o.claimed)
            continue;
        if (o.verdict == Verdict::refuted)
            return "refuted";
        undecided = undecided || o.verdict != Verdict::proved;
    }
    return undecided ? "undecided" : "proved";
}

int VerifyReport::exit_status() const {
    const std::string v = verdict();
    return v == "proved" ? 0 : v == "refuted" ? 1 : 3;
}

const ObligationResult& VerifyReport::at(const std::string& id) const {
    for (const auto& o : obligations)
        if (o.id == id)
            return o;
    throw std::out_of_range("no obligation " + id);
}

// ---------------------------------------------------------------------------------------------
// Shared by the obligations (prover.hpp)

namespace detail {

// Internal consistency: a refutation whose witness does not witness is a bug in impactcert.
void ensure(bool ok, const char* what) {
    if (!ok)
        throw std::logic_error(std::string("internal witness check failed: ") + what);
}

bool nonnegative(const Vector& v) {
    return std::all_of(v.begin(), v.end(), [](const Rational& x) { return sign_of(x) != Sign::negative; });
}

Outcome refute(Outcome o, Json witness) {
    o.proved = false;
    o.counterexample = std::move(witness);
    return o;
}

Json certificate_json(const CopositivityResult& r) {
    Json c;
    c["method"] = to_string(r.method);
    switch (r.method) {
    case CopositivityMethod::nonnegative_entries:
        break;
    case CopositivityMethod::psd_plus_nonnegative:
        c["N"] = to_json(r.N);
        [[fallthrough]];
    case CopositivityMethod::psd:
        c["L"] = to_json(r.ldl.L);
        c["D"] = to_json(r.ldl.D);
        break;
    case CopositivityMethod::kkt_enumeration: {
        Json cands = Json::array();
        for (const auto& k : r.candidates) {
            Json support = Json::array();
            for (auto i : k.support)
                support.push_back(i);
            cands.push_back(Json{{"support", support}, {"x", to_json(k.x)}, {"value", to_json(k.value)}});
        }
        c["candidates"] = cands;
        c["minimum"] = to_json(r.minimum);
        break;
    }
    }
    return c;
}

// ---------------------------------------------------------------------------------------------
// The Prover: every obligation in order, each through the dispatch

VerifyReport Prover::run() {
    VerifyReport report;
    report.law = m_.law().name;
    for (const char* id : obligation_ids(m_.has_friction())) {
        const auto start = std::chrono::steady_clock::now();
        ObligationResult r;
        r.id = id;
        r.claimed = m_.claimed(id);
        r.friction = m_.has_friction();
        if (only_ && std::find(only_->begin(), only_->end(), r.id) == only_->end()) {
            r.verdict = Verdict::skipped;
            r.method = "not requested";
        } else if (!m_.applies(id)) {
            r.verdict = Verdict::skipped;
            r.method = r.id == "P3" ? (m_.redundant() ? "not applicable on dependent contact columns" : "not applicable with friction")
                                    : "nothing declared";
        } else {
            try {
                Outcome o = dispatch(r.id);
                r.verdict = o.proved ? (o.limit.empty() ? Verdict::proved : Verdict::undecided) : Verdict::refuted;
                r.limit = o.limit;
                r.checks = o.checks;
                r.method = o.method;
                r.counterexample = std::move(o.counterexample);
                r.data = std::move(o.data);
            } catch (const LimitExceeded& e) {
                r.verdict = Verdict::undecided;
                r.method = "exact decision beyond a limit";
                r.limit = std::string(e.what()) + " (raise it with " + e.option + ")";
                r.data = Json::object();
            }
        }
        r.elapsed = std::chrono::steady_clock::now() - start;
        if (sink_) {
            (*sink_)(r);
            r.data = Json::object(); // written: not held
        }
        report.obligations.push_back(std::move(r));
    }
    return report;
}

Outcome Prover::dispatch(const std::string& id) {
    if (id == "fan") return fan();
    if (id == "P1") return p1();
    if (id == "P2") return p2();
    if (id == "P3") return p3();
    if (id == "kinematic") return kinematic();
    if (id == "kinetic") return kinetic();
    if (id == "coulomb") return coulomb();
    if (id == "energetic") return energetic();
    if (id == "identities") return identities();
    if (id == "single-impacts") return single_impacts();
    if (id == "nonexpansive") return nonexpansive();
    if (id == "nonexpansive-lemma") return nonexpansive_lemma();
    if (id == "outcomes") return outcomes();
    if (id == "symmetries") return symmetries_outcome();
    throw std::logic_error("unknown obligation " + id);
}

} // namespace detail

VerifyReport verify(const Model& model, const Limits& limits, const Progress& progress,
                    const std::vector<std::string>* only) {
    return detail::Prover(model, limits, progress, only).run();
}

VerifyReport verify_streaming(const Model& model, const Limits& limits, const Progress& progress,
                              const ResultSink& sink) {
    return detail::Prover(model, limits, progress, nullptr, &sink).run();
}

} // namespace impactcert
