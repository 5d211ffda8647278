// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>


using namespace impactcert;
using impactcert::test::q;
using impactcert::test::read_file;
using impactcert::test::source_path;

namespace {

const std::string kPaperFile = "proofs/newton3/law.json";

// The paper's law file with one textual replacement applied (the replacement must apply).
std::string mutated(const std::string& from, const std::string& to) {
    std::string text = read_file(source_path(kPaperFile));
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

std::string error_of(const std::string& text) {
    try {
        parse_law_text(text, "law.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("law file: proofs/newton3/law.json states exactly the embedded default law", "[law_json]") {
    const Law from_file = load_law_file(source_path(kPaperFile));
    const Law embedded = paper_law();
    CHECK(law_to_json(from_file).dump() == law_to_json(embedded).dump());
    CHECK(from_file.description == embedded.description);
}

TEST_CASE("law file: the canonical form reads back to itself", "[law_json]") {
    const Law law = load_law_file(source_path(kPaperFile));
    const std::string once = law_to_json(law).dump(2);
    CHECK(law_to_json(parse_law_text(once, "canonical")).dump(2) == once);
}

TEST_CASE("law file: every control law parses and validates", "[law_json]") {
    for (const char* name : {"perturbed-entry", "swapped-pieces", "missing-cone", "newton-simultaneous",
                             "discontinuous-isometric", "expansive-scaled"}) {
        INFO(name);
        const Law law = load_law_file(source_path(std::string("proofs/controls/") + name + ".json"));
        CHECK_FALSE(law.description.empty()); // each control says what is wrong with it
    }
}

TEST_CASE("law file: bad input is rejected with one line naming the JSON path", "[law_json]") {
    struct Case {
        const char* defect;
        std::string text;
        const char* expected; // a substring of the message
    };
    const std::vector<Case> cases = {
        {"malformed JSON", mutated("\"masses\": [", "\"masses\": [,"), "law.json: line 5, column 14: malformed JSON"},
        {"truncated JSON", read_file(source_path(kPaperFile)).substr(0, 200), "malformed JSON"},
        {"non-integer JSON number", mutated("\"masses\": [\"1\"", "\"masses\": [1.0"),
         "law.json: $.masses[0]: JSON number 1.0 is not an integer"},
        {"exponent JSON number", mutated("\"masses\": [\"1\"", "\"masses\": [1e3"), "$.masses[0]: JSON number"},
        {"JSON integers are accepted", mutated("\"masses\": [\"1\", \"1\", \"1\"]", "\"masses\": [1, 1, 1]"), ""},
        {"zero denominator", mutated("\"Q\": [[\"1\", \"0\"]", "\"Q\": [[\"1\", \"0/0\"]"),
         "law.json: $.pieces[0].Q[0][1]: \"0/0\": zero denominator"},
        {"rational with exponent", mutated("\"masses\": [\"1\"", "\"masses\": [\"1e3\""), "$.masses[0]: \"1e3\""},
        {"negative mass", mutated("\"masses\": [\"1\", \"1\", \"1\"]", "\"masses\": [\"1\", \"1\", \"-1/2\"]"),
         "$.masses[2]: mass must be positive, got -1/2"},
        {"zero mass", mutated("\"masses\": [\"1\"", "\"masses\": [\"0\""), "$.masses[0]: mass must be positive"},
        {"ragged Q", mutated("\"Q\": [[\"1\", \"0\"], [\"0\", \"1\"]]", "\"Q\": [[\"1\", \"0\", \"0\"], [\"0\", \"1\"]]"),
         "$.pieces[0].Q[1]: row has 2 entries, row 0 has 3"},
        {"wrong Q dimensions", mutated("\"Q\": [[\"1\", \"0\"], [\"0\", \"1\"]]", "\"Q\": [[\"1\", \"0\", \"0\"], [\"0\", \"1\", \"0\"]]"),
         "$.pieces[0].Q: expected a 2x2 matrix, got 2x3"},
        {"too few balls in an outcome", mutated("\"u_plus\": [\"0\", \"0\", \"1\"]", "\"u_plus\": [\"0\", \"1\"]"),
         "$.outcomes[0].u_plus: expected 3 ball velocities, got 2"},
        {"unknown key", mutated("\"name\": \"IIa\"", "\"name\": \"IIa\", \"Qs\": []"), "$.pieces[1].Qs: unknown key \"Qs\""},
        {"duplicate key", mutated("\"name\": \"IIa\"", "\"name\": \"IIa\", \"name\": \"IIc\""),
         "$.pieces[1].name: duplicate key \"name\""},
        // At the top level the key pass names the key too (the callback reader once read it
        // through a reference its own push_back had invalidated, and printed "").
        {"duplicate top-level key", mutated("\"name\": \"newton3-sequential\"", "\"name\": \"newton3-sequential\", \"name\": \"x\""),
         "law.json: $.name: duplicate key \"name\""},
        {"a number beyond a double", mutated("\"contact\": 2", "\"contact\": 1e400"),
         "law.json: malformed JSON: number overflow parsing '1e400'"},
        {"a NUL byte after the document (the reader would stop there)",
         read_file(source_path(kPaperFile)) + std::string(1, '\0') + "{\"name\": 1, \"name\": 2}",
         "malformed JSON: a NUL character"},
        {"duplicate piece name", mutated("\"name\": \"IIb\"", "\"name\": \"IIa\""), "$.pieces[2].name: duplicate piece name \"IIa\""},
        {"unknown piece in an identity", mutated("\"product\": [\"IVa\", \"IIa\"]", "\"product\": [\"IVa\", \"IIc\"]"),
         "$.identities[0].product[1]: unknown piece \"IIc\""},
        {"zero ray", mutated("\"rays\": [[\"0\", \"1\"], [\"-1\", \"1\"]]", "\"rays\": [[\"0\", \"0\"], [\"-1\", \"1\"]]"),
         "$.pieces[1].rays[0]: zero ray"},
        {"repeated ray", mutated("\"rays\": [[\"0\", \"1\"], [\"-1\", \"1\"]]", "\"rays\": [[\"0\", \"1\"], [\"0\", \"7\"]]"),
         "$.pieces[1].rays[1]: repeats ray 0"},
        {"dependent rays", mutated("\"rays\": [[\"0\", \"1\"], [\"-1\", \"1\"]]", "\"rays\": [[\"0\", \"1\"], [\"0\", \"-1\"]]"),
         "$.pieces[1].rays: linearly dependent rays"},
        {"three rays in the plane", mutated("\"rays\": [[\"0\", \"1\"], [\"-1\", \"1\"]]", "\"rays\": [[\"0\", \"1\"], [\"-1\", \"1\"], [\"-1\", \"0\"]]"),
         "$.pieces[1].rays: expected 2 rays, got 3"},
        {"unknown obligation", mutated("\"outcomes\"]", "\"outcomes\", \"P4\"]"), "$.claims[12]: unknown obligation \"P4\""},
        {"obligation claimed twice", mutated("\"outcomes\"]", "\"outcomes\", \"P1\"]"), "$.claims[12]: obligation \"P1\" claimed twice"},
        {"wrong format", mutated("impactcert-law/1", "impactcert-law/2"), "$.format: expected \"impactcert-law/1\""},
        {"missing pieces", mutated("\"pieces\"", "\"piecez\""), "$.piecez: unknown key"},
        {"wrong contacts", mutated("\"contacts\": \"chain\"", "\"contacts\": \"ring\""), "$.contacts: expected \"chain\""},
        {"restitution out of range", mutated("\"restitution\": \"1\"", "\"restitution\": \"3/2\""),
         "$.single_impacts[0].restitution: restitution must be in [0, 1]"},
        {"contact out of range", mutated("\"contact\": 2", "\"contact\": 3"), "$.single_impacts[1].contact: contact must be in 1..2"},
        {"contact 2^64 - 1 (wraps to -1 when read signed)", mutated("\"contact\": 2", "\"contact\": 18446744073709551615"),
         "$.single_impacts[1].contact: integer out of range: 18446744073709551615"},
        {"contact 2^63", mutated("\"contact\": 2", "\"contact\": 9223372036854775808"),
         "$.single_impacts[1].contact: integer out of range: 9223372036854775808"},
        {"contact -2^63", mutated("\"contact\": 2", "\"contact\": -9223372036854775808"),
         "$.single_impacts[1].contact: integer out of range: -9223372036854775808"},
        {"contact 2^32 + 2 (wraps to 2 as an int)", mutated("\"contact\": 2", "\"contact\": 4294967298"),
         "$.single_impacts[1].contact: integer out of range: 4294967298"},
        {"contact given as a string", mutated("\"contact\": 2", "\"contact\": \"2\""), "$.single_impacts[1].contact: expected an integer"},
        {"duplicate outcome name", mutated("\"name\": \"two balls in, two balls out\"", "\"name\": \"one ball in, one ball out\""),
         "$.outcomes[1].name: duplicate outcome name \"one ball in, one ball out\""},
        {"note that is not text", mutated("\"description\": \"Leine", "\"note\": 3, \"description\": \"Leine"),
         "$.note: free text must be a string"},
    };
    for (const auto& c : cases) {
        INFO("defect: " << c.defect);
        const std::string message = error_of(c.text);
        INFO("message: " << message);
        if (std::string(c.expected).empty())
            CHECK(message.empty());
        else
            CHECK(message.find(c.expected) != std::string::npos);
        CHECK(message.find('\n') == std::string::npos); // one line
    }
}

TEST_CASE("law file: singular Q is an error only when it must define the cone", "[law_json]") {
    const std::string text = R"({"format": "impactcert-law/1", "name": "plastic", "masses": ["1", "1"],
        "pieces": [{"name": "sep", "Q": [["1"]]}, {"name": "hit", "Q": [["0"]]}]})";
    CHECK(error_of(text).find("law.json: $.pieces[1].Q: singular matrix, and no rays given") != std::string::npos);
    // With its ray given, the plastic two-ball impact (e = 0, Q = 0) is a valid law.
    const std::string with_rays = R"({"format": "impactcert-law/1", "name": "plastic", "masses": ["1", "1"],
        "pieces": [{"name": "sep", "Q": [["1"]]}, {"name": "hit", "Q": [["0"]], "rays": [["-1"]]}]})";
    CHECK(error_of(with_rays).empty());
}

