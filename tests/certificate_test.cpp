// SPDX-License-Identifier: GPL-3.0-or-later
#include "prover/certificate.hpp"
#include "impactcert_check.hpp"
#include "linalg.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>
#include <cctype>
#include <random>
#include <sstream>

#include <dirent.h>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <map>
#include <set>

using namespace impactcert;
using impactcert::test::read_file;
using impactcert::test::source_path;

namespace {

// Committed law -> committed certificate.
const std::vector<std::pair<std::string, std::string>> kCommitted = {
    {"proofs/newton3/law.json", "proofs/newton3/certificate.json"},
    {"proofs/newton4/law.json", "proofs/newton4/certificate.json"},
    {"proofs/controls/perturbed-entry.json", "proofs/controls/perturbed-entry.certificate.json"},
    {"proofs/controls/swapped-pieces.json", "proofs/controls/swapped-pieces.certificate.json"},
    {"proofs/controls/missing-cone.json", "proofs/controls/missing-cone.certificate.json"},
    {"proofs/controls/newton-simultaneous.json", "proofs/controls/newton-simultaneous.certificate.json"},
    {"proofs/controls/discontinuous-isometric.json", "proofs/controls/discontinuous-isometric.certificate.json"},
    {"proofs/controls/expansive-scaled.json", "proofs/controls/expansive-scaled.certificate.json"},
    {"proofs/cradle4/law.json", "proofs/cradle4/certificate.json"},
    {"proofs/controls/symmetry-wrong-reversal.json", "proofs/controls/symmetry-wrong-reversal.certificate.json"},
    {"proofs/controls/symmetric-expansive.json", "proofs/controls/symmetric-expansive.certificate.json"},
    {"proofs/classical3/newton/law.json", "proofs/classical3/newton/certificate.json"},
    {"proofs/classical3/newton-approaching/law.json", "proofs/classical3/newton-approaching/certificate.json"},
    {"proofs/classical3/poisson/law.json", "proofs/classical3/poisson/certificate.json"},
};

std::string certify_text(const std::string& law_path) {
    const Model m(law_path.empty() ? paper_law() : load_law_file(source_path(law_path)));
    return certificate_text(make_certificate(m, verify(m)));
}

std::vector<std::string> files_in(const std::string& dir) {
    std::vector<std::string> out;
    if (DIR* d = opendir(dir.c_str())) {
        while (dirent* e = readdir(d))
            if (e->d_name[0] != '.')
                out.push_back(e->d_name);
        closedir(d);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// ---- the mutator: single changes to a certificate's content

struct Mutation {
    std::string where; // JSON pointer
    std::string kind;
    Json document;
};

// Keys whose values are informational text or counts, not mathematical content.
bool informational(const std::string& key) {
    return key == "statement" || key == "method" || key == "checks" || key == "tool" || key == "reason";
}

// "/obligations/3/data/pairs" -> "$.obligations[3].data.pairs"
std::string json_path_of(const std::string& pointer) {
    std::string path = "$";
    std::stringstream parts(pointer);
    for (std::string part; std::getline(parts, part, '/');)
        if (!part.empty())
            path += std::isdigit(static_cast<unsigned char>(part[0])) ? "[" + part + "]" : "." + part;
    return path;
}

// Why a verified mutation is an equivalent change, or "" when it is not one of the listed kinds.
std::string equivalent_change(const Json& original, const Mutation& m) {
    const std::string& p = m.where;
    if (p == "/law/name")
        return "the law renamed (the name is not mathematics)";
    const Json& before = original[Json::json_pointer(p)];
    const Json& after = m.document[Json::json_pointer(p)];
    if (m.kind == "swap-first-two" && p.size() > 5 && p.substr(p.size() - 5) == "/rays")
        return "a piece's rays listed in another order (SPEC: their order does not matter)";
    // A ray component changed so that the ray is a positive multiple of itself (e.g. (2, 0) -> (3, 0)).
    const auto rays_at = p.find("/rays/");
    if (rays_at != std::string::npos) {
        const std::string ray_pointer = p.substr(0, p.find('/', rays_at + 6) == std::string::npos ? p.size() : p.find('/', rays_at + 6));
        auto vec = [](const Json& j) {
            Vector v;
            for (const auto& x : j)
                v.push_back(*parse_rational(x.get<std::string>()));
            return v;
        };
        const Json& r0 = original[Json::json_pointer(ray_pointer)];
        const Json& r1 = m.document[Json::json_pointer(ray_pointer)];
        if (r0.is_array() && r1.is_array() && r0.size() == r1.size() && !is_zero(vec(r1)) &&
            primitive_ray(vec(r0)) == primitive_ray(vec(r1)))
            return "a ray rescaled by a positive factor (the same cone)";
    }
    (void)before;
    (void)after;
    // Declarations changed (an identity, single impact, outcome or claim dropped, reordered or
    // altered) with the hash recomputed: the certificate is then one of that other law, whose
    // verdicts the checker re-derived; it certifies nothing about the original.
    for (const char* key : {"/law/identities", "/law/single_impacts", "/law/outcomes", "/law/claims"})
        if (p.rfind(key, 0) == 0)
            return std::string("a declaration of ") + (key + 5) + " changed: a certificate of another law";
    return "";
}

// `wanted` is asked before a mutated copy is made, so that sampling a large certificate is cheap.
void mutations_of(const Json& root, const Json& node, const std::string& pointer, const std::string& key,
                  const std::function<bool()>& wanted, const std::function<void(Mutation)>& emit) {
    if (informational(key))
        return;
    auto with = [&](const char* kind, const Json& replacement) {
        if (!wanted())
            return;
        Json doc = root;
        doc[Json::json_pointer(pointer)] = replacement;
        emit({pointer, kind, std::move(doc)});
    };
    if (node.is_object()) {
        for (auto it = node.begin(); it != node.end(); ++it)
            mutations_of(root, it.value(), pointer + "/" + it.key(), it.key(), wanted, emit);
    } else if (node.is_array()) {
        if (!node.empty()) {
            Json dropped = node;
            dropped.erase(dropped.end() - 1);
            with("drop-last-element", dropped);
        }
        if (node.size() >= 2 && node[0] != node[1]) {
            Json swapped = node;
            std::swap(swapped[0], swapped[1]);
            with("swap-first-two", swapped);
        }
        for (std::size_t i = 0; i < node.size(); ++i)
            mutations_of(root, node[i], pointer + "/" + std::to_string(i), key, wanted, emit);
    } else if (node.is_string()) {
        const std::string s = node.get<std::string>();
        if (auto q = parse_rational(s)) {
            with("rational-plus-one", to_string(*q + 1));
            if (sign_of(*q) != Sign::zero)
                with("rational-negated", to_string(-*q));
        } else if (key == "verdict") {
            with("verdict-changed", s == "proved" ? "refuted" : "proved");
        } else if (key == "law_sha256") {
            with("hash-digit-changed", std::string(1, s[0] == '0' ? '1' : '0') + s.substr(1));
        } else {
            with("text-changed", s + "x");
        }
    } else if (node.is_boolean()) {
        with("boolean-flipped", !node.get<bool>());
    } else if (node.is_number_integer()) {
        with("integer-plus-one", node.get<long long>() + 1);
    }
}

} // namespace

TEST_CASE("certificates: the prover's SHA-256 is the standard one", "[certificate]") {
    CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST_CASE("certificates: the committed certificates are regenerated byte for byte and verified", "[certificate]") {
    for (const auto& [law, cert] : kCommitted) {
        INFO(cert << " (regenerate with scripts/certify-all)");
        const std::string committed = read_file(source_path(cert));
        CHECK(certify_text(law) == committed);
        const auto outcome = impactcert_check::check_text(committed);
        INFO(outcome.message);
        CHECK(outcome.status == impactcert_check::kVerified);
    }
    // The embedded default certifies to the same bytes as its law file.
    CHECK(certify_text("") == read_file(source_path("proofs/newton3/certificate.json")));
}

TEST_CASE("certificates: certify + impactcert-check as processes, exit statuses", "[certificate][cli]") {
    const std::string path = "/tmp/impactcert-cert-test.json";
    auto run = test::run_cli("certify -o " + path);
    CHECK(run.status == 0);
    const std::string checker = std::string(IMPACTCERT_CHECKER);
    CHECK(std::system(("'" + checker + "' " + path + " >/dev/null").c_str()) == 0);
    run = test::run_cli("certify --law '" + source_path("proofs/controls/missing-cone.json") + "' -o " + path);
    CHECK(run.status == 1); // refuted, and the refutation certificate verifies
    CHECK(std::system(("'" + checker + "' " + path + " >/dev/null").c_str()) == 0);
    std::remove(path.c_str());
}

TEST_CASE("certificates: certify streams, one obligation at a time, the very bytes of the in-process certificate",
          "[certificate][cli]") {
    const std::string path = "/tmp/impactcert-cert-stream-test.json";
    for (const auto& [law, cert] : kCommitted) {
        INFO(law);
        const auto run = test::run_cli("certify --jobs 2 --law '" + source_path(law) + "' -o " + path);
        const Model model(load_law_file(source_path(law)));
        CHECK(run.status == verify(model).exit_status()); // 0 for the proved laws, 1 for the controls
        CHECK(read_file(path) == certify_text(law));
    }
    std::remove(path.c_str());
}

TEST_CASE("certificates: every fixture gives its registered exit status and reason", "[certificate]") {
    // valid/: exit 0; fail/: exit 1 (content does not follow); parse/: exit 2 (unreadable);
    // limit/: exit 3 (undecided: checking it would exceed a limit, which the message names).
    const std::map<std::string, std::string> registered = {
        {"valid/two_ball_proved.json", "verified (two-ball-elastic: proved)"},
        {"valid/two_ball_refuted.json", "verified (two-ball-expansive: refuted)"},
        {"valid/tjunction_orthants_proved.json", "verified (tjunction-orthants-zero: proved)"},
        {"valid/overlap_duplicate_proved.json", "verified (overlap-newton3-duplicate: proved)"},
        {"valid/gap_newton4_refuted.json", "verified (gap-newton4-missing-cone: refuted)"},
        // Issue 7 (soundness): each defect the review found, as a fixture named after it.
        {"fail/empty_pieces_hash_recomputed.json", "$.law.pieces: no pieces"},
        {"fail/via_fan_on_p2.json", "$.obligations[2].counterexample.via: a witness of \"fan\" does not refute P2"},
        {"fail/via_p1_on_kinematic.json", "$.obligations[4].counterexample.via: a witness of \"P1\" does not refute kinematic"},
        {"fail/via_cycle_fan_on_fan.json", "$.obligations[0].counterexample.via: a witness of \"fan\" does not refute fan"},
        {"fail/claimed_obligation_skipped.json", "$.obligations[2].verdict: the law declares something to check"},
        {"fail/unknown_claim_id.json", "$.law.claims[1]: unknown obligation"},
        {"fail/duplicate_claim_id.json", "$.law.claims[2]: claimed twice"},
        {"fail/empty_claims.json", "$.law.claims: no obligation claimed"},
        {"fail/law_format_changed.json", "$.law.format: is not \"impactcert-law/1\""},
        {"fail/undecided_with_evidence.json", "$.obligations[6].data: an undecided obligation carries no evidence"},
        {"parse/added_key_in_witness.json", "$.obligations[0].counterexample.extra: unknown key"},
        {"parse/fan_facet_witness.json", "$.obligations[0].counterexample: missing key \"gamma\""},
        {"parse/nested_100000_deep.json", "nested more than 64 levels deep"},
        {"fail/claim_dropped.json", "$.obligations[11].claimed: does not match the law's claims"},
        {"fail/kkt_candidate_missing.json", "certificate.candidates: lists 2 KKT candidates, there are 3"},
        {"fail/law_changed_hash_kept.json", "$.law_sha256: does not match"},
        {"fail/missing_pair.json", "$.obligations[9].data.pairs: is incomplete"},
        {"fail/negative_ldl_pivot.json", "$.obligations[10].data.pieces[1].D: negative entry in D"},
        {"fail/refutation_without_violation.json", "$.obligations[2].counterexample.gamma: is not the canonical witness"},
        {"fail/refuted_claimed_proved.json", "$.obligations[2].verdict: \"proved\" does not follow"},
        {"fail/tampered_denominator.json", "$.system.H: is not G^-1"},
        {"fail/tampered_law_hash.json", "$.law_sha256: does not match"},
        {"fail/top_verdict_flipped.json", "$.verdict: does not follow"},
        {"fail/witness_lhs_equals_rhs.json", "$.obligations[9].counterexample.lhs: is not |S(a) - S(b)|_H^2"},
        {"fail/witness_outside_its_cone.json", "$.obligations[9].counterexample.gamma_b: not in the interior"},
        {"parse/decimal_in_matrix.json", "$.system.G[0][0]: \"2.0\" is not a rational"},
        {"parse/law_outcome_without_u_plus.json", "$.law.outcomes[0]: missing key \"u_plus\""},
        {"parse/law_outcome_wrong_size.json", "$.law.outcomes[0].u_minus: expected one velocity per ball"},
        {"parse/missing_obligation.json", "$.obligations: expected the 13 obligations"},
        {"parse/missing_system.json", "missing key \"system\""},
        {"parse/not_json.json", "malformed JSON"},
        {"parse/wrong_format.json", "$.format: not an impactcert-certificate/1 document"},
        // Checker hardening (review 2): each defect as a fixture named after it.
        {"parse/p1_intersections_key_on_face_to_face.json", "$.obligations[1].data.intersections: unknown key"},
        {"parse/added_key_in_p2_counterexample.json", "$.obligations[2].counterexample.bogus: unknown key"},
        {"parse/added_key_in_evidence_entry.json", "$.obligations[2].data.QtHQ[0].bogus: unknown key"},
        {"parse/added_key_in_copositivity_certificate.json", "$.obligations[6].data.pieces[0].certificate.bogus: unknown key"},
        {"parse/note_in_system.json", "$.system.note: unknown key"},
        {"fail/skipped_with_evidence.json", "$.obligations[7].data: a skipped obligation carries no evidence"},
        {"fail/psd_plus_nonnegative_n_one_column.json", "$.obligations[9].data.pairs[0].certificate.N: expected 2 x 2, got 2 x 1"},
        {"fail/psd_ldlt_l_one_column.json", "$.obligations[9].data.pairs[0].certificate.L: expected 2 x 2, got 2 x 1"},
        {"parse/newline_in_key.json", "malformed: $.obligations[0].bad\\nkey: unknown key"},
        {"parse/contact_as_float.json", "$.obligations[8].data.impacts[0].contact: expected a non-negative integer"},
        {"parse/rational_not_in_lowest_terms.json", "$.system.G[0][0]: \"4/2\" is not in canonical form"},
        {"fail/p2_refutation_hidden_as_undecided.json", "$.obligations[2].limit: the prover decides P2 without a limit"},
        {"fail/energetic_undecided_by_the_wrong_limit.json", "$.obligations[6].limit: names no limit that can stop energetic"},
        {"fail/p1_undecided_on_a_face_to_face_fan.json", "$.obligations[1].limit: the cones meet face to face"},
        {"limit/kkt_faces_beyond_max_faces.json", "undecided: max-faces exceeded: $.obligations[6].data.pieces[0].certificate"},
        {"limit/p1_intersections_beyond_max_subsets.json", "undecided: max-subsets exceeded: $.obligations[1].data.intersections"},
        {"limit/identity_product_beyond_max_product_bits.json", "undecided: max-product-bits exceeded: $.law.identities[0].product"},
    };
    std::set<std::string> on_disk;
    for (const char* dir : {"valid", "fail", "parse", "limit"})
        for (const auto& f : files_in(source_path(std::string("tests/certificates/") + dir)))
            on_disk.insert(std::string(dir) + "/" + f);
    for (const auto& f : on_disk) {
        INFO("fixture on disk but not registered: " << f);
        CHECK(registered.count(f) == 1);
    }
    for (const auto& [name, reason] : registered) {
        INFO(name);
        REQUIRE(on_disk.count(name) == 1);
        const auto outcome = impactcert_check::check_text(read_file(source_path("tests/certificates/" + name)));
        const int expected = name.rfind("valid/", 0) == 0   ? impactcert_check::kVerified
                             : name.rfind("fail/", 0) == 0  ? impactcert_check::kRejected
                             : name.rfind("limit/", 0) == 0 ? impactcert_check::kUndecided
                                                            : impactcert_check::kMalformed;
        INFO(outcome.message);
        CHECK(outcome.status == expected);
        CHECK(outcome.message.find(reason) != std::string::npos);
    }
}

TEST_CASE("certificates: the checker rejects every single-change mutation of content", "[certificate][tamper]") {
    // Every rational (plus one, negated), dropped or swapped array element, verdict, flag, index,
    // name and the law hash of the committed certificates.
    std::size_t tried = 0, rejected = 0, malformed = 0, unnamed = 0;
    std::map<std::string, std::size_t> equivalent;
    std::vector<std::string> certs;
    for (const auto& entry : kCommitted)
        certs.push_back(entry.second);
    certs.push_back("tests/certificates/valid/two_ball_proved.json");
    certs.push_back("tests/certificates/valid/two_ball_refuted.json");
    certs.push_back("tests/certificates/valid/tjunction_orthants_proved.json");
    certs.push_back("tests/certificates/valid/overlap_duplicate_proved.json");
    certs.push_back("tests/certificates/valid/gap_newton4_refuted.json");
    for (const auto& cert : certs) {
        const Json root = Json::parse(read_file(source_path(cert)));
        // Exhaustive on the small certificates; a fixed sample of the large ones (every mutation
        // of every certificate with IMPACTCERT_TAMPER_ALL=1, the 4-ball one 1 in 7).
        const bool all = std::getenv("IMPACTCERT_TAMPER_ALL") != nullptr;
        const std::size_t stride = cert.find("newton4") != std::string::npos ||
                                           cert.find("symmetry-wrong-reversal") != std::string::npos
                                       ? (all ? 7 : 331)
                                   : cert.find("two_ball") != std::string::npos || all ? 1
                                   : cert.find("newton3") != std::string::npos      ? 4
                                                                                     : 8;
        // The sanitizer run takes every (kSanitizerDivisor^2 / 2)-th of these, and every other
        // mutation of the small certificates (the Release run's are exhaustive).
        const std::size_t step = stride == 1 ? (test::kSanitizerDivisor == 1 ? 1 : 2) : stride * test::kSanitizerDivisor * test::kSanitizerDivisor / 2;
        std::size_t index = 0;
        mutations_of(root, root, "", "", [&] { return index++ % step == 0; }, [&](Mutation m) {
            ++tried;
            // A change of the law carries a recomputed hash: the checker must refuse it by its own
            // re-derivation, not by the stale law_sha256.
            const bool in_law = m.where.rfind("/law/", 0) == 0;
            if (in_law)
                m.document["law_sha256"] = sha256_hex(m.document["law"].dump());
            const auto outcome = impactcert_check::check_text(m.document.dump());
            const std::string path = json_path_of(m.where);
            if (outcome.status == impactcert_check::kVerified) {
                // Only changes that leave the certified law the same law, or make the certificate
                // one of another valid law (its hash recomputed), may verify; each is listed.
                const std::string why = equivalent_change(root, m);
                if (why.empty()) {
                    FAIL_CHECK("accepted mutation " << m.kind << " at " << cert << " " << m.where);
                    return;
                }
                // Second route: the prover, on the mutated law, gives every verdict the accepted
                // certificate states (so it certifies that law truthfully).
                const Model changed(parse_law_text(m.document["law"].dump(), "mutated law"));
                const VerifyReport report = verify(changed);
                for (const auto& o : m.document["obligations"]) {
                    INFO(cert << " " << m.kind << " at " << m.where << ": " << o["id"]);
                    CHECK(o["verdict"].get<std::string>() == to_string(report.at(o["id"].get<std::string>()).verdict));
                }
                ++equivalent[why];
                return;
            }
            // Refused for a reason: rejected or malformed (undecided is not a refusal), naming the
            // mutated place (a law change may be caught where its consequence is checked).
            INFO(cert << " " << m.kind << " at " << m.where << ": " << outcome.message);
            CHECK((outcome.status == impactcert_check::kRejected || outcome.status == impactcert_check::kMalformed));
            // The message's path and the mutated one lie on one branch (one is a prefix of the
            // other: the checker names the value or the object it found wrong).
            const auto dollar = outcome.message.find('$');
            const std::string named = dollar == std::string::npos
                                          ? std::string()
                                          : outcome.message.substr(dollar, outcome.message.find(": ", dollar) - dollar);
            // Or the same obligation (a changed witness input is caught at the quantity computed
            // from it, a dropped row at its ragged sibling): $.obligations[9] on both.
            auto head = [](const std::string& x) {
                std::size_t steps = 0, i = 1;
                for (; i < x.size() && steps < 3; ++i)
                    if (x[i] == '.' || x[i] == '[')
                        ++steps;
                return steps == 3 ? x.substr(0, i - 1) : x;
            };
            const bool on_branch = !named.empty() && (path.rfind(named, 0) == 0 || named.rfind(path, 0) == 0 ||
                                                      (head(path) != path && head(named) == head(path)));
            if (!in_law && !on_branch) {
                ++unnamed;
                if (unnamed <= 5)
                    std::cout << "tamper: unnamed " << path << " -> " << outcome.message << "\n";
            }
            ++(outcome.status == impactcert_check::kRejected ? rejected : malformed);
        });
    }
    std::size_t accepted = 0;
    for (const auto& [why, count] : equivalent) {
        std::cout << "tamper: accepted as equivalent: " << count << " x " << why << "\n";
        accepted += count;
    }
    std::cout << "tamper: " << tried << " mutations tried, " << rejected + malformed << " refused (" << rejected
              << " rejected, " << malformed << " malformed), " << accepted << " equivalent, " << unnamed
              << " refused without naming the mutated path\n";
    CHECK(tried > 2000 / test::kSanitizerDivisor);
    CHECK(rejected + malformed + accepted == tried);
    CHECK(unnamed == 0);
}

TEST_CASE("certificates: a gap beside a facet with one cone is held to the prover's facet, cone and point",
          "[certificate][fan]") {
    // The 4-ball sort law without one cone (c = 3): refuted by the point beside the first facet
    // with one cone that has a gap beside it (method unmatched-facet).
    const Model m(load_law_file(source_path("tests/laws/gap-newton4-missing-cone.json")));
    const VerifyReport r = verify(m);
    REQUIRE(r.at("fan").method == "unmatched-facet");
    const Json cert = make_certificate(m, r);
    REQUIRE(impactcert_check::check_text(cert.dump()).status == impactcert_check::kVerified);
    std::size_t fan = 0;
    while (cert["obligations"][fan]["id"] != "fan")
        ++fan;
    const Json data = cert["obligations"][fan]["data"];
    REQUIRE(data.contains("gap_point"));
    auto rejected = [&](const std::function<void(Json&)>& change, const std::string& reason) {
        Json forged = cert;
        change(forged);
        const auto outcome = impactcert_check::check_text(forged.dump());
        INFO(outcome.message);
        CHECK(outcome.status != impactcert_check::kVerified); // rejected, or malformed (a key missing)
        CHECK(outcome.message.find(reason) != std::string::npos);
    };
    auto& at = fan; // the fan's index in every copy
    // Another point: scaled (still in no cone, but not the prover's), or moved into a cone.
    rejected([&](Json& c) {
        for (auto& x : c["obligations"][at]["data"]["gap_point"])
            x = to_string(parse_rational(x.get<std::string>()).value() * Rational(2));
    }, "gap_point");
    rejected([&](Json& c) { c["obligations"][at]["data"]["gap_point"] = Json::array({"1", "1", "1"}); }, "gap_point");
    // Another facet (its rays swapped), another cone, a missing key.
    rejected([&](Json& c) {
        auto& rays = c["obligations"][at]["data"]["facet"]["rays"];
        std::swap(rays[0], rays[1]);
    }, "facet.rays");
    rejected([&](Json& c) { c["obligations"][at]["data"]["facet"]["pieces"] = Json::array({m.pieces()[0].name == c["obligations"][at]["data"]["facet"]["pieces"][0] ? m.pieces()[1].name : m.pieces()[0].name}); },
             "facet.pieces");
    rejected([&](Json& c) { c["obligations"][at]["data"].erase("facet"); }, "facet");
    // The chambers' evidence in its place, or the fan left undecided by --max-chambers.
    rejected([&](Json& c) {
        c["obligations"][at]["data"] = Json{{"hyperplanes", Json::array()}, {"chamber_points", Json::array()}};
    }, "data");
    rejected([&](Json& c) {
        auto& o = c["obligations"][at];
        o["verdict"] = "undecided";
        o.erase("counterexample");
        o["data"] = Json::object();
        o["limit"] = "the facet arrangement needs more than 1 chamber-enumeration steps (raise it with --max-chambers)";
    }, "the fan is decided without enumerating chambers");
}

TEST_CASE("checker: products of integer rows and columns are summed as integers, equal to the rational sums", "[certificate]") {
    // The checker's mul sums integer-valued entries with mpz_addmul; any fraction in a row or a
    // column takes the rational sum. Both must give what the textbook triple loop gives, on
    // matrices that mix integral rows, fractional rows, zeros and large entries.
    using impactcert_check::detail::Mat;
    using impactcert_check::detail::Q;
    using impactcert_check::detail::Vec;
    std::mt19937_64 rng(19);
    auto entry = [&](int kind) -> Q {
        const long v = static_cast<long>(rng() % 19) - 9;
        switch (kind) {
        case 0: return Q(v);                                          // small integer (often 0)
        case 1: return Q(mpz_class(v) * mpz_class("123456789012345678901234567890"));
        default: { // a fraction (canonical, as the checker's reader makes every value)
            Q f(mpz_class(v), mpz_class(static_cast<long>(rng() % 7) + 2));
            f.canonicalize();
            return f;
        }
        }
    };
    for (int trial = 0; trial < 300; ++trial) {
        const std::size_t n = 1 + rng() % 6, m = 1 + rng() % 6, p = 1 + rng() % 6;
        Mat a(n, Vec(m)), b(m, Vec(p));
        Vec x(m);
        const int kind_a = static_cast<int>(rng() % 3), kind_b = static_cast<int>(rng() % 3);
        for (auto& row : a)
            for (auto& e : row)
                e = entry(rng() % 4 == 0 ? kind_a : 0);
        for (auto& row : b)
            for (auto& e : row)
                e = entry(rng() % 4 == 0 ? kind_b : 0);
        for (auto& e : x)
            e = entry(rng() % 4 == 0 ? kind_b : 0);
        const Mat c = impactcert_check::detail::mul(a, b);
        const Vec y = impactcert_check::detail::mul(a, x);
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t j = 0; j < p; ++j) {
                Q want = 0;
                for (std::size_t k = 0; k < m; ++k)
                    want += a[i][k] * b[k][j];
                REQUIRE(c[i][j] == want);
                REQUIRE(gcd(c[i][j].get_num(), c[i][j].get_den()) == 1); // canonical
                REQUIRE(c[i][j].get_den() > 0);
            }
            Q want = 0;
            for (std::size_t k = 0; k < m; ++k)
                want += a[i][k] * x[k];
            REQUIRE(y[i] == want);
        }
    }
}
