// SPDX-License-Identifier: GPL-3.0-or-later
// soundness_test.cpp -- the adversarial suite of issue 7: laws at the edges (tilings that are not
// face to face, overlaps, one cone in R^12), forged and mutated certificates (changed, added,
// deleted keys, nesting, borrowed witnesses, cycles of "via"), each with the verdict it must get.
#include "prover/certificate.hpp"
#include "exact/copositivity.hpp"
#include "impactcert_check.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <cctype>
#include <sstream>

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>

using namespace impactcert;
using impactcert::test::check_certificate;
using impactcert::test::source_path;

namespace {

using test::require_sound;

Model load(const std::string& relative) { return Model(load_law_file(source_path(relative))); }

Json certificate_of(const Model& m, const Limits& limits = {}) {
    return make_certificate(m, verify(m, limits));
}

// A forged certificate whose law hash is recomputed (the checker must not lean on the hash).
Json rehash(Json cert) {
    cert["law_sha256"] = sha256_hex(cert["law"].dump());
    return cert;
}

std::size_t index_of(const Json& cert, const std::string& id) {
    for (std::size_t k = 0; k < cert["obligations"].size(); ++k)
        if (cert["obligations"][k]["id"] == id)
            return k;
    throw std::logic_error("no obligation " + id);
}


Vector random_point(std::mt19937_64& rng, std::size_t c) {
    Vector x(c);
    for (auto& v : x)
        v = Rational(static_cast<int>(rng() % 41) - 20, static_cast<int>(1 + rng() % 6));
    return x;
}

} // namespace

TEST_CASE("soundness 1: a cone split through an edge midpoint is the same law, every claim proved", "[soundness]") {
    const Model split = load("tests/laws/tjunction-newton4-split.json");
    const Model whole = load("proofs/newton4/law.json");
    const VerifyReport r = verify(split);
    CHECK(r.exit_status() == 0);
    CHECK(r.at("fan").method == "walls");
    CHECK(r.at("P1").method == "extreme rays of intersections across walls");
    for (const char* id : {"fan", "P1", "kinematic", "nonexpansive", "nonexpansive-lemma"})
        CHECK(r.at(id).verdict == Verdict::proved);
    CHECK(r.at("P3").verdict == Verdict::refuted); // true: the halves map onto half the orthant
    require_sound(split, r);
    // The same function: S agrees with the unsplit law everywhere we look.
    std::mt19937_64 rng(11);
    for (int k = 0; k < 2000; ++k) {
        const Vector x = random_point(rng, 3);
        REQUIRE(split.values_at(x) == whole.values_at(x));
    }
}

TEST_CASE("soundness 1: eight orthants mapped to 0, one split in two", "[soundness]") {
    const Model m = load("tests/laws/tjunction-orthants-zero.json");
    const VerifyReport r = verify(m);
    CHECK(r.exit_status() == 0);
    CHECK(r.at("fan").verdict == Verdict::proved);
    CHECK(r.at("nonexpansive").verdict == Verdict::proved);
    require_sound(m, r);
}

TEST_CASE("soundness 1: a duplicated cone refutes the fan, yet S is a non-expansive function", "[soundness]") {
    const Model m = load("tests/laws/overlap-newton3-duplicate.json");
    const VerifyReport r = verify(m);
    CHECK(r.exit_status() == 0);
    REQUIRE(r.at("fan").verdict == Verdict::refuted);
    CHECK(r.at("fan").counterexample["interior_of"].size() == 2);
    for (const char* id : {"P1", "kinematic", "nonexpansive", "nonexpansive-lemma"})
        CHECK(r.at(id).verdict == Verdict::proved);
    require_sound(m, r);
}

TEST_CASE("soundness 1: a duplicated cone with another matrix is two-valued: refuted with a point", "[soundness]") {
    Law law = load_law_file(source_path("tests/laws/overlap-newton3-duplicate.json"));
    law.pieces.back().Q = Matrix::from_rows({test::vec({"0", "1"}), test::vec({"1", "0"})});
    const Model m(law);
    const VerifyReport r = verify(m);
    for (const char* id : {"kinematic", "nonexpansive", "nonexpansive-lemma"}) {
        INFO(id);
        REQUIRE(r.at(id).verdict == Verdict::refuted);
        CHECK(r.at(id).counterexample["via"] == "fan");
    }
    CHECK(r.at("P1").verdict == Verdict::refuted);
    require_sound(m, r);
}

