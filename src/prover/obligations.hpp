// SPDX-License-Identifier: GPL-3.0-or-later
// obligations.hpp -- every proof obligation of SPEC section 3, decided exactly.
//
// Contract: verify(model) evaluates all twelve obligations in kObligationIds order, claimed or
// not (an obligation the law declares nothing for is `skipped`; one whose exact decision would
// exceed a limit of `limits` is `undecided`, with the limit and its option in `limit`). Each result carries the number
// of exact checks done and, when refuted, an exact counterexample as JSON with rationals as
// strings (the shapes are listed in proofs/README.md). A refutation is always re-validated
// internally before it is returned: a witness that does not witness is a std::logic_error.
// The reductions from universal statements to these finite checks are argued in
// proofs/README.md; each obligation is decided in its own file under src/prover/obligations/, which
// opens with the lemma it relies on.
#pragma once

#include "base/json.hpp"
#include "model/law.hpp"
#include "base/limits.hpp"

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace impactcert {

enum class Verdict { proved, refuted, skipped, undecided };
const char* to_string(Verdict v);

struct ObligationResult {
    std::string id;
    bool claimed = false;
    Verdict verdict = Verdict::skipped;
    std::size_t checks = 0;               // exact checks done
    std::string method;                   // how the finite check was made
    Json counterexample;                  // null unless refuted
    std::string limit;                    // undecided: the limit reached and the option raising it
    Json data;                            // what was checked: the certificate's evidence
    std::chrono::nanoseconds elapsed{0};  // wall time of this obligation
    bool friction = false;                // the law has friction (the statements of section 9)
};

struct VerifyReport {
    std::string law;
    std::vector<ObligationResult> obligations;
    // The gate: every claimed obligation proved.
    bool passed() const;
    // "proved" (every claim proved), "refuted" (a claim refuted), else "undecided".
    const char* verdict() const;
    int exit_status() const; // 0 proved, 1 refuted, 3 undecided
    const ObligationResult& at(const std::string& id) const; // throws std::out_of_range
};

// Progress on long runs: called now and then with the obligation id and a one-line status.
using Progress = std::function<void(const std::string& id, const std::string& status)>;

// only: when given, the obligations outside it are `skipped` ("not requested") without cost.
VerifyReport verify(const Model& model, const Limits& limits = {}, const Progress& progress = {},
                    const std::vector<std::string>* only = nullptr);

// The same, handing each obligation's result to `sink` as soon as it is decided; the report then
// keeps everything but the evidence (`data`), so that a certificate can be written one
// obligation at a time (certificate.hpp, CertificateWriter).
using ResultSink = std::function<void(ObligationResult&)>; // may move the evidence out
VerifyReport verify_streaming(const Model& model, const Limits& limits, const Progress& progress,
                              const ResultSink& sink);

} // namespace impactcert
