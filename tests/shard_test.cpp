// SPDX-License-Identifier: GPL-3.0-or-later
// shard_test.cpp -- issue 19: `--shard K/N` as separate processes, merged and checked: certify's
// parts by impactcert-check PART..., the sweep's by `sweep --merge`. The merged result must be
// the single run's (same verdicts, same certificate content), and a missing, duplicated, foreign
// or forged part must be rejected.
#include "checker.hpp"
#include "sha256.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <string>

using impactcert::test::read_file;
using impactcert::test::run_cli;
using impactcert::test::source_path;
namespace fs = std::filesystem;
using CJson = impactcert_check::detail::Json;

namespace {


void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE(out.good());
}

// impactcert-check on the given files: exit status and its line.
std::pair<int, std::string> check_files(const std::vector<std::string>& files) {
    std::string cmd = std::string("'") + IMPACTCERT_CHECKER + "'";
    for (const auto& f : files)
        cmd += " '" + f + "'";
    cmd += " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string out;
    char buf[4096];
    for (std::size_t got; (got = fread(buf, 1, sizeof buf, pipe)) > 0;)
        out.append(buf, got);
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

impactcert_check::Outcome check_parts(const std::vector<std::string>& texts, std::string* merged = nullptr) {
    std::vector<std::string> names;
    for (std::size_t k = 0; k < texts.size(); ++k)
        names.push_back("part" + std::to_string(k + 1));
    return impactcert_check::check_parts(texts, names, impactcert_check::detail::Limits{}, merged);
}

// certify --shard k/n for k = 1..n, each a separate process; returns the part texts.
std::vector<std::string> certify_shards(const std::string& law, std::size_t n, const std::string& dir,
                                        const std::string& extra = "") {
    std::vector<std::string> texts;
    for (std::size_t k = 1; k <= n; ++k) {
        const std::string part = dir + "/part" + std::to_string(k) + ".json";
        const auto run = run_cli("certify --law '" + law + "' --shard " + std::to_string(k) + "/" + std::to_string(n) +
                                 " -o '" + part + "' " + extra);
        INFO(run.err);
        REQUIRE(run.status == 0);
        texts.push_back(read_file(part));
    }
    return texts;
}

CJson& nonexpansive_of(CJson& part) {
    for (auto& o : part["obligations"])
        if (o["id"] == "nonexpansive")
            return o;
    throw std::logic_error("no nonexpansive in the part");
}

} // namespace

TEST_CASE("shards: certify in three processes, merged by impactcert-check, is the single run's certificate",
          "[shard][issue19]") {
    const impactcert::test::ScratchDir scratch("shard-certify");
    const std::string& dir = scratch.path;
    // A continuous inelastic law whose pair forms take every route (A >= 0, PSD, PSD + N, KKT),
    // cut into blocks of 7 pairs; a law refuted by a pair form; a law with symmetries; a law
    // stopped by --max-faces in a block.
    REQUIRE(run_cli("derive sequential --masses 1,1/3,1 --restitution 1/3 -o '" + dir + "/m13.json'").status == 0);
    REQUIRE(run_cli("derive cradle --balls 5 -o '" + dir + "/c5.json'").status == 0);
    const std::vector<std::pair<std::string, std::string>> runs = {
        {dir + "/m13.json", "--shard-block 7"},
        {source_path("proofs/controls/expansive-scaled.json"), "--shard-block 1"},
        {dir + "/c5.json", "--shard-block 3"},
        {dir + "/m13.json", "--shard-block 5 --max-faces 3"},
    };
    for (const auto& [law, extra] : runs) {
        INFO(law << " " << extra);
        const std::string limits = extra.find("--max-faces") != std::string::npos ? "--max-faces 3" : "";
        const auto single = run_cli("certify --law '" + law + "' -o '" + dir + "/single.json' " + limits);
        REQUIRE((single.status == 0 || single.status == 1 || single.status == 3));
        const std::vector<std::string> texts = certify_shards(law, 3, dir, extra);
        std::string merged;
        impactcert_check::detail::Limits check_limits;
        if (!limits.empty())
            check_limits.max_faces = 3;
        const auto outcome = impactcert_check::check_parts(texts, {"p1", "p2", "p3"}, check_limits, &merged);
        INFO(outcome.message);
        REQUIRE(outcome.status == impactcert_check::kVerified);
        // Same content as one run (the parsed documents are equal, key for key).
        CHECK(CJson::parse(merged) == CJson::parse(read_file(dir + "/single.json")));
        // And the same verdict from the command line, given the parts in any order.
        if (limits.empty()) {
            const auto [status, line] = check_files({dir + "/part3.json", dir + "/part1.json", dir + "/part2.json"});
            INFO(line);
            CHECK(status == 0);
            CHECK(line.find("3 parts merged") != std::string::npos);
        }
    }
}