TEST_CASE("soundness 1: every refutation of every law we ship and test is a point witness", "[soundness]") {
    for (const char* path : {"proofs/controls/missing-cone.json", "proofs/controls/swapped-pieces.json",
                             "proofs/controls/perturbed-entry.json", "proofs/controls/newton-simultaneous.json",
                             "proofs/controls/discontinuous-isometric.json", "proofs/controls/expansive-scaled.json",
                             "tests/laws/one-piece-c8.json", "tests/laws/gap-newton4-missing-cone.json"}) {
        INFO(path);
        const Model m = load(path);
        require_sound(m, verify(m));
    }
}

TEST_CASE("soundness 5: a one-piece law in R^12 claiming only P2 answers within the limits", "[soundness][limits]") {
    const Model m = load("tests/laws/one-piece-c12.json");
    const auto start = std::chrono::steady_clock::now();
    const VerifyReport r = verify(m);
    const auto seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(r.at("P2").claimed);
    CHECK(r.at("P2").verdict == Verdict::refuted);
    CHECK(r.exit_status() == 1);
    // The gap makes nonexpansive false without its 2^24 KKT faces.
    CHECK(r.at("nonexpansive").verdict == Verdict::refuted);
    CHECK(r.at("nonexpansive").counterexample["via"] == "fan");
    WARN("verify of the c = 12 one-piece law: " << seconds << " s");
}

TEST_CASE("soundness 5: beyond a limit a claim is undecided (exit 3), naming the option", "[soundness][limits]") {
    Law law = load_law_file(source_path("tests/laws/one-piece-c8.json"));
    law.claims = std::vector<std::string>{"energetic"};
    Limits tight;
    tight.max_faces = 100; // energetic needs 2^8 - 1 = 255 faces
    const Model m(law);
    const VerifyReport r = verify(m, tight);
    REQUIRE(r.at("energetic").verdict == Verdict::undecided);
    CHECK(r.at("energetic").limit.find("--max-faces") != std::string::npos);
    CHECK(r.exit_status() == 3);
    CHECK(std::string(r.verdict()) == "undecided");
    // An undecided certificate verifies as undecided; it cannot be turned into "proved".
    Json cert = make_certificate(m, r);
    CHECK(check_certificate(cert).status == impactcert_check::kVerified);
    cert["verdict"] = "proved";
    CHECK(check_certificate(cert).status == impactcert_check::kRejected);
    // With the default limit it is decided.
    CHECK(verify(m).at("energetic").verdict == Verdict::refuted);
    // The KKT enumeration refuses sizes whose 2^N would overflow, instead of shifting by N.
    CHECK_THROWS_AS(decide_copositivity(Matrix::from_rows(std::vector<Vector>(70, Vector(70, Rational(-1)))), 1000),
                    LimitExceeded);
}

TEST_CASE("soundness 6: claims [] is an input error", "[soundness]") {
    Law law = paper_law();
    law.claims = std::vector<std::string>{};
    CHECK_THROWS_WITH(Model(law), Catch::Contains("$.claims") && Catch::Contains("no obligation claimed"));
}

// ---- forged certificates (defects 2 and 3)

TEST_CASE("soundness 2a: a law without pieces is never verified", "[soundness][checker]") {
    Json cert = certificate_of(Model(paper_law()));
    cert["law"]["pieces"] = Json::array();
    for (auto& o : cert["obligations"]) {
        if (o["verdict"] != "skipped")
            o["verdict"] = "proved";
        o["data"] = Json::object();
        o.erase("counterexample");
    }
    cert["verdict"] = "proved";
    const auto out = check_certificate(rehash(cert));
    INFO(out.message);
    CHECK(out.status != impactcert_check::kVerified);
    CHECK(out.message.find("$.law.pieces") != std::string::npos);
}

TEST_CASE("soundness 2b: a borrowed witness is accepted only where the rules allow it", "[soundness][checker]") {
    // A refuted P2 carrying the missing-cone fan's witness, in the paper's certificate.
    const Json gap = certificate_of(load("proofs/controls/missing-cone.json"));
    const Json fan_witness = gap["obligations"][index_of(gap, "fan")]["counterexample"];
    Json cert = certificate_of(load("proofs/controls/expansive-scaled.json"));
    const std::size_t p2 = index_of(cert, "P2");
    REQUIRE(cert["obligations"][p2]["verdict"] == "refuted");
    for (const char* via : {"fan", "P1"}) {
        Json forged = cert;
        Json w = fan_witness;
        w["via"] = via;
        forged["obligations"][p2]["counterexample"] = w;
        const auto out = check_certificate(forged);
        INFO(via << ": " << out.message);
        // Refused for the rule it was written for (not, say, for a missing key).
        CHECK(out.status == impactcert_check::kRejected);
        CHECK(out.message == std::string("rejected: $.obligations[2].counterexample.via: a witness of \"") + via +
                                 "\" does not refute P2");
    }
    // The same for a proved-elsewhere law: nonexpansive refuted "via fan" where S is a function.
    Json paper = certificate_of(Model(paper_law()));
    const std::size_t ne = index_of(paper, "nonexpansive");
    paper["obligations"][ne]["verdict"] = "refuted";
    Json w = fan_witness;
    w["via"] = "fan";
    paper["obligations"][ne]["counterexample"] = w;
    paper["verdict"] = "refuted";
    const auto out = check_certificate(paper);
    CHECK(out.status == impactcert_check::kRejected);
    CHECK(out.message == "rejected: $.obligations[9].counterexample.via: S is a function on R^c: nothing to borrow");
}

