// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/json.hpp"

namespace impactcert {

Json to_json(const Rational& x) { return to_string(x); }

Json to_json(const Vector& v) {
    Json a = Json::array();
    for (const auto& x : v)
        a.push_back(to_string(x));
    return a;
}

Json to_json(const Matrix& m) {
    Json a = Json::array();
    for (std::size_t i = 0; i < m.rows(); ++i)
        a.push_back(to_json(m.row(i)));
    return a;
}

} // namespace impactcert