TEST_CASE("shards: a missing, duplicated, foreign or forged part is rejected", "[shard][issue19]") {
    const impactcert::test::ScratchDir scratch("shard-forged");
    const std::string& dir = scratch.path;
    REQUIRE(run_cli("derive sequential --masses 1,1/3,1 --restitution 1/3 -o '" + dir + "/m13.json'").status == 0);
    REQUIRE(run_cli("derive sequential --masses 1,1/2,1 --restitution 1/2 -o '" + dir + "/m12.json'").status == 0);
    const auto parts = certify_shards(dir + "/m13.json", 3, dir, "--shard-block 7");
    const auto other = certify_shards(dir + "/m12.json", 3, dir + "/..", "--shard-block 7");
    REQUIRE(check_parts(parts).status == impactcert_check::kVerified);
    auto rejected = [](const impactcert_check::Outcome& o, const std::string& words) {
        INFO(o.message);
        CHECK(o.status != impactcert_check::kVerified);
        CHECK(o.message.find(words) != std::string::npos);
    };
    rejected(check_parts({parts[0], parts[1]}), "3 shards, 2 parts given");          // missing
    rejected(check_parts({parts[0], parts[1], parts[1]}), "given twice");            // duplicated
    rejected(check_parts({parts[0], other[1], parts[2]}), "a part of another run");  // foreign
    {
        // Forged: a pair's certificate changed in a block.
        CJson p = CJson::parse(parts[1]);
        auto& blocks = nonexpansive_of(p)["data"]["blocks"];
        REQUIRE(!blocks.empty());
        // (Issue 33, 10a: the method is written "nonnegative-entries"; the test looked for
        // "nonnegative entries", never forged anything, and passed on a missing pair.) A number
        // inside an LDL^T certificate is changed, and the rejection must name that entry: pair i
        // of shard 2's block list entry b is block 1 + 3b of 7 pairs, the merged list's pair
        // 7 (1 + 3b) + i.
        std::string forged_path;
        for (std::size_t b = 0; b < blocks.size() && forged_path.empty(); ++b)
            for (std::size_t i = 0; i < blocks[b]["pairs"].size() && forged_path.empty(); ++i) {
                auto& cert = blocks[b]["pairs"][i]["certificate"];
                if (cert["method"] == "psd-ldlt") {
                    REQUIRE(cert["D"][0] != "3/7");
                    cert["D"][0] = "3/7";
                    forged_path = "data.pairs[" + std::to_string(7 * (1 + 3 * b) + i) + "].certificate";
                }
            }
        REQUIRE(!forged_path.empty());
        rejected(check_parts({parts[0], p.dump(), parts[2]}), forged_path);
    }
    {
        // Forged: a block dropped, or taken from another shard.
        CJson p = CJson::parse(parts[2]);
        auto& blocks = nonexpansive_of(p)["data"]["blocks"];
        REQUIRE(blocks.size() >= 2);
        blocks.erase(0);
        rejected(check_parts({parts[0], parts[1], p.dump()}), "is not the shard's next pair block");
        CJson q = CJson::parse(parts[2]);
        nonexpansive_of(q)["data"]["blocks"].erase(nonexpansive_of(q)["data"]["blocks"].size() - 1);
        rejected(check_parts({parts[0], parts[1], q.dump()}), "is missing");
    }
    {
        // Forged: an obligation moved to a shard that does not own it, or dropped.
        CJson a = CJson::parse(parts[0]), b = CJson::parse(parts[1]);
        b["obligations"].erase(0); // P1 (index 1) is shard 2's
        rejected(check_parts({parts[0], b.dump(), parts[2]}), "missing from its shard");
        CJson c = CJson::parse(parts[0]);
        c["shard"]["index"] = 2;
        rejected(check_parts({c.dump(), parts[1], parts[2]}), "given twice");
        (void)a;
    }
    {
        // Forged: a part of a run with another block size, or a pair count that does not fit.
        CJson p = CJson::parse(parts[1]);
        nonexpansive_of(p)["data"]["slice"]["block_pairs"] = 8;
        rejected(check_parts({parts[0], p.dump(), parts[2]}), "differs between the parts");
    }
    // A certificate is not a part, and a part alone is not a certificate.
    const auto single = run_cli("certify --law '" + dir + "/m13.json' -o '" + dir + "/single.json'");
    REQUIRE(single.status <= 1);
    rejected(check_parts({read_file(dir + "/single.json"), parts[1], parts[2]}), "not an impactcert-certificate-part/1");
    CHECK(impactcert_check::check_text(parts[0]).status != impactcert_check::kVerified);
    const auto [status, line] = check_files({dir + "/part1.json"});
    INFO(line);
    CHECK(status != 0); // one part of three
}

