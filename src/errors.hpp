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
// C1, U+2028 and U+2029) written as \n, \r, \t or \uXXXX, so that a name or key taken from the input
// can neither break the message into lines nor send escape sequences to a terminal.
inline std::string one_line_text(const std::string& text) {
    static const char* hex = "0123456789abcdef";
    auto escape = [&](std::string& out, unsigned code) {
        out += "\\u";
        for (int shift = 12; shift >= 0; shift -= 4)
            out += hex[(code >> shift) & 15];
    };
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const unsigned char ch = static_cast<unsigned char>(text[i]);
        const unsigned char next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
        const unsigned char third = i + 2 < text.size() ? static_cast<unsigned char>(text[i + 2]) : 0;
        if (ch == '\\')
            out += "\\\\";
        else if (ch == '\n')
            out += "\\n";
        else if (ch == '\r')
            out += "\\r";
        else if (ch == '\t')
            out += "\\t";
        else if (ch < 0x20 || ch == 0x7f)
            escape(out, ch);
        else if (ch == 0xc2 && next >= 0x80 && next <= 0x9f) { // U+0080..U+009F
            escape(out, next);
            ++i;
        } else if (ch == 0xe2 && next == 0x80 && (third == 0xa8 || third == 0xa9)) { // U+2028, U+2029
            escape(out, 0x2000u + third - 0x80u);
            i += 2;
        } else {
            out += static_cast<char>(ch);
        }
    }
    return out;
}

// The parts of such a place: "base[i]", and a key or a text quoted as it appears ("name").
inline std::string idx(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }
inline std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

} // namespace impactcert
