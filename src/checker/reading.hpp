// SPDX-License-Identifier: GPL-3.0-or-later
// reading.hpp -- strict reading of a certificate's JSON: paths, errors, rationals, schemas.
//
// Contract: every reader takes the JSON path of its value ("$.obligations[9].data") and throws
// Malformed naming it when the value is not what the schema says (wrong type, a missing or
// unknown key, a rational not in canonical form): not a certificate the checker can read.
// Rejected (reject, require) is a readable statement that is wrong; Undecided a decision that
// would exceed a limit. Rationals are strings in canonical form only, as the prover writes them,
// so that none can be re-spelled unnoticed; counts and indices have the JSON integer type.
#pragma once

#include "linalg.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <initializer_list>
#include <string>

namespace impactcert_check::detail {

using Json = nlohmann::ordered_json;

struct Malformed {
    std::string path, why;
};
struct Rejected {
    std::string path, why;
};
// A decision the prover bounds by a limit would exceed the checker's copy of that limit: the
// certificate is neither verified nor rejected (it may be right, made with a raised limit).
struct Undecided {
    std::string option, path, why; // option: "--max-faces", "--max-chambers" or "--max-subsets"
};

[[noreturn]] inline void malformed(const std::string& path, const std::string& why) { throw Malformed{path, why}; }
[[noreturn]] inline void reject(const std::string& path, const std::string& why) { throw Rejected{path, why}; }
[[noreturn]] inline void undecided(const std::string& option, const std::string& path, const std::string& why) {
    throw Undecided{option, path, why};
}
inline void require(bool ok, const std::string& path, const std::string& why) {
    if (!ok)
        reject(path, why);
}

inline std::string at(const std::string& path, const std::string& key) { return path + "." + key; }
inline std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

const Json& field(const Json& j, const std::string& path, const std::string& key);
std::string str(const Json& j, const std::string& path);
std::size_t natural(const Json& j, const std::string& path);
Q rat(const Json& j, const std::string& path);
Vec vec(const Json& j, const std::string& path);
Mat mat(const Json& j, const std::string& path);

void expect_keys(const Json& j, const std::string& path, std::initializer_list<const char*> required,
                 std::initializer_list<const char*> optional = {});

} // namespace impactcert_check::detail