TEST_CASE("defect 33.7 fail: every block of every part is examined, also after the first refuting block",
          "[shard][reliability]") {
    // The approaching-only Newton law of three equal balls: with one pair per block and three
    // shards, pair 4 (shard 2's second block) is the first that fails, so the merged certificate
    // ends at block 4. The blocks after it -- 5 in shard 3's part (it fails too), 6, 9, ..., 24 in
    // shard 1's (24 fails) -- were never read: any forgery there was "verified".
    const impactcert::test::ScratchDir scratch("shard-after-cut");
    const std::string law = impactcert::test::source_path("proofs/classical3/newton-approaching/law.json");
    const auto parts = certify_shards(law, 3, scratch.path, "--shard-block 1");
    const auto good = check_parts(parts);
    INFO(good.message);
    REQUIRE(good.status == impactcert_check::kVerified);
    REQUIRE(good.message.find("refuted") != std::string::npos);
    auto blocks_of = [](CJson& p) -> CJson& { return nonexpansive_of(p)["data"]["blocks"]; };
    auto rejected = [&](std::size_t part, const CJson& forged, const std::string& words) {
        std::vector<std::string> texts = parts;
        texts[part] = forged.dump();
        const auto o = check_parts(texts);
        INFO(o.message);
        CHECK(o.status != impactcert_check::kVerified);
        CHECK(o.message.find(words) != std::string::npos);
    };
    {
        // Shard 1's blocks are 0, 3, ..., 24; the last (list index 8) fails, after the cut: its
        // counterexample's number is forged.
        CJson p = CJson::parse(parts[0]);
        auto& blocks = blocks_of(p);
        REQUIRE(blocks.back()["block"] == 24);
        REQUIRE(blocks.back().contains("counterexample"));
        CJson q = p;
        blocks_of(q).back()["counterexample"]["lhs"] = "12345";
        rejected(0, q, "$.obligations[nonexpansive].data.blocks[8]");
    }
    {
        // Shard 3's part: block 5 lies after the cut (block 4 fails first); its counterexample,
        // its KKT certificate and its pair names are forged in turn.
        CJson p = CJson::parse(parts[2]);
        REQUIRE(blocks_of(p).size() == 2);
        REQUIRE(blocks_of(p)[1]["block"] == 5);
        CJson a = p;
        blocks_of(a)[1]["counterexample"]["rhs"] = "1";
        rejected(2, a, "blocks[1].counterexample.rhs");
        CJson b = p;
        auto& cert = blocks_of(b)[1]["pairs"][0]["certificate"];
        REQUIRE(cert["method"] == "kkt-enumeration");
        cert["minimum"] = "1";
        rejected(2, b, "blocks[1].pairs[0].certificate");
        CJson c = p;
        blocks_of(c)[1]["pairs"][0]["piece_b"] = blocks_of(c)[1]["pairs"][0]["piece_a"];
        rejected(2, c, "blocks[1].pairs[0]");
        CJson d = p; // the failing pair's counterexample removed: the block ends at a failure unshown
        blocks_of(d)[1].erase("counterexample");
        rejected(2, d, "data.blocks");
    }
    {
        // Shard 1's part: a whole block after the cut (block 6) with its pair's certificate forged
        // to a failing one, and one with its pair dropped.
        CJson p = CJson::parse(parts[0]);
        REQUIRE(blocks_of(p)[2]["block"] == 6);
        CJson a = p;
        blocks_of(a)[2]["pairs"].erase(0);
        rejected(0, a, "blocks[2].pairs");
        CJson b = p;
        blocks_of(b)[2]["limit"] = "forged limit";
        rejected(0, b, "blocks[2]");
        // The shape of a block after the cut, as of one before it (the adversarial review): its
        // counts, and its pairs where the run records them.
        CJson c = p;
        blocks_of(c)[2]["checks"] = -1;
        rejected(0, c, "blocks[2].checks");
        CJson d = p;
        blocks_of(d)[2]["by_method"] = nullptr;
        rejected(0, d, "blocks[2].by_method");
        CJson e = p;
        blocks_of(e)[2].erase("pairs");
        rejected(0, e, "has no pairs");
    }
}

