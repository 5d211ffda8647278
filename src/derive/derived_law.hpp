// SPDX-License-Identifier: GPL-3.0-or-later
// derived_law.hpp -- a derived law as `impactcert derive` and the library hand it out.
//
// Contract:
//   - set_expected_claims: the claims of a derived law (docs/laws.md, "What a law claims"), from
//     its restitution and whether it has friction.
//   - law_file_text: the law file's text, canonical (law_to_json) with the law's description
//     (a derivation's) after the name when it has one, 2-space JSON ending in a newline.
//   - not_a_function_json: the impactcert-derive/1 object `derive --json` prints when a law with
//     friction is not a function (the sequential law: gamma- and the reason; Newton's: gamma-
//     with no solution, or with two, their modes, impulses and gamma+), and not_a_function_text
//     the line the command and the library's Derivation say it in.
#pragma once

#include "base/json.hpp"
#include "derive/derive.hpp"
#include "model/law.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace impactcert {

void set_expected_claims(Law& law, const std::vector<Rational>& restitution);
std::string law_file_text(const Law& law);
Json not_a_function_json(const Vector& gamma_minus, const std::string& reason);
// The one-line reason both give: "the Newton law with friction is not a function: gamma- = (5822,
// 28989) has two solutions, gamma+ = (...) (mode o) and (...) (mode s)"; "the sequential law with
// friction is not a function: at gamma- = (...) REASON".
std::string not_a_function_text(const Vector& gamma_minus, const std::string& reason);
std::string not_a_function_text(const NotAFunction& w);

// A law file written piece by piece (derive sequential --stream), byte for byte the text
// law_file_text gives for the same law with its pieces and identities in the order they are
// written: the head up to "pieces" at construction, each piece, then each identity, then the rest
// from `tail` (the head with its single impacts, outcomes and claims; its pieces and identities
// are not written again). std::logic_error when the tail's head differs from the head's.
class LawTextWriter {
  public:
    LawTextWriter(std::ostream& out, const Law& head);
    void piece(const PieceDecl& piece);
    void identity(const IdentityDecl& identity);
    void finish(Law tail);
    std::size_t pieces() const { return pieces_; }

  private:
    std::ostream& out_;
    std::string prefix_;
    std::size_t pieces_ = 0, identities_ = 0;
    bool finished_ = false;
    void close_pieces();
};
Json not_a_function_json(const NotAFunction& w);

} // namespace impactcert
