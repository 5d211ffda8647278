// SPDX-License-Identifier: GPL-3.0-or-later
// The whole certificate (proofs/README.md, "What the checker establishes", 0-4): its shape, the
// law's hash, G and H, every obligation's claim and verdict through the Checker, the top
// verdict; and check_text, which turns every outcome, error and exception into one line.
#include "checker.hpp"
#include "sha256.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <unistd.h>
#include <exception>
#include <functional>
#include <new>
#include <set>
#include <string>
#include <vector>

namespace impactcert_check {
namespace detail {

int check(const Json& cert, const Limits& limits, const std::vector<ExtraBlock>& extra, const std::optional<SliceClaim>& slice) {
    if (!cert.is_object() || !cert.contains("format") || cert.at("format") != "impactcert-certificate/1")
        malformed("$.format", "not an impactcert-certificate/1 document");
    expect_keys(cert, "$", {"format", "tool", "law_sha256", "law", "verdict", "system", "obligations"}, {"worst_case"});
    str(field(cert, "$", "tool"), "$.tool");
    const Json& law_json = field(cert, "$", "law");
    const std::string hash = str(field(cert, "$", "law_sha256"), "$.law_sha256");
    require(sha256_hex(law_json.dump()) == hash, "$.law_sha256", "does not match the SHA-256 of the law's canonical text");
    const Law law = read_law(law_json, "$.law", limits.max_pieces, limits.max_memory);

    const Json& system = field(cert, "$", "system");
    expect_keys(system, "$.system", {"G", "H"});
    require(mat(field(system, "$.system", "G"), "$.system.G") == law.G, "$.system.G", "is not W^T M^-1 W");
    require(mat(field(system, "$.system", "H"), "$.system.H") == law.H, "$.system.H", "is not G^-1");

    const Json& obligations = field(cert, "$", "obligations");
    if (!obligations.is_array() || obligations.size() != ids_of(law).size())
        malformed("$.obligations", "expected the " + std::to_string(ids_of(law).size()) + " obligations");
    if (slice) {
        // The pairs of nonexpansive in the single run's order: each first piece (the orbit
        // representatives the obligation lists, or every piece) against every piece.
        std::size_t firsts = law.pieces.size();
        for (const auto& o : obligations)
            if (o.is_object() && o.contains("id") && o.at("id") == "nonexpansive" && o.contains("data") &&
                o.at("data").is_object() && o.at("data").contains("first_pieces") && o.at("data").at("first_pieces").is_array())
                firsts = o.at("data").at("first_pieces").size();
        const std::size_t want = firsts * law.pieces.size();
        require(slice->pairs == want, slice->path,
                "is not the law's number of pairs (" + std::to_string(firsts) + " first pieces x " +
                    std::to_string(law.pieces.size()) + " pieces = " + std::to_string(want) + ")");
    }
    Checker checker(law, obligations, limits, extra);
    bool any_claimed_refuted = false, any_claimed_undecided = false;
    bool fan_holds = false, p1_holds = false; // a continuous tiling: the worst case's Lipschitz bound
    // Progress on a terminal for long checks: the obligation being checked, rewritten in place.
    const bool terminal = limits.progress && isatty(2) != 0;
    const auto start = std::chrono::steady_clock::now();
    struct ClearLine { // on every way out, a rejection included
        bool shown = false;
        ~ClearLine() {
            if (shown)
                std::fprintf(stderr, "\r\033[K");
        }
    } line;
    bool& shown = line.shown;
    for (std::size_t k = 0; k < ids_of(law).size(); ++k) {
        if (terminal && std::chrono::steady_clock::now() - start > std::chrono::seconds(1)) {
            std::fprintf(stderr, "\r\033[Kimpactcert-check: %s (%zu/%zu)", ids_of(law)[k].c_str(), k + 1, ids_of(law).size());
            std::fflush(stderr);
            shown = true;
        }
        const std::string path = at("$.obligations", k);
        const Json& o = obligations[k];
        expect_keys(o, path, {"id", "statement", "method", "claimed", "verdict", "checks", "data"},
                    {"counterexample", "limit"});
        require(str(field(o, path, "id"), at(path, "id")) == ids_of(law)[k], at(path, "id"), "expected \"" + ids_of(law)[k] + "\"");
        str(field(o, path, "statement"), at(path, "statement")); // informational, but text
        str(field(o, path, "method"), at(path, "method"));
        natural(field(o, path, "checks"), at(path, "checks"));
        const bool applies = detail::applies(law_json, ids_of(law)[k], law.redundant);
        const bool claimed = law.claims_given ? law.claimed_ids.count(ids_of(law)[k]) > 0 : applies;
        const Json& claimed_json = field(o, path, "claimed");
        if (!claimed_json.is_boolean())
            malformed(at(path, "claimed"), "expected true or false");
        require(claimed_json.get<bool>() == claimed, at(path, "claimed"), "does not match the law's claims");
        const std::string verdict = str(field(o, path, "verdict"), at(path, "verdict"));
        if (!applies) {
            require(verdict == "skipped", at(path, "verdict"), "nothing is declared: must be \"skipped\"");
            // Nothing was decided, so nothing may ride along.
            const Json& data = field(o, path, "data");
            require(data.is_object() && data.empty(), at(path, "data"), "a skipped obligation carries no evidence");
            require(!o.contains("counterexample"), at(path, "counterexample"), "a skipped obligation has no counterexample");
            require(!o.contains("limit"), at(path, "limit"), "only an undecided obligation names a limit");
            continue;
        }
        require(verdict != "skipped", at(path, "verdict"), "the law declares something to check");
        require((verdict == "refuted") == o.contains("counterexample"), path,
                "a counterexample goes with a refutation, and only with one");
        const auto truth = checker.holds(k);
        if (ids_of(law)[k] == "fan")
            fan_holds = truth == Checker::Truth::proved;
        if (ids_of(law)[k] == "P1")
            p1_holds = truth == Checker::Truth::proved;
        if (claimed && truth == Checker::Truth::refuted)
            any_claimed_refuted = true;
        if (claimed && truth == Checker::Truth::undecided)
            any_claimed_undecided = true;
    }
    checker.check_extra_blocks();
    if (cert.contains("worst_case"))
        check_worst_case(law, cert.at("worst_case"), fan_holds && p1_holds, limits);
    const std::string top = str(field(cert, "$", "verdict"), "$.verdict");
    const char* follows = any_claimed_refuted ? "refuted" : any_claimed_undecided ? "undecided" : "proved";
    require(top == follows, "$.verdict", "does not follow from the claimed obligations");
    return 0;
}

// One line: control characters (C0, DEL, C1 and the Unicode line and paragraph separators)
// and the backslash that introduces an escape are escaped, so that a name or key from the
// input cannot break a message into several lines.
std::string one_line(const std::string& text) {
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
        } else
            out += static_cast<char>(ch);
    }
    return out;
}

} // namespace detail

