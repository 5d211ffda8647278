// SPDX-License-Identifier: GPL-3.0-or-later
// cli/arguments.cpp -- the number and system arguments of derive, fuzz and eval (cli/tools.hpp).
#include "cli/tools.hpp"

#include <gmp.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace impactcert::cli {

// A comma-separated list of command-line numbers ("1,m,1" has no names here: see sweep).
std::vector<Rational> number_list(const std::string& option, const std::string& text) {
    return parse_number_list(option, text);
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
