// SPDX-License-Identifier: GPL-3.0-or-later
// The parts of a sharded certify run (impactcert-certificate-part/1; proofs/README.md, "Shards"):
// assembled into the certificate a single run writes, with every coverage rule checked first
// (parts of one run, every shard once, every obligation from its owner, every pair block of
// nonexpansive from its shard, in order up to the first block that fails), and then checked like
// any certificate. The sharding rule is restated here, not shared with the prover: obligation i
// belongs to shard i mod N + 1, pair block b (of block_pairs pairs, in the single run's order)
// to shard b mod N + 1.
#include "checker.hpp"
#include "sha256.hpp"

#include <algorithm>
#include <new>

namespace impactcert_check {
namespace detail {

namespace {

const char* const kPartFormat = "impactcert-certificate-part/1";

struct Part {
    std::string name; // the file, for messages
    Json doc;
    std::size_t index = 0; // 0-based
};

std::string where(const Part& p, const std::string& path) { return p.name + ": " + path; }

// The nonexpansive entries of slice parts, merged in the single run's order.
Json merge_slices(const std::vector<Part>& parts, const std::vector<const Json*>& entries, std::size_t n,
                  std::vector<ExtraBlock>& extra, std::optional<SliceClaim>& claim) {
    const Json& first = *entries[0];
    const std::string p0 = where(parts[0], "$.obligations[nonexpansive].data");
    const Json& slice0 = field(field(first, p0, "data"), p0, "slice");
    expect_keys(slice0, at(p0, "slice"), {"shard", "of", "block_pairs", "pairs", "method_suffix"});
    const std::size_t block_pairs = natural(field(slice0, p0, "block_pairs"), at(p0, "slice.block_pairs"));
    const std::size_t total = natural(field(slice0, p0, "pairs"), at(p0, "slice.pairs"));
    require(block_pairs > 0, at(p0, "slice.block_pairs"), "must be positive");
    const std::size_t blocks = (total + block_pairs - 1) / block_pairs;
    claim = SliceClaim{total, at(p0, "slice.pairs")};
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const Json& e = *entries[k];
        const std::string p = where(parts[k], "$.obligations[nonexpansive]");
        for (const char* key : {"statement", "claimed"})
            require(field(e, p, key) == field(first, p0, key), at(p, key), "differs between the parts");
        const Json& data = field(e, p, "data");
        expect_keys(data, at(p, "data"), {"slice", "blocks"}, {"first_pieces", "fan_limit"});
        const Json& slice = field(data, at(p, "data"), "slice");
        require(natural(field(slice, at(p, "data.slice"), "shard"), at(p, "data.slice.shard")) == parts[k].index + 1 &&
                    natural(field(slice, at(p, "data.slice"), "of"), at(p, "data.slice.of")) == n,
                at(p, "data.slice"), "is not this part's shard");
        for (const char* key : {"block_pairs", "pairs", "method_suffix"})
            require(field(slice, at(p, "data.slice"), key) == field(slice0, p0, key), at(p, std::string("data.slice.") + key),
                    "differs between the parts");
        require(data.contains("first_pieces") == first.at("data").contains("first_pieces") &&
                    (!data.contains("first_pieces") || data.at("first_pieces") == first.at("data").at("first_pieces")),
                at(p, "data.first_pieces"), "differs between the parts");
        require(data.contains("fan_limit") == first.at("data").contains("fan_limit"), at(p, "data.fan_limit"),
                "differs between the parts");
        // The part's blocks: its own, in order, until one that fails or stops at a limit.
        const Json& list = field(data, at(p, "data"), "blocks");
        if (!list.is_array())
            malformed(at(p, "data.blocks"), "expected an array");
        std::size_t b = parts[k].index;
        for (std::size_t i = 0; i < list.size(); ++i, b += n) {
            const std::string bp = at(at(p, "data.blocks"), i);
            expect_keys(list[i], bp, {"block", "checks", "by_method"}, {"pairs", "counterexample", "limit"});
            require(natural(field(list[i], bp, "block"), at(bp, "block")) == b && b < blocks, at(bp, "block"),
                    "is not the shard's next pair block (blocks b with b mod N = K - 1, in order)");
            const bool event = list[i].contains("counterexample") || list[i].contains("limit");
            require(!(list[i].contains("counterexample") && list[i].contains("limit")), bp,
                    "a block either fails or stops at a limit, not both");
            // Every block's shape, merged or not: its counts, and its pairs exactly when the run
            // records them (the first part's first block says whether it does).
            natural(field(list[i], bp, "checks"), at(bp, "checks"));
            const Json& by = field(list[i], bp, "by_method");
            if (!by.is_array() || by.size() != 4)
                malformed(at(bp, "by_method"), "expected four counts");
            for (std::size_t m = 0; m < 4; ++m)
                natural(by[m], at(at(bp, "by_method"), m));
            const Json& first_blocks = entries[0]->at("data").at("blocks");
            const bool with_pairs = !first_blocks.empty() && first_blocks[0].contains("pairs");
            require(list[i].contains("pairs") == with_pairs, bp,
                    with_pairs ? "has no pairs, where the run records them" : "has pairs, where the run records none");
            require(!event || i + 1 == list.size(), bp, "a block that fails or stops must be the shard's last");
        }
        const bool stopped = !list.empty() && (list.back().contains("counterexample") || list.back().contains("limit"));
        require(stopped || b >= blocks, at(p, "data.blocks"),
                "pair block " + std::to_string(b) + " of this shard is missing");
    }
    // In the single run's order, up to the first block that fails or stops.
    Json pairs = Json::array();
    std::size_t checks = 0, counts[4] = {0, 0, 0, 0};
    Json out;
    out["id"] = "nonexpansive";
    out["statement"] = first.at("statement");
    out["method"] = "";
    out["claimed"] = first.at("claimed");
    out["verdict"] = "proved";
    out["checks"] = std::size_t{0};
    std::optional<Json> counterexample;
    std::optional<std::string> limit;
    for (std::size_t b = 0; b < blocks && !counterexample && !limit; ++b) {
        const std::size_t k = b % n, i = b / n;
        const Json& list = entries[k]->at("data").at("blocks");
        require(i < list.size(), where(parts[k], "$.obligations[nonexpansive].data.blocks"),
                "pair block " + std::to_string(b) + " is missing");
        const Json& block = list[i];
        const std::string bp = where(parts[k], "$.obligations[nonexpansive].data.blocks[" + std::to_string(i) + "]");
        checks += natural(block.at("checks"), at(bp, "checks"));
        const Json& by = block.at("by_method");
        if (!by.is_array() || by.size() != 4)
            malformed(at(bp, "by_method"), "expected four counts");
        for (std::size_t m = 0; m < 4; ++m)
            counts[m] += natural(by[m], at(at(bp, "by_method"), m));
        if (block.contains("pairs")) {
            if (!block.at("pairs").is_array())
                malformed(at(bp, "pairs"), "expected an array");
            for (const auto& e : block.at("pairs"))
                pairs.push_back(e);
        }
        if (block.contains("counterexample"))
            counterexample = block.at("counterexample");
        if (block.contains("limit"))
            limit = str(block.at("limit"), at(bp, "limit"));
    }
    // Every block after the cut, in any part, is checked too (ExtraBlock): a part is a claim
    // about each of its blocks, and none may go unexamined because an earlier block failed.
    if (counterexample || limit) {
        std::size_t cut = 0; // the first block that fails or stops
        for (std::size_t b = 0; b < blocks; ++b) {
            const Json& block = entries[b % n]->at("data").at("blocks")[b / n];
            if (block.contains("counterexample") || block.contains("limit")) {
                cut = b;
                break;
            }
        }
        for (std::size_t k = 0; k < n; ++k) {
            const Json& list = entries[k]->at("data").at("blocks");
            for (std::size_t i = 0; i < list.size(); ++i) {
                const std::size_t b = parts[k].index + i * n;
                if (b <= cut)
                    continue;
                ExtraBlock x;
                x.first = b * block_pairs;
                x.block_pairs = block_pairs;
                x.pairs = list[i].contains("pairs") ? &list[i].at("pairs") : nullptr;
                x.counterexample = list[i].contains("counterexample") ? &list[i].at("counterexample") : nullptr;
                x.limit = list[i].contains("limit") ? &list[i].at("limit") : nullptr;
                x.path = where(parts[k], "$.obligations[nonexpansive].data.blocks[" + std::to_string(i) + "]");
                extra.push_back(std::move(x));
            }
        }
    }
    if (!counterexample && !limit && first.at("data").contains("fan_limit"))
        limit = str(first.at("data").at("fan_limit"), at(p0, "fan_limit"));
    if (limit) {
        out["method"] = "exact decision beyond a limit";
        out["verdict"] = "undecided";
        out["data"] = Json::object();
        out["limit"] = *limit;
        return out;
    }
    out["method"] = "copositive pair forms: " + std::to_string(counts[0]) + " A>=0, " + std::to_string(counts[1]) +
                    " PSD, " + std::to_string(counts[2]) + " PSD+N, " + std::to_string(counts[3]) + " KKT" +
                    str(slice0.at("method_suffix"), at(p0, "slice.method_suffix"));
    out["checks"] = checks;
    Json data = Json::object();
    if (first.at("data").contains("first_pieces"))
        data["first_pieces"] = first.at("data").at("first_pieces");
    if (!pairs.empty() || entries[0]->at("data").at("blocks").empty() ||
        entries[0]->at("data").at("blocks")[0].contains("pairs"))
        data["pairs"] = std::move(pairs);
    out["data"] = std::move(data);
    if (counterexample) {
        out["verdict"] = "refuted";
        out["counterexample"] = *counterexample;
    }
    return out;
}

Json assemble(std::vector<Part>& parts, std::vector<ExtraBlock>& extra, std::optional<SliceClaim>& claim) {
    const std::size_t n = parts.size();
    for (auto& part : parts) {
        const Json& d = part.doc;
        if (!d.is_object() || !d.contains("format") || d.at("format") != kPartFormat)
            malformed(where(part, "$.format"), std::string("not an ") + kPartFormat + " document");
        expect_keys(d, where(part, "$"), {"format", "tool", "law_sha256", "law", "system", "shard", "obligations"});
        const Json& shard = field(d, where(part, "$"), "shard");
        expect_keys(shard, where(part, "$.shard"), {"index", "count"});
        const std::size_t count = natural(field(shard, where(part, "$.shard"), "count"), where(part, "$.shard.count"));
        const std::size_t index = natural(field(shard, where(part, "$.shard"), "index"), where(part, "$.shard.index"));
        require(count == n, where(part, "$.shard.count"),
                "the run has " + std::to_string(count) + " shards, " + std::to_string(n) + " parts given");
        require(index >= 1 && index <= n, where(part, "$.shard.index"), "expected 1.." + std::to_string(n));
        part.index = index - 1;
    }
    std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) { return a.index < b.index; });
    for (std::size_t k = 1; k < n; ++k)
        require(parts[k].index != parts[k - 1].index, where(parts[k], "$.shard.index"),
                "shard " + std::to_string(parts[k].index + 1) + " is given twice (also " + parts[k - 1].name + ")");
    for (std::size_t k = 0; k < n; ++k) {
        require(parts[k].index == k, where(parts[k], "$.shard.index"),
                "shard " + std::to_string(k + 1) + " of " + std::to_string(n) + " is missing");
        for (const char* key : {"tool", "law_sha256", "law", "system"})
            require(parts[k].doc.at(key) == parts[0].doc.at(key), where(parts[k], std::string("$.") + key),
                    "differs from " + parts[0].name + ": a part of another run");
    }
    // Each part's obligations: its own, in order; nonexpansive's slice in every part.
    std::vector<std::vector<const Json*>> by_id(kIds.size(), std::vector<const Json*>(n, nullptr));
    for (std::size_t k = 0; k < n; ++k) {
        const std::string lp = where(parts[k], "$.obligations");
        const Json& list = parts[k].doc.at("obligations");
        if (!list.is_array())
            malformed(lp, "expected an array");
        std::size_t last = 0;
        for (std::size_t e = 0; e < list.size(); ++e) {
            const std::string ep = at(lp, e);
            const std::string id = str(field(list[e], ep, "id"), at(ep, "id"));
            const auto it = std::find(kIds.begin(), kIds.end(), id);
            require(it != kIds.end(), at(ep, "id"), "is not an obligation");
            const std::size_t i = static_cast<std::size_t>(it - kIds.begin());
            require(e == 0 || i > last, at(ep, "id"), "out of order or repeated");
            last = i;
            const bool slice = list[e].contains("data") && list[e].at("data").is_object() &&
                               list[e].at("data").contains("slice");
            require(i % n == k || (id == "nonexpansive" && slice), at(ep, "id"),
                    "belongs to shard " + std::to_string(i % n + 1) + ", not " + std::to_string(k + 1));
            by_id[i][k] = &list[e];
        }
    }
    Json obligations = Json::array();
    bool refuted = false, undecided = false;
    for (std::size_t i = 0; i < kIds.size(); ++i) {
        const std::size_t owner = i % n;
        const Json* own = by_id[i][owner];
        Json entry;
        const bool slices = own && own->contains("data") && own->at("data").is_object() && own->at("data").contains("slice");
        if (kIds[i] == "nonexpansive" && slices) {
            for (std::size_t k = 0; k < n; ++k)
                require(by_id[i][k] != nullptr, where(parts[k], "$.obligations"),
                        "the pair blocks of nonexpansive are missing from this shard");
            entry = merge_slices(parts, by_id[i], n, extra, claim);
        } else {
            require(own != nullptr, where(parts[owner], "$.obligations"), "obligation " + kIds[i] + " is missing from its shard");
            for (std::size_t k = 0; k < n; ++k)
                require(k == owner || by_id[i][k] == nullptr, where(parts[k], "$.obligations"),
                        kIds[i] + " is decided before its pair blocks: only its owner lists it");
            entry = *own;
        }
        if (entry.value("claimed", false)) {
            refuted = refuted || entry.value("verdict", "") == "refuted";
            undecided = undecided || entry.value("verdict", "") != "proved";
        }
        obligations.push_back(std::move(entry));
    }
    Json cert;
    cert["format"] = "impactcert-certificate/1";
    cert["tool"] = parts[0].doc.at("tool");
    cert["law_sha256"] = parts[0].doc.at("law_sha256");
    cert["law"] = parts[0].doc.at("law");
    cert["verdict"] = refuted ? "refuted" : undecided ? "undecided" : "proved";
    cert["system"] = parts[0].doc.at("system");
    cert["obligations"] = std::move(obligations);
    return cert;
}

} // namespace
} // namespace detail