TEST_CASE("shards: sweep --shard in three processes, sweep --merge equals the single sweep", "[shard][sweep][issue19]") {
    const impactcert::test::ScratchDir scratch("shard-sweep");
    const std::string& dir = scratch.path;
    const std::string spec = "--masses 1,m,1 --restitution e --vary m=1/2..2:3 --vary e=1/4..1:3 --jobs 1";
    REQUIRE(run_cli("sweep " + spec + " -o '" + dir + "/single'").status == 0);
    std::string merge;
    for (int k = 1; k <= 3; ++k) {
        const auto run = run_cli("sweep " + spec + " --shard " + std::to_string(k) + "/3 -o '" + dir + "/s" + std::to_string(k) + "'");
        INFO(run.err);
        REQUIRE(run.status == 0);
        const std::string part = dir + "/s" + std::to_string(k) + "/sweep.part-" + std::to_string(k) + "-of-3.json";
        REQUIRE(fs::exists(part));
        CHECK(run.out == part + "\n");
        merge += " '" + part + "'";
    }
    const auto merged = run_cli("sweep --merge" + merge + " -o '" + dir + "/merged'");
    INFO(merged.err);
    REQUIRE(merged.status == 0);
    for (const char* file : {"sweep.csv", "sweep.json", "sweep.html"})
        CHECK(read_file(dir + "/merged/" + file) == read_file(dir + "/single/" + file));

    // Missing, duplicated, foreign (another grid) and forged (a verdict changed) parts.
    const std::string p1 = dir + "/s1/sweep.part-1-of-3.json", p2 = dir + "/s2/sweep.part-2-of-3.json",
                      p3 = dir + "/s3/sweep.part-3-of-3.json";
    auto merge_fails = [&](const std::string& parts, const std::string& words) {
        const auto run = run_cli("sweep --merge " + parts + " -o '" + dir + "/bad'");
        INFO(run.err);
        CHECK(run.status == 2);
        CHECK(run.err.find(words) != std::string::npos);
        CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    };
    merge_fails("'" + p1 + "' '" + p2 + "'", "3 shards, 2 parts given");
    merge_fails("'" + p1 + "' '" + p2 + "' '" + p2 + "'", "also given by");
    REQUIRE(run_cli("sweep --masses 1,m,1 --restitution e --vary m=1/2..2:3 --vary e=0..1:3 --jobs 1 --shard 2/3 -o '" + dir +
                    "/other'").status == 0);
    merge_fails("'" + p1 + "' '" + dir + "/other/sweep.part-2-of-3.json' '" + p3 + "'", "a part of another run");
    {
        CJson p = CJson::parse(read_file(p2));
        p["points"][0]["obligations"]["P1"]["verdict"] = "proved";
        p["points"][0]["derive"] = "ok";
        p["points"][0]["max_word"] = 99;
        write_text(dir + "/forged.json", p.dump());
        merge_fails("'" + p1 + "' '" + dir + "/forged.json' '" + p3 + "'", "does not match the part's content");
    }
    merge_fails("'" + p1 + "' '" + p2 + "' '" + p3 + "' --masses 1,2,1", "give no --masses");
    const auto bad_shard = run_cli("sweep " + spec + " --shard 4/3 -o '" + dir + "/x'");
    CHECK(bad_shard.status == 2);
    CHECK(bad_shard.err.find("--shard") != std::string::npos);
}