TEST_CASE("law file: a claim must have something declared to check", "[law_json]") {
    const std::string text = R"({"format": "impactcert-law/1", "name": "x", "masses": ["1", "1"],
        "pieces": [{"name": "a", "Q": [["1"]]}, {"name": "b", "Q": [["-1"]]}], "claims": ["fan", "outcomes"]})";
    CHECK(error_of(text).find("$.claims[1]: \"outcomes\" is claimed but the law declares nothing for it") !=
          std::string::npos);
}

TEST_CASE("law file: explicit W with dependent columns: a law on the basis, with impulses", "[law_json]") {
    // W's two columns have rank 1: the law is 1 x 1 on the first column's velocity, and each
    // piece declares its impulses (2 x 1); a 2 x 2 law, or one without impulses, is bad input.
    const std::string two = R"({"format": "impactcert-law/1", "name": "x", "masses": ["1", "1"],
        "contacts": {"W": [["-1", "1"], ["1", "-1"]]},
        "pieces": [{"name": "a", "Q": [["1", "0"], ["0", "1"]]}]})";
    CHECK(error_of(two).find("$.pieces[0].Q: expected a 1x1") != std::string::npos);
    const std::string bare = R"({"format": "impactcert-law/1", "name": "x", "masses": ["1", "1"],
        "contacts": {"W": [["-1", "1"], ["1", "-1"]]},
        "pieces": [{"name": "a", "Q": [["1"]]}, {"name": "b", "Q": [["-1"]]}]})";
    CHECK(error_of(bare).find("$.pieces[0]: missing \"impulses\"") != std::string::npos);
    const std::string with = R"({"format": "impactcert-law/1", "name": "x", "masses": ["1", "1"],
        "contacts": {"W": [["-1", "1"], ["1", "-1"]]},
        "pieces": [{"name": "a", "Q": [["1"]], "impulses": [["0"], ["0"]]},
                   {"name": "b", "Q": [["-1"]], "impulses": [["-1"], ["0"]]}]})";
    CHECK(error_of(with).empty());
}

TEST_CASE("law file: rationals with hundreds of digits load and prove", "[law_json]") {
    // Masses scaled by a 300-digit rational and rays stretched by another: the same law.
    const std::string big = std::string(299, '9') + "7";
    const std::string text = mutated("\"masses\": [\"1\", \"1\", \"1\"]",
                                     "\"masses\": [\"" + big + "/3\", \"" + big + "/3\", \"" + big + "/3\"]");
    const std::string stretched = std::string(text).replace(
        text.find("\"rays\": [[\"1\", \"0\"], [\"0\", \"1\"]]"), 32,
        "\"rays\": [[\"" + big + "\", \"0\"], [\"0\", \"1/" + big + "\"]]");
    const Law law = parse_law_text(stretched, "big");
    CHECK(to_string(law.masses[0]) == big + "/3");
    const auto report = verify(Model(law));
    CHECK(report.passed());
}
