// SPDX-License-Identifier: GPL-3.0-or-later
// Reading a certificate's JSON strictly (reading.hpp).
#include "reading.hpp"

#include <algorithm>
#include <cctype>

namespace impactcert_check::detail {

const Json& field(const Json& j, const std::string& path, const std::string& key) {
    if (!j.is_object())
        malformed(path, "expected an object");
    if (!j.contains(key))
        malformed(path, "missing key \"" + key + "\"");
    return j[key];
}

std::string str(const Json& j, const std::string& path) {
    if (!j.is_string())
        malformed(path, "expected a string");
    return j.get<std::string>();
}

// A count or index: the JSON integer type only (1.0 is a number equal to 1, not an integer).
std::size_t natural(const Json& j, const std::string& path) {
    if (!j.is_number_unsigned())
        malformed(path, "expected a non-negative integer");
    return j.get<std::size_t>();
}

// A rational: a string in canonical form (lowest terms, no sign on zero, no leading zeros, no
// "+", no "/1"), as the prover writes it, so that no rational can be re-spelled unnoticed.
Q rat(const Json& j, const std::string& path) {
    if (!j.is_string())
        malformed(path, "expected a rational string");
    const std::string s = j.get<std::string>();
    std::size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
    const std::size_t digits_start = i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])))
        ++i;
    bool ok = i > digits_start;
    if (ok && i < s.size()) {
        ok = s[i] == '/';
        const std::size_t den_start = ++i;
        while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])))
            ++i;
        ok = ok && i > den_start && i == s.size();
    }
    if (!ok)
        malformed(path, "\"" + s + "\" is not a rational p or p/q");
    Q q;
    q.set_str(s[0] == '+' ? s.substr(1) : s, 10);
    if (s.find('/') != std::string::npos && q.get_den() == 0)
        malformed(path, "zero denominator");
    q.canonicalize();
    if (q.get_str() != s)
        malformed(path, "\"" + s + "\" is not in canonical form (\"" + q.get_str() + "\")");
    return q;
}

Vec vec(const Json& j, const std::string& path) {
    if (!j.is_array())
        malformed(path, "expected an array");
    Vec v;
    for (std::size_t i = 0; i < j.size(); ++i)
        v.push_back(rat(j[i], at(path, i)));
    return v;
}

Mat mat(const Json& j, const std::string& path) {
    if (!j.is_array() || j.empty())
        malformed(path, "expected a non-empty array of rows");
    Mat m;
    for (std::size_t i = 0; i < j.size(); ++i) {
        m.push_back(vec(j[i], at(path, i)));
        if (m.back().size() != m.front().size() || m.back().empty())
            malformed(at(path, i), "ragged or empty row");
    }
    return m;
}

// An object with exactly the keys `required` plus some of `optional`. Every object the checker
// reads goes through here first (then `field`), so that no key is read unchecked and nothing
// outside the schema rides along. A certificate is written by the prover and carries no free
// text: its law is in canonical form, which drops `note` and `description`.
void expect_keys(const Json& j, const std::string& path, std::initializer_list<const char*> required,
                 std::initializer_list<const char*> optional) {
    if (!j.is_object())
        malformed(path, "expected an object");
    for (const char* k : required)
        if (!j.contains(k))
            malformed(path, std::string("missing key \"") + k + "\"");
    for (const auto& item : j.items()) {
        const std::string& k = item.key();
        const bool known = std::any_of(required.begin(), required.end(), [&](const char* r) { return k == r; }) ||
                           std::any_of(optional.begin(), optional.end(), [&](const char* o) { return k == o; });
        if (!known)
            malformed(at(path, k), "unknown key");
    }
}

} // namespace impactcert_check::detail