TEST_CASE("soundness 2c: skipped claims, unknown or duplicate claim ids and a wrong format are rejected", "[soundness][checker]") {
    const Json cert = certificate_of(Model(paper_law()));
    {
        Json c = cert;
        const std::size_t k = index_of(c, "P2");
        c["obligations"][k]["verdict"] = "skipped";
        c["obligations"][k]["data"] = Json::object();
        CHECK(check_certificate(c).status != impactcert_check::kVerified);
    }
    for (const Json& claims : {Json::array({"fan", "bogus"}), Json::array({"fan", "fan"}), Json::array(),
                               Json::array({"P2", 3})}) {
        Json c = cert;
        c["law"]["claims"] = claims;
        const auto out = check_certificate(rehash(c));
        INFO(claims.dump() << ": " << out.message);
        CHECK(out.status != impactcert_check::kVerified);
    }
    Json c = cert;
    c["law"]["format"] = "impactcert-law/2";
    CHECK(check_certificate(rehash(c)).status != impactcert_check::kVerified);
    c = cert;
    c["law"]["pieces"][0]["colour"] = "red";
    CHECK(check_certificate(rehash(c)).status != impactcert_check::kVerified);
}

TEST_CASE("soundness 3: via cycles, added keys and deep nesting give one line and exit 1 or 2", "[soundness][checker]") {
    const Json cert = certificate_of(load("proofs/controls/missing-cone.json"));
    std::vector<Json> forged;
    std::vector<std::string> expected; // the reason each forgery is refused for, pinned
    for (const char* id : {"fan", "P1", "kinematic", "nonexpansive", "nonexpansive-lemma"})
        for (const char* via : {"fan", "P1", "nonexpansive", "kinematic", "nonexpansive-lemma"}) {
            Json c = cert;
            const std::size_t k = index_of(c, id);
            if (c["obligations"][k]["verdict"] != "refuted")
                continue;
            Json& w = c["obligations"][k]["counterexample"];
            if (w.contains("via") && w["via"] == via)
                continue; // that is the certificate as written
            w["via"] = via;
            forged.push_back(c);
            const std::string at = "$.obligations[" + std::to_string(k) + "].counterexample";
            // The fan's gap point read as a P1 witness lacks P1's keys: refused by its shape.
            expected.push_back(std::string(id) == "nonexpansive-lemma" && std::string(via) == "P1"
                                   ? "malformed: " + at + ": missing key \"piece_a\""
                                   : "rejected: " + at + ".via: a witness of \"" + via + "\" does not refute " + id);
        }
    REQUIRE(forged.size() >= 10);
    // Added keys everywhere a key can go.
    for (const char* pointer : {"", "/system", "/obligations/0", "/obligations/0/counterexample",
                                "/obligations/9/counterexample", "/obligations/0/data"}) {
        Json c = cert;
        c[Json::json_pointer(pointer)]["extra"] = "1";
        forged.push_back(c);
        std::string path = "$"; // "/obligations/0" -> "$.obligations[0]"
        std::stringstream parts(pointer);
        for (std::string part; std::getline(parts, part, '/');)
            if (!part.empty())
                path += std::isdigit(static_cast<unsigned char>(part[0])) ? "[" + part + "]" : "." + part;
        expected.push_back("malformed: " + path + ".extra: unknown key");
    }
    for (std::size_t f = 0; f < forged.size(); ++f) {
        const auto out = check_certificate(forged[f]);
        INFO(out.message);
        CHECK(out.message == expected[f]);
        CHECK(out.status == (expected[f].rfind("rejected", 0) == 0 ? impactcert_check::kRejected : impactcert_check::kMalformed));
    }
    // Nesting 100,000 deep: text that nlohmann would parse, and whose dump() would recurse.
    const auto out = impactcert_check::check_text(std::string(100000, '[') + std::string(100000, ']'));
    CHECK(out.status == impactcert_check::kMalformed);
    Json nested = Json::array();
    Json* inner = &nested;
    for (int k = 0; k < 200; ++k) {
        inner->push_back(Json::array());
        inner = &(*inner)[0];
    }
    Json c = cert;
    c["law"]["pieces"][0]["note"] = nested;
    CHECK(check_certificate(c).status == impactcert_check::kMalformed);
}

