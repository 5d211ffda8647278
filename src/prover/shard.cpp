// SPDX-License-Identifier: GPL-3.0-or-later
#include "prover/shard.hpp"

#include "base/errors.hpp"

#include <algorithm>

namespace impactcert {

Shard parse_shard(const std::string& text) {
    const auto slash = text.find('/');
    auto digits = [](const std::string& s) {
        return !s.empty() && s.size() <= 7 && std::all_of(s.begin(), s.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
    };
    const std::string k = slash == std::string::npos ? "" : text.substr(0, slash);
    const std::string n = slash == std::string::npos ? "" : text.substr(slash + 1);
    if (!digits(k) || !digits(n) || std::stoul(k) < 1 || std::stoul(k) > std::stoul(n) || std::stoul(n) > 1000000)
        throw InputError("--shard: expected K/N with 1 <= K <= N <= 1000000, got \"" + text + "\"");
    return Shard{std::stoul(k) - 1, std::stoul(n)};
}

} // namespace impactcert
