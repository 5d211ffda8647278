// SPDX-License-Identifier: GPL-3.0-or-later
// derive_stream_test.cpp -- the streamed sequential derivation (derive_sequential_streamed)
// writes the in-memory law: the same head, pieces (name, map, rays), identities, single impacts,
// outcomes and claims, the pieces and identities in another order; with any number of buckets;
// holding far less; and nothing at the output path when it stops early.
#include "derive/derive.hpp"
#include "derive/derived_law.hpp"
#include "model/law_json.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace impactcert;
using impactcert::test::q;

namespace {

DeriveOptions chain(std::vector<const char*> masses, const char* e, ImpactRule rule = ImpactRule::most_negative) {
    DeriveOptions o;
    for (auto m : masses)
        o.masses.push_back(q(m));
    o.restitution.assign(o.masses.size() - 1, q(e));
    o.rule = rule;
    return o;
}

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A law's document in canonical order: pieces by name, identities by their left side (every
// other member compared as written).
nlohmann::json canonical(const std::string& text) {
    nlohmann::json law = nlohmann::json::parse(text);
    for (const auto& [array, key] : {std::pair{"pieces", "name"}, std::pair{"identities", "lhs"}})
        if (law.contains(array))
            std::sort(law[array].begin(), law[array].end(),
                      [key = key](const auto& a, const auto& b) { return a[key] < b[key]; });
    return law;
}

// A chain with walls, and a system given by M and W (two bodies on a line and a wall, as a file).
DeriveOptions walled(std::vector<const char*> masses, const char* e, Walls walls) {
    DeriveOptions o = chain(masses, e);
    std::vector<Rational> m;
    for (auto x : masses)
        m.push_back(q(x));
    static_cast<System&>(o) = chain_system(m, walls);
    o.restitution.assign(make_mechanics(o).contacts(), q(e));
    return o;
}

DeriveOptions explicit_system(const char* e) {
    DeriveOptions o;
    static_cast<System&>(o) = parse_system_text(R"({"format": "impactcert-system/1", "name": "three bodies",
        "M": [["2", "0", "0"], ["0", "1", "0"], ["0", "0", "3"]],
        "contacts": {"W": [["-1", "0", "1"], ["1", "-1", "0"], ["0", "1", "0"]]}})", "system");
    o.restitution.assign(3, q(e));
    return o;
}

