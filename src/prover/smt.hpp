// SPDX-License-Identifier: GPL-3.0-or-later
// smt.hpp -- SMT-LIB2 encodings of the universal claims, for an independent second decision.
//
// Contract: smt_problems(model) returns one self-contained SMT-LIB2 script per universal claim
// (fan, P1, P2, P3, kinematic, kinetic, energetic, nonexpansive). Each asserts the *negation*
// of the claim over the reals (QF_NRA: the law is written as nested `ite` over the cones, the
// cones as linear inequalities in cone coordinates), so a solver answers `unsat` exactly when
// the claim holds and `sat` (with a model: a counterexample) when it fails. Nothing here shares
// the prover's reductions: the formulas state the claims directly.
#pragma once

#include "model/law.hpp"

#include <string>
#include <vector>

namespace impactcert {

struct SmtProblem {
    std::string id;     // obligation id
    std::string script; // SMT-LIB2 text, ends with (check-sat)
};

std::vector<SmtProblem> smt_problems(const Model& model);

} // namespace impactcert
