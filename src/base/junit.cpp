// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/junit.hpp"

#include "prover/verdict_output.hpp"

#include <cstdio>

namespace impactcert {

namespace {
std::string seconds(std::chrono::nanoseconds t) {
    const long long us = std::chrono::duration_cast<std::chrono::microseconds>(t).count();
    char buf[32];
    std::snprintf(buf, sizeof buf, "%lld.%06lld", us / 1000000, us % 1000000);
    return buf;
}
} // namespace

std::string junit_xml(const JunitSuite& suite) {
    std::size_t failures = 0, skipped = 0;
    std::chrono::nanoseconds total{0};
    for (const auto& c : suite.cases) {
        total += c.time;
        failures += c.kind == JunitCase::Kind::failed;
        skipped += c.kind == JunitCase::Kind::skipped;
    }
    const std::string counts = " tests=\"" + std::to_string(suite.cases.size()) + "\" failures=\"" +
                               std::to_string(failures) + "\" errors=\"0\" skipped=\"" + std::to_string(skipped) +
                               "\" time=\"" + seconds(total) + "\"";
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += "<testsuites name=\"impactcert\"" + counts + ">\n";
    out += "  <testsuite name=\"" + xml_escape(suite.name) + "\"" + counts + ">\n";
    for (const auto& c : suite.cases) {
        out += "    <testcase classname=\"" + xml_escape(c.classname) + "\" name=\"" + xml_escape(c.name) + "\" time=\"" +
               seconds(c.time) + "\"";
        switch (c.kind) {
        case JunitCase::Kind::passed:
            if (c.system_out.empty()) {
                out += "/>\n";
                continue;
            }
            out += ">\n";
            break;
        case JunitCase::Kind::failed:
            out += ">\n      <failure type=\"" + xml_escape(c.type) + "\" message=\"" + xml_escape(c.message) + "\">" +
                   xml_escape(c.text) + "</failure>\n";
            break;
        case JunitCase::Kind::skipped:
            out += ">\n      <skipped message=\"" + xml_escape(c.message) + "\"/>\n";
            break;
        }
        if (!c.system_out.empty())
            out += "      <system-out>" + xml_escape(c.system_out) + "</system-out>\n";
        out += "    </testcase>\n";
    }
    return out + "  </testsuite>\n</testsuites>\n";
}

} // namespace impactcert
