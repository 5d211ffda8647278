// SPDX-License-Identifier: GPL-3.0-or-later
// json.hpp -- exact values as JSON: the Json type of verdicts and certificates.
//
// Contract: Json keeps keys in insertion order, so every document impactcert writes is
// deterministic. to_json writes a rational as its canonical string ("p" or "p/q", lowest terms,
// rational.hpp's to_string), a vector as an array of them and a matrix as an array of rows;
// nothing is ever written as a JSON number. The law file format is in law_json.hpp.
#pragma once

#include "exact/matrix.hpp"
#include "exact/rational.hpp"

#include <nlohmann/json.hpp>

namespace impactcert {

using Json = nlohmann::ordered_json;

Json to_json(const Rational& x);
Json to_json(const Vector& v);
Json to_json(const Matrix& m);

} // namespace impactcert