std::string scratch(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("impactcert-stream-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

// The in-memory law's text, with the claims derive sets.
std::string in_memory(const DeriveOptions& o) {
    DeriveResult r = derive_sequential(o);
    REQUIRE(r.law);
    set_expected_claims(*r.law, o.restitution);
    return law_file_text(*r.law);
}

} // namespace

TEST_CASE("derive --stream: the in-memory law, canonically ordered, on chains of 3 to 6 balls", "[derive][stream]") {
    const std::vector<DeriveOptions> cases = {
        chain({"1", "1", "1"}, "1/2"),
        chain({"1", "1", "1", "1"}, "9/10"),
        chain({"1", "2", "1", "3"}, "1/2", ImpactRule::left_first),
        chain({"3", "1", "2", "1"}, "1/3", ImpactRule::right_first),
        chain({"1", "1", "1", "1", "1"}, "9/10"),
        chain({"2", "1", "1", "1", "2"}, "1"),
        walled({"1", "2", "1"}, "1/2", Walls::left),
        walled({"1", "1", "1"}, "9/10", Walls::right),
        explicit_system("1/2"),
        // Six balls: the elastic chain with the left-first rule (720 regions, 720 pieces, a fraction
        // of a second; the most-negative rule's 16,064 regions took 11 s of the test here).
        chain({"1", "1", "1", "1", "1", "1"}, "1", ImpactRule::left_first),
    };
    for (const auto& o : cases) {
#ifdef IMPACTCERT_SANITIZER_BUILD
        if (o.masses.size() == 5)
            continue; // the sanitizers' time: the same code on the smaller chains and systems
#endif
        const std::string expected = in_memory(o);
        const bool large = o.masses.size() == 5; // one spill-file count for the 5-ball chains (the time)
#ifdef IMPACTCERT_SANITIZER_BUILD
        const std::vector<std::size_t> counts = {7}; // the sanitizers' time: one count, several buckets
#else
        const std::vector<std::size_t> counts = {1, 7, kStreamBuckets};
#endif
        for (const std::size_t buckets : counts) {
            if (large && buckets != kStreamBuckets)
                continue;
            const std::string path = scratch("law.json");
            const DeriveResult r = derive_sequential_streamed(o, path, buckets);
            REQUIRE(!r.not_finite);
            const std::string written = read(path);
            INFO(o.masses.size() << " balls, e = " << to_string(o.restitution[0]) << ", " << buckets << " buckets");
            CHECK(canonical(written) == canonical(expected));
            CHECK(r.pieces == canonical(written)["pieces"].size());
            // The file is a valid law (the first cases: validating a large one costs more than deriving it).
            if (!large && o.masses.size() <= 4)
                CHECK_NOTHROW(parse_law_text(written, "law"));
            // Nothing is left beside the law: the spill directory is gone.
            std::size_t beside = 0;
            for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
                beside += entry.path().filename().string().find("derive-spill") != std::string::npos;
            CHECK(beside == 0);
        }
    }
    // Restitution 0 at one contact, 1/2 and 1 at the others; and outcomes given (--outcomes-from).
    DeriveOptions mixed = chain({"1", "2", "1", "3"}, "1");
    mixed.restitution = {q("0"), q("1/2"), q("1")};
    DeriveOptions given = chain({"1", "1", "1", "1"}, "9/10");
    given.outcomes_override = {OutcomeDecl{"given", {q("-1"), q("0"), q("0"), q("0")}, {q("0"), q("0"), q("0"), q("-1")}}};
    for (const auto& o : {mixed, given}) {
        const std::string path = scratch("law.json");
        derive_sequential_streamed(o, path, 5);
        CHECK(canonical(read(path)) == canonical(in_memory(o)));
    }
    // A negative control for the comparison: one entry of one piece changed is another document.
    const std::string path = scratch("law.json");
    derive_sequential_streamed(chain({"1", "1", "1", "1"}, "9/10"), path);
    std::string changed = read(path);
    changed.replace(changed.find("\"Q\": [") + 30, 1, "7");
    CHECK(canonical(changed) != canonical(in_memory(chain({"1", "1", "1", "1"}, "9/10"))));
    std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}

TEST_CASE("derive --stream: the law file writer gives law_file_text byte for byte", "[derive][stream]") {
    // In the law's own order, the streamed text is the whole law's text: with identities, without
    // (nor single impacts), and with none of the declarations.
    DeriveResult r = derive_sequential(chain({"1", "2", "1", "3"}, "1/2"));
    REQUIRE(r.law);
    set_expected_claims(*r.law, std::vector<Rational>(3, q("1/2")));
    Law bare = *r.law;
    bare.identities.clear();
    bare.single_impacts.clear();
    Law plain = bare;
    plain.outcomes.clear();
    plain.claims.reset();
    plain.description.clear();
    for (const Law* law : {&*r.law, &bare, &plain}) {
        std::ostringstream out;
        LawTextWriter writer(out, *law);
        for (const auto& piece : law->pieces)
            writer.piece(piece);
        for (const auto& id : law->identities)
            writer.identity(id);
        writer.finish(*law);
        CHECK(out.str() == law_file_text(*law));
    }
    // A tail that is not the head is a bug, not a law.
    std::ostringstream out;
    LawTextWriter writer(out, *r.law);
    Law other = *r.law;
    other.name = "another";
    CHECK_THROWS_AS(writer.finish(other), std::logic_error);
}

TEST_CASE("derive --stream: a limit leaves no file, and the memory counted is the frontier and one bucket", "[derive][stream]") {
    const std::string path = scratch("limited.json");
    std::remove(path.c_str());
    DeriveOptions o = chain({"1", "2", "1", "3"}, "1/2");
    o.max_impacts = 5; // this chain needs up to 9 impacts
    const DeriveResult r = derive_sequential_streamed(o, path);
    CHECK(r.not_finite);
    CHECK(!std::filesystem::exists(path));
    // --max-memory bounds what the streamed derivation holds: undecided, no file.
    o.max_impacts = 100;
    o.max_memory_mb = 0;
    CHECK_THROWS_AS(derive_sequential_streamed(o, path), DeriveLimit);
    CHECK(!std::filesystem::exists(path));
    // What it counted is far below the in-memory derivation's count of the same law.
    o.max_memory_mb = 2048;
    const DeriveResult in_memory_run = derive_sequential(o);
    const DeriveResult streamed = derive_sequential_streamed(o, path);
    CHECK(streamed.peak_bytes > 0);
    CHECK(streamed.peak_bytes * 4 < in_memory_run.peak_bytes);
    std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}
