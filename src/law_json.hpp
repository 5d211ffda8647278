// law_json.hpp -- the `impactcert-law/1` file format (SPEC section 4).
//
// Contract:
//   - parse_law_text / load_law_file: strict reading. Unknown keys are errors except `note` and
//     `description` on any object; rationals are strings of the SPEC grammar or JSON integers;
//     every error is an InputError whose one-line message names the file (for files), the JSON
//     path and the reason, e.g. "law.json: $.pieces[1].Q[0][1]: zero denominator". Syntax
//     errors name line and column. The result is validated (Model's checks) before it is
//     returned, so a law that loads is a law that can be proved. A path that cannot be read
//     is one line too: "<path>: is a directory", "<path>: cannot read file: <reason>".
//   - law_to_json: the canonical form (fixed key order, rationals in lowest terms, rays written
//     out only where the file gave them), the input of the certificate's hash.
#pragma once

#include "law.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace impactcert {

inline constexpr const char* kLawFormat = "impactcert-law/1";

Law parse_law_text(const std::string& text, const std::string& origin);
Law load_law_file(const std::string& path);
nlohmann::ordered_json law_to_json(const Law& law);

} // namespace impactcert
