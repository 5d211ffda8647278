// SPDX-License-Identifier: GPL-3.0-or-later
// errors.cpp -- one-line messages (errors.hpp).
#include "base/errors.hpp"

namespace impactcert {

std::string one_line_text(const std::string& text) {
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

} // namespace impactcert
