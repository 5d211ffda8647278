#include "cli/common.hpp"

#include "law_json.hpp"
#include "paper_law.hpp"

#include <gmp.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>

namespace impactcert::cli {

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


Model load_model(const std::string& law_path, std::size_t max_pieces, std::size_t max_memory_mb) {
    return law_path.empty() ? Model(paper_law(), max_pieces, max_memory_mb)
                            : load_model_file(law_path, max_pieces, max_memory_mb);
}

TerminalProgress::TerminalProgress() : enabled_(isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}

TerminalProgress::~TerminalProgress() {
    if (shown_)
        std::fprintf(stderr, "\r\033[K");
}

Progress TerminalProgress::callback() {
    if (!enabled_)
        return {};
    return [this](const std::string& id, const std::string& status) {
        const auto now = std::chrono::steady_clock::now();
        if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(200))
            return;
        last_ = now;
        shown_ = true;
        std::fprintf(stderr, "\r\033[Kimpactcert: %s %s", id.c_str(), status.c_str());
        std::fflush(stderr);
    };
}

void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out)
        throw InputError(path + ": cannot write");
}

void write_stdout(const std::string& text) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::cout.flush(); // synchronised with stdio: its writes went to stdout's buffer
    if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout)
        throw InputError(std::string("standard output: cannot write: ") + std::strerror(errno));
}

// A comma-separated list of command-line numbers ("1,m,1" has no names here: see sweep).
std::vector<Rational> number_list(const std::string& option, const std::string& text) {
    std::vector<Rational> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        std::string why;
        const auto x = parse_cli_number(item, &why);
        if (!x)
            throw InputError(option + ": \"" + item + "\" is not a number" + (why.empty() ? "" : " (" + why + ")"));
        out.push_back(*x);
        if (comma == std::string::npos)
            return out;
        start = comma + 1;
    }
}

// Splits on white space and commas; parentheses and brackets are decoration.
std::vector<std::string> tokens_of(const std::string& text) {
    std::vector<std::string> out;
    std::string cur;
    for (char ch : text) {
        if (ch == ' ' || ch == '\t' || ch == ',' || ch == '(' || ch == ')' || ch == '[' ||
            ch == ']' || ch == '\r' || ch == '\n') {
            if (!cur.empty())
                out.push_back(cur);
            cur.clear();
        } else {
            cur += ch;
        }
    }
    if (!cur.empty())
        out.push_back(cur);
    return out;
}

std::string line_of(const Vector& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i)
        s += (i ? " " : "") + to_string(v[i]);
    return s;
}


// Finite doubles from text: decimals correctly rounded (strtod), hex floats exactly.
double parse_double(const std::string& text, const std::string& where) {
    char* end = nullptr;
    errno = 0;
    const double d = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size())
        throw InputError(where + ": " + text + ": not a number");
    if (!std::isfinite(d))
        throw InputError(where + ": " + text + ": not a finite double (NaN and infinities are outside the domain)");
    return d;
}

std::string short_text(const Rational& x) {
    std::string s = to_string(x);
    if (s.size() <= 40)
        return s;
    // mpf has an exponent range far beyond double's: an approximation of any rational.
    mpf_t f;
    mpf_init2(f, 64);
    mpf_set_q(f, x.mpq());
    char buf[64];
    gmp_snprintf(buf, sizeof buf, "~%.6Fe", f);
    mpf_clear(f);
    return std::string(buf) + " [" + std::to_string(s.size()) + " characters exact]";
}

std::string short_text(const Vector& v) {
    std::string s = "(";
    for (std::size_t i = 0; i < v.size(); ++i)
        s += (i ? ", " : "") + short_text(v[i]);
    return s + ")";
}

System system_from(const SystemArgs& a) {
    if (!a.masses.empty() && !a.system_path.empty())
        throw InputError("--masses and --system: give one system");
    if (!a.system_path.empty()) {
        if (a.walls != "none")
            throw InputError("--walls: only with --masses (a system file states its own contacts)");
        return load_system_file(a.system_path);
    }
    if (a.masses.empty())
        throw InputError("--masses or --system: a system is needed");
    return chain_system(number_list("--masses", a.masses), parse_walls(a.walls));
}

std::string system_flags(const SystemArgs& a) {
    if (!a.system_path.empty())
        return "--system " + fuzz::shell_quote(a.system_path);
    std::string s = "--masses " + fuzz::shell_quote(a.masses);
    if (a.walls != "none")
        s += " --walls " + a.walls;
    return s;
}

std::vector<Rational> restitution_list(const std::string& text, std::size_t contacts) {
    auto e = number_list("--restitution", text);
    if (e.size() == 1 && contacts > 1)
        e.assign(contacts, e[0]);
    return e;
}

} // namespace impactcert::cli
