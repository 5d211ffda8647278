// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_report.cpp -- the report of a law-mode fuzz run (fuzz_report.hpp).
#include "fuzz/fuzz_report.hpp"

#include "prover/obligations.hpp"

#include <cstdio>

namespace impactcert::fuzz {

LawFacts law_facts(const Model& model, bool velocities) {
    // The fuzzer's own limits come before any proof work (a c = 70 law used to be verified, with
    // certificate evidence, for a minute before this was said).
    const std::size_t dim = velocities ? model.balls() : model.contacts();
    if (dim > kMaxDim || model.contacts() > kMaxDim)
        throw InputError("the fuzzer handles laws of at most " + std::to_string(kMaxDim) + " " +
                         (velocities ? "balls" : "contacts") + " (this law has " + std::to_string(dim) + ")");
    static const std::vector<std::string> ids = {"fan", "P1", "kinematic", "energetic", "nonexpansive-lemma"};
    Limits limits;
    limits.evidence = false; // verdicts only: the fuzzer uses no certificate evidence
    const VerifyReport report = verify(model, limits, {}, &ids);
    auto proved = [&](const char* id) { return report.at(id).verdict == Verdict::proved; };
    LawFacts f;
    f.continuous_tiling = proved("fan") && proved("P1");
    f.properties.nonnegative = proved("kinematic");
    f.properties.energy = proved("energetic");
    f.properties.nonexpansive = proved("nonexpansive-lemma");
    return f;
}

std::string count_text(std::uint64_t n) {
    char buf[32];
    if (n >= 1000000)
        std::snprintf(buf, sizeof buf, "%.1fM", static_cast<double>(n) / 1e6);
    else
        std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(n));
    return buf;
}

// The coverage line (text, JSON and JUnit alike) and what the run did not test.
std::string coverage_text(const Summary& sum) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "pieces %llu/%llu hit, facets %llu/%llu probed, scales 1e%d..1e%d (%llu decades), prefix %llu probes",
                  static_cast<unsigned long long>(sum.pieces_hit), static_cast<unsigned long long>(sum.pieces),
                  static_cast<unsigned long long>(sum.facets_probed), static_cast<unsigned long long>(sum.facets),
                  sum.decade_lo, sum.decade_hi, static_cast<unsigned long long>(sum.decades),
                  static_cast<unsigned long long>(sum.prefix));
    return buf;
}

std::vector<std::string> untested(const Summary& sum, const Options& o) {
    std::vector<std::string> out;
    auto u = [](std::uint64_t x) { return std::to_string(x); };
    if (sum.pieces_hit < sum.pieces)
        out.push_back(u(sum.pieces - sum.pieces_hit) + " of " + u(sum.pieces) + " pieces never held a checked input (raise --samples or --seconds)");
    if (sum.facets_probed < sum.facets)
        out.push_back(u(sum.facets - sum.facets_probed) + " of " + u(sum.facets) + " facets never probed");
    char buf[160];
    if (o.range_hi > 0 && o.range_lo > 0x1p-1000) {
        std::snprintf(buf, sizeof buf, "no magnitude below %.3g: thresholds and tolerances there are unseen", o.range_lo);
        out.push_back(buf);
    }
    if (o.range_hi > 0 && o.range_hi < 0x1p1000) {
        std::snprintf(buf, sizeof buf, "no magnitude above %.3g: overflow there is unseen", o.range_hi);
        out.push_back(buf);
    }
    return out;
}

std::string tolerance_text(const Options& o) {
    return o.tolerance == Tolerance::relative ? "--max-rel-error " + shortest_decimal(o.max_rel_error)
           : o.tolerance == Tolerance::ulps   ? "--max-ulps " + std::to_string(o.max_ulps)
                                                    : "the implementation's stated bound";
}

Json report_json(const Summary& sum, const Options& options, const Properties& properties,
                 const std::string& law_name, const std::string& implementation, bool velocities,
                 const std::optional<StderrSummary>& stderr_summary) {
    auto hexes = [](const std::vector<double>& v) {
        Json a = Json::array();
        for (double x : v)
            a.push_back(hex(x));
        return a;
    };
    Json j;
    j["format"] = "impactcert-fuzz/1";
    j["law"] = law_name;
    j["space"] = velocities ? "ball velocities" : "contact velocities";
    j["implementation"] = implementation;
    j["tolerance"] = tolerance_text(options);
    j["seed"] = options.seed;
    j["jobs"] = options.jobs;
    j["samples"] = sum.samples;
    j["pairs"] = sum.pairs;
    j["seconds"] = sum.seconds;
    j["samples_per_second"] = sum.seconds > 0 ? static_cast<double>(sum.samples) / sum.seconds : 0;
    if (options.range_hi > 0) {
        char range[96];
        std::snprintf(range, sizeof range, "%.6g..%.6g", options.range_lo, options.range_hi);
        j["range"] = range;
    }
    j["reference_through_gmp"] = sum.slow;
    j["outside_every_cone"] = sum.outside;
    j["max_error_ulps"] = sum.max_ulps;
    j["max_relative_error"] = sum.max_rel_error;
    j["checked_properties"] = {{"nonnegative", properties.nonnegative}, {"energy", properties.energy},
                               {"nonexpansive", properties.nonexpansive}};
    j["coverage"] = {{"pieces_hit", sum.pieces_hit}, {"pieces", sum.pieces}, {"facets_probed", sum.facets_probed},
                     {"facets", sum.facets}, {"decade_lo", sum.decade_lo}, {"decade_hi", sum.decade_hi},
                     {"decades", sum.decades}, {"prefix", sum.prefix}, {"text", coverage_text(sum)},
                     {"not_tested", untested(sum, options)}};
    j["extreme_samples"] = sum.extreme;
    j["gated_samples"] = sum.gated;
    j["allow_extreme"] = options.allow_extreme;
    j["violations"] = {{"outside_tolerance", sum.inaccurate}, {"classification", sum.misclassified},
                       {"non_finite", sum.non_finite}, {"negative_output", sum.negative},
                       {"energy", sum.energy}, {"nonexpansive", sum.nonexpansive},
                       {"crashed", sum.crashed}, {"hung", sum.hung}, {"malformed", sum.malformed},
                       {"refused", sum.refused}};
    Json examples = Json::array();
    for (const auto& v : sum.examples) {
        Json e = {{"index", v.index}, {"what", v.what}, {"generator", v.kind}, {"extreme", v.extreme},
                  {"input", hexes(v.input)}};
        if (!v.input_b.empty())
            e["input_b"] = hexes(v.input_b);
        e["output"] = hexes(v.output);
        e["expected"] = hexes(v.expected);
        e["replay"] = v.replay;
        examples.push_back(e);
    }
    j["examples"] = examples;
    if (const auto& e = stderr_summary)
        j["stderr"] = Json{{"lines", e->lines}, {"bytes", e->bytes}, {"first", e->first}};
    j["verdict"] = sum.fails(options.allow_extreme) ? "violations" : sum.samples == 0 ? "undecided" : "no violation";
    return j;
}

} // namespace impactcert::fuzz
