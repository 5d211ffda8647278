// SPDX-License-Identifier: GPL-3.0-or-later
// sweep_point.hpp -- internal to sweep*.cpp and threshold.cpp: the law a sweep names at one point
// of its parameters.
//
// Contract:
//   - law_at(spec, values) (one value per spec.parameters) derives the law: a chain by --masses
//     (names resolved), or the system/scene with the parameters applied (mu: every friction
//     coefficient, muK: contact K's, e: every normal restitution, eK: contact K's); the
//     restitution is --restitution's items (names resolved; one for every contact or one per
//     contact), else the system's own (a scene's), else 1; the law is --law's kind. The result
//     is ok with the law, not-finite (a gamma- beyond --max-impacts, with its word),
//     not-a-function (friction: the derivation's witness, as `derive --json` gives it) or
//     undecided (a derivation limit, named).
//   - validate_parameters(spec) refuses, before any work (InputError, one line), a parameter that
//     is not used, a system parameter that names no contact (or a frictionless one), a value
//     outside its range (masses positive, restitution in [0, 1], mu >= 0) at any grid value,
//     and the Poisson law with friction. spec.parameters must have their values.
#pragma once

#include "sweep/sweep.hpp"
#include "model/law.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert::sweep_detail {

struct PointLaw {
    std::string derive; // ok, not-finite, not-a-function, undecided
    std::optional<Law> law;
    Json detail; // not-finite: {gamma, word}; not-a-function: the witness; undecided: the limit (a string)
    std::size_t max_word = 0;
    std::optional<DeriveOptions> sequential; // the frictionless sequential process (the order column)
};

PointLaw law_at(const SweepSpec& spec, const std::vector<Rational>& values);
void validate_parameters(const SweepSpec& spec);

// The key under which a point's JSON keeps the detail of a derivation that is not ok.
const char* detail_key(const std::string& derive);

bool is_name(const std::string& s);
Rational number(const std::string& text, const std::string& where);

} // namespace impactcert::sweep_detail
