// SPDX-License-Identifier: GPL-3.0-or-later
// impactcert_check.hpp -- the independent checker as a function, for impactcert-check's main
// and for the tamper tests (which run thousands of checks in one process).
//
// Contract: check_text(certificate JSON text) -> status 0 verified, 1 rejected, 2 malformed,
// 3 undecided (checking it would exceed a limit; the message names it and its option), and a
// one-line message ("rejected: $.obligations[9].data.pairs[3].A: is not the pair's
// quadratic form"). Shares no code with the prover; depends on GMP and nlohmann-json only.
#pragma once

#include <string>

namespace impactcert_check {

inline constexpr int kVerified = 0;
inline constexpr int kRejected = 1;
inline constexpr int kMalformed = 2;
inline constexpr int kUndecided = 3;

struct Outcome {
    int status;
    std::string message;
};

Outcome check_text(const std::string& text);

} // namespace impactcert_check