TEST_CASE("soundness 2: every certificate of the adversarial laws verifies, and survives its own mutations", "[soundness][checker]") {
    for (const char* path : {"tests/laws/tjunction-newton4-split.json", "tests/laws/tjunction-orthants-zero.json",
                             "tests/laws/overlap-newton3-duplicate.json", "tests/laws/one-piece-c8.json",
                             "tests/laws/gap-newton4-missing-cone.json"}) {
        INFO(path);
        const Json cert = certificate_of(load(path));
        REQUIRE(check_certificate(cert).status == impactcert_check::kVerified);
        // Delete each chamber or intersection entry, or change one coordinate: rejected.
        for (std::size_t k = 0; k < cert["obligations"].size(); ++k) {
            const Json& data = cert["obligations"][k]["data"];
            for (const char* list : {"chamber_points", "intersections", "sector_points", "hyperplanes", "shared"}) {
                if (!data.contains(list) || data[list].empty())
                    continue;
                Json dropped = cert;
                dropped["obligations"][k]["data"][list].erase(0);
                CHECK(check_certificate(dropped).status != impactcert_check::kVerified);
                Json doubled = cert;
                doubled["obligations"][k]["data"][list].push_back(data[list][0]);
                CHECK(check_certificate(doubled).status != impactcert_check::kVerified);
            }
        }
    }
}

TEST_CASE("soundness 5: the CLI exits 3 on an undecided claim, certify too, and the checker agrees", "[soundness][limits][cli]") {
    Json law = Json::parse(test::read_file(source_path("tests/laws/one-piece-c8.json")));
    law["claims"] = Json::array({"energetic"});
    const std::string path = "/tmp/impactcert-soundness-undecided.json";
    const std::string cert = "/tmp/impactcert-soundness-undecided.certificate.json";
    std::ofstream(path) << law.dump();
    const auto run = test::run_cli("verify --law " + path + " --max-faces 100");
    CHECK(run.status == 3);
    CHECK(run.out.find("verdict: undecided") != std::string::npos);
    CHECK(run.out.find("raise it with --max-faces") != std::string::npos);
    CHECK(test::run_cli("verify --law " + path).status == 1);
    CHECK(test::run_cli("certify --law " + path + " --max-faces 100 -o " + cert).status == 3);
    const int checked = std::system((std::string(IMPACTCERT_CHECKER) + " " + cert + " >/dev/null 2>&1").c_str());
    CHECK(WEXITSTATUS(checked) == 0);
    std::remove(path.c_str());
    std::remove(cert.c_str());
}

TEST_CASE("soundness 3: impactcert-check on a file nested 100,000 deep exits 2 with one line", "[soundness][checker][cli]") {
    const std::string path = "/tmp/impactcert-soundness-deep.json";
    std::ofstream(path) << "{\"format\": \"impactcert-certificate/1\", \"law\": " << std::string(100000, '[')
                        << std::string(100000, ']') << "}";
    const std::string out = "/tmp/impactcert-soundness-deep.out";
    const int status = std::system((std::string(IMPACTCERT_CHECKER) + " " + path + " >" + out + " 2>&1").c_str());
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 2);
    const std::string text = test::read_file(out);
    CHECK(std::count(text.begin(), text.end(), '\n') == 1);
    std::remove(path.c_str());
    std::remove(out.c_str());
}

TEST_CASE("soundness 3: a law file nested 100,000 deep is one line of bad input, not a crash", "[soundness][cli]") {
    const std::string path = "/tmp/impactcert-soundness-deep-law.json";
    std::ofstream(path) << R"({"format": "impactcert-law/1", "name": "x", "masses": ["1", "1"], "contacts": )"
                        << std::string(100000, '[') << std::string(100000, ']') << R"(, "pieces": []})";
    const auto run = test::run_cli("verify --law " + path);
    CHECK(run.status == 2);
    CHECK(run.err.find("nested more than 64 levels deep") != std::string::npos);
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    std::remove(path.c_str());
}