// The string value of the top-level "format" key, found in one pass without parsing the document
// (a certificate may be gigabytes); "" when there is none. Only routes the file: whatever it
// says, the document is then read and checked in full.
std::string top_level_format(const std::string& text) {
    int depth = 0;
    bool in_string = false, escaped = false, key_pending = false, want_format = false;
    std::string token, last;
    for (const char ch : text) {
        if (in_string) {
            if (escaped) {
                escaped = false;
                token += ch;
            } else if (ch == '\\') {
                escaped = true;
                token += ch;
            } else if (ch == '"') {
                in_string = false;
                if (depth == 1) {
                    if (want_format)
                        return token;
                    last = token;
                    key_pending = true;
                }
            } else if (depth == 1) {
                token += ch;
            }
            continue;
        }
        if (ch == '"') {
            in_string = true;
            token.clear();
        } else if (ch == '{' || ch == '[') {
            if (want_format)
                return "";
            ++depth;
        } else if (ch == '}' || ch == ']') {
            --depth;
        } else if (ch == ':' && depth == 1 && key_pending) {
            want_format = last == "format";
            key_pending = false;
        } else if (ch == ',' && depth == 1) {
            if (want_format)
                return "";
            key_pending = false;
        } else if (want_format && ch != ' ' && ch != '\n' && ch != '\t' && ch != '\r') {
            return ""; // a number, true, false or null
        }
    }
    return "";
}