TEST_CASE("shards: a certificate is routed by its top-level format, whatever its names say", "[shard][issue19]") {
    // A law named like the part format, with a piece named "shard": still a certificate.
    const impactcert::test::ScratchDir scratch("shard-route");
    const std::string& dir = scratch.path;
    CJson law = CJson::parse(read_file(source_path("proofs/newton3/law.json")));
    law["name"] = "impactcert-certificate-part/1";
    write_text(dir + "/law.json", law.dump());
    REQUIRE(run_cli("certify --law '" + dir + "/law.json' -o '" + dir + "/c.json'").status == 0);
    const auto [status, line] = check_files({dir + "/c.json"});
    INFO(line);
    CHECK(status == 0);
    CHECK_FALSE(impactcert_check::is_part_text(read_file(dir + "/c.json")));
    const auto parts = certify_shards(source_path("proofs/newton3/law.json"), 2, dir);
    CHECK(impactcert_check::is_part_text(parts[0]));
}

TEST_CASE("shards: sweep --merge refuses malformed parts with one line, and oversized grids before allocating",
          "[shard][sweep][issue19]") {
    const impactcert::test::ScratchDir scratch("shard-malformed");
    const std::string& dir = scratch.path;
    REQUIRE(run_cli("sweep --masses 1,1,1 --restitution e,f --vary e=0..1:2 --vary f=0..1:2 --jobs 1 --shard 1/1 -o '" + dir +
                    "/R'").status == 0);
    const CJson source = CJson::parse(read_file(dir + "/R/sweep.part-1-of-1.json"));
    // The digest a forger would recompute (the part's own SHA-256 of its compact text).
    auto resealed = [&](CJson part) {
        part.erase("sha256");
        const std::string digest = impactcert_check::detail::sha256_hex(part.dump());
        part["sha256"] = digest;
        write_text(dir + "/mut.json", part.dump());
        return run_cli("sweep --merge '" + dir + "/mut.json' -o '" + dir + "/out'");
    };
    REQUIRE(resealed(source).status == 0);
    struct Case {
        const char* what;
        std::function<void(CJson&)> change;
        int status;
    };
    const std::vector<Case> cases = {
        {"no values", [](CJson& p) { p["run"]["parameters"][0]["values"] = CJson::array(); }, 2},
        {"no values of the second", [](CJson& p) { p["run"]["parameters"][1]["values"] = CJson::array(); }, 2},
        {"shard not an object", [](CJson& p) { p["shard"] = "x"; }, 2},
        {"index a string", [](CJson& p) { p["points"][0]["index"] = "0"; }, 2},
        {"junk on a point", [](CJson& p) { p["points"][0]["obligations"] = "x"; }, 2},
        {"no derive", [](CJson& p) { p["points"][1].erase("derive"); }, 2},
        {"a verdict not a string", [](CJson& p) { p["points"][3]["obligations"]["P1"]["verdict"] = 1; }, 2},
        {"a 36 M point grid",
         [](CJson& p) {
             for (int k = 0; k < 2; ++k) {
                 CJson values = CJson::array();
                 for (int i = 0; i < 6000; ++i)
                     values.push_back(std::to_string(i));
                 p["run"]["parameters"][k]["values"] = values;
             }
         },
         3},
    };
    for (const auto& c : cases) {
        INFO(c.what);
        CJson part = source;
        c.change(part);
        const auto run = resealed(part);
        INFO(run.err);
        CHECK(run.status == c.status);
        CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    }
}
