// SPDX-License-Identifier: GPL-3.0-or-later
// driver_lines.hpp -- the line protocol of the `impactcert fuzz --impl-cmd` drivers here: each stdin
// line holds n numbers (decimals or hex floats, read by strtod); each answer is one line of the
// numbers printed with %.17g, flushed at once.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace driver_lines {

// Calls answer(u) for every line of exactly n finite numbers and prints what it returns (a vector
// of float or double); a malformed line is fail(message), which must not return.
template <class Answer, class Fail>
void serve(std::size_t n, Answer answer, Fail fail) {
    std::string line;
    std::vector<double> u;
    for (unsigned long lineno = 1; std::getline(std::cin, line); ++lineno) {
        u.clear();
        const char* p = line.c_str();
        for (;;) {
            while (*p == ' ' || *p == '\t' || *p == '\r')
                ++p;
            if (*p == '\0')
                break;
            char* end = nullptr;
            const double x = std::strtod(p, &end);
            if (end == p || (*end != '\0' && *end != ' ' && *end != '\t' && *end != '\r') || !std::isfinite(x))
                fail("line " + std::to_string(lineno) + ": not a finite number: '" + std::string(p, std::strcspn(p, " \t\r")) +
                     "'");
            u.push_back(x);
            p = end;
        }
        if (u.size() != n)
            fail("line " + std::to_string(lineno) + ": expected " + std::to_string(n) + " numbers, got " +
                 std::to_string(u.size()));
        const auto v = answer(u);
        for (std::size_t i = 0; i < v.size(); ++i)
            std::printf(i ? " %.17g" : "%.17g", static_cast<double>(v[i]));
        std::printf("\n");
        std::fflush(stdout);
    }
}

} // namespace driver_lines
