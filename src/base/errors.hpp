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

// A message as one line of plain text: the backslash doubled, and control characters (C0, DEL,
// C1, U+2028 and U+2029) written as \n, \r, \t or \uXXXX, so that a name or key taken from the
// input can neither break an error line nor send escape sequences to a terminal. The command line
// prints every message through it, and the library's exceptions carry it.
std::string one_line_text(const std::string& text);

// The parts of such a place: "base[i]", and a key or a text quoted as it appears ("name").
inline std::string idx(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }
inline std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

} // namespace impactcert
