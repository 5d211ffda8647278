// SPDX-License-Identifier: GPL-3.0-or-later
// errors.hpp -- the one exception type for bad input.
//
// Contract: an InputError carries a one-line message that names the place of the defect
// ("$.pieces[2].Q[0][1]: zero denominator"); the CLI prefixes the file and exits with status 2.
// Bugs are std::logic_error and must never be reported as bad input.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace impactcert {

struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

[[noreturn]] inline void input_error(const std::string& path, const std::string& reason) {
    throw InputError(path + ": " + reason);
}

// The parts of such a place: "base[i]", and a key or a text quoted as it appears ("name").
inline std::string idx(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }
inline std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

} // namespace impactcert