bool is_part_text(const std::string& text) { return top_level_format(text) == detail::kPartFormat; }

Outcome check_parts(const std::vector<std::string>& texts, const std::vector<std::string>& names,
                    const detail::Limits& limits, std::string* merged) {
    using namespace detail;
    try {
        std::vector<Part> parts;
        for (std::size_t k = 0; k < texts.size(); ++k) {
            if (nesting_depth(texts[k]) > 64)
                return {kMalformed, one_line(names[k] + ": malformed: nested more than 64 levels deep")};
            try {
                parts.push_back(Part{names[k], parse_unique_keys(texts[k]), 0});
            } catch (const Json::exception& e) {
                return {kMalformed, one_line(names[k] + ": malformed JSON: " + e.what())};
            } catch (const RefusedText& d) {
                return {kMalformed, one_line(names[k] + ": malformed: " + d.message())};
            }
        }
        return outcome_of([&] {
            std::vector<ExtraBlock> extra;
            std::optional<SliceClaim> claim;
            const Json cert = assemble(parts, extra, claim);
            if (merged)
                *merged = cert.dump(1) + "\n";
            check(cert, limits, extra, claim);
            return cert.at("law").at("name").get<std::string>() + ": " + cert.at("verdict").get<std::string>() + ", " +
                   std::to_string(parts.size()) + (parts.size() == 1 ? " part" : " parts") + " merged";
        });
    } catch (const std::bad_alloc&) {
        return {kMalformed, "error: out of memory while checking (status 2: not checked)"};
    } catch (const std::exception& e) {
        return {kMalformed, one_line(std::string("error: internal: ") + e.what() + " (status 2: not checked)")};
    }
}

} // namespace impactcert_check
