// SPDX-License-Identifier: GPL-3.0-or-later
// junit.hpp -- the one JUnit XML writer of verify, fuzz (law mode) and fuzz (consistency mode).
//
// Contract: junit_xml(suite) writes
//   <testsuites name="impactcert" tests= failures= errors="0" skipped= time=>
//     <testsuite name=SUITE (the same counts)>
//       <testcase classname= name= time=/> | with <failure type= message=>TEXT</failure>
//                                          | with <skipped message=/>
//                                          (any of them with <system-out>TEXT</system-out>)
// every attribute and text escaped for XML 1.0 (xml_escape, verdict_output.hpp); the counts are
// those of the cases; time is the sum of the cases' times (seconds, 6 decimals).
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace impactcert {

struct JunitCase {
    enum class Kind { passed, failed, skipped };
    std::string classname, name;
    Kind kind = Kind::passed;
    std::string type;    // failed: the kind of failure ("refuted", "violations", ...)
    std::string message; // failed or skipped: one line
    std::string text;    // failed: the body (a witness, a replay)
    std::string system_out; // any kind: written as <system-out> when not empty (a coverage line)
    std::chrono::nanoseconds time{0};
};

struct JunitSuite {
    std::string name;
    std::vector<JunitCase> cases;
};

std::string junit_xml(const JunitSuite& suite);

} // namespace impactcert