using detail::Json;
using detail::Limits;
using detail::Malformed;
using detail::Rejected;
using detail::Undecided;
using detail::check;
using detail::one_line;

// The deepest nesting of arrays and objects in a JSON text, counted without recursion (a
// certificate nested 100,000 deep must not overflow the stack of a recursive parser or dump).
std::size_t nesting_depth(const std::string& text) {
    std::size_t depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (char ch : text) {
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (ch == '\\')
                escaped = true;
            else if (ch == '"')
                in_string = false;
        } else if (ch == '"') {
            in_string = true;
        } else if (ch == '[' || ch == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((ch == ']' || ch == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

// Status kUndecided (3, impactcert_check.hpp): a limit (the prover's, or --max-product-bits)
// would be exceeded. The certificate may be right; raising the limit decides it.

// The JSON text parsed with every object's keys checked for repeats: a repeated key would be
// read by nlohmann as the last one and by another reader as the first, so the certified law (its
// hash covers the re-serialised, last-wins object) would not be the one a reader sees.
// The keys are checked in a first pass by a SAX handler that builds nothing, and the document is
// then parsed without a callback: nlohmann's callback parser rescans the enclosing array at the
// end of every object (to drop discarded values), which made the 40,320 pair entries of the 8-ball
// cradle's certificate take 22 % of its check. (The prover's law reader has its own pass,
// SyntaxCheck in src/model/law_json.cpp: the checker shares no code with it.)
namespace {

class KeyCheck {
  public:
    bool null() { return element(); }
    bool boolean(bool) { return element(); }
    bool number_integer(Json::number_integer_t) { return element(); }
    bool number_unsigned(Json::number_unsigned_t) { return element(); }
    bool number_float(Json::number_float_t, const Json::string_t&) { return element(); }
    bool string(Json::string_t&) { return element(); }
    bool binary(Json::binary_t&) { return element(); }
    bool start_object(std::size_t) { return open(true); }
    bool start_array(std::size_t) { return open(false); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }
    bool key(Json::string_t& k) {
        Level& level = levels_.back();
        level.key = k;
        // A certificate's objects have at most a few dozen keys; ordered_json finds keys by a
        // linear search, so an object of a million keys would take half an hour to read.
        if (level.keys.size() >= 4096) {
            levels_.push_back({false, {}, {}, 0});
            throw RefusedText{path(), "", RefusedText::Kind::too_many};
        }
        if (!level.keys.insert(k).second) {
            levels_.push_back({false, {}, {}, 0});
            throw RefusedText{path(), levels_[levels_.size() - 2].key};
        }
        return true;
    }
    // A syntax error: the exception Json::parse would throw (same type, same message).
    template <class Exception> bool parse_error(std::size_t, const std::string&, const Exception& ex) { throw ex; }

  private:
    struct Level {
        bool object;
        std::set<std::string> keys;
        std::string key;  // object: the key being read
        std::size_t next; // array: the index of the next element
    };
    std::vector<Level> levels_;

    bool element() {
        if (!levels_.empty() && !levels_.back().object)
            ++levels_.back().next;
        return true;
    }
    bool open(bool object) {
        element();
        levels_.push_back({object, {}, {}, 0});
        return true;
    }
    bool close() {
        levels_.pop_back();
        return true;
    }
    std::string path() const {
        std::string p = "$";
        for (std::size_t i = 0; i + 1 < levels_.size(); ++i)
            p += levels_[i].object ? "." + levels_[i].key : "[" + std::to_string(levels_[i].next - 1) + "]";
        return p;
    }
};

} // namespace

Json parse_unique_keys(const std::string& text) {
    if (const auto nul = text.find('\0'); nul != std::string::npos)
        throw RefusedText{"byte " + std::to_string(nul), "", RefusedText::Kind::nul_byte};
    KeyCheck keys;
    Json::sax_parse(text, &keys);
    return Json::parse(text);
}

Outcome check_text(const std::string& text, const Limits& limits) {
    constexpr std::size_t kMaxDepth = 64; // a certificate is at most 6 deep
    try {
        if (nesting_depth(text) > kMaxDepth)
            return {kMalformed, "malformed: nested more than " + std::to_string(kMaxDepth) + " levels deep"};
        Json cert;
        try {
            cert = parse_unique_keys(text);
        } catch (const Json::exception& e) {
            return {kMalformed, one_line(std::string("malformed JSON: ") + e.what())};
        } catch (const RefusedText& d) {
            return {kMalformed, one_line("malformed: " + d.message())};
        }
        return outcome_of([&] {
            check(cert, limits);
            return cert.at("law").at("name").get<std::string>() + ": " + cert.at("verdict").get<std::string>();
        });
    } catch (const std::bad_alloc&) {
        return {kMalformed, "error: out of memory while checking (status 2: not checked)"};
    } catch (const std::exception& e) {
        return {kMalformed, one_line(std::string("error: internal: ") + e.what() + " (status 2: not checked)")};
    }
}

Outcome outcome_of(const std::function<std::string()>& checks) {
    try {
        return {kVerified, one_line("verified (" + checks() + ")")};
    } catch (const Rejected& r) {
        return {kRejected, one_line("rejected: " + r.path + ": " + r.why)};
    } catch (const Malformed& m) {
        return {kMalformed, one_line("malformed: " + m.path + ": " + m.why)};
    } catch (const Undecided& u) {
        return {kUndecided, one_line("undecided: " + u.option.substr(2) + " exceeded: " + u.path + ": " + u.why +
                                     " (raise it with " + u.option + ")")};
    } catch (const Json::exception& e) {
        return {kMalformed, one_line(std::string("malformed: ") + e.what())};
    }
}

Outcome check_text(const std::string& text) { return check_text(text, Limits{}); }

} // namespace impactcert_check
