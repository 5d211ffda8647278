// SPDX-License-Identifier: GPL-3.0-or-later
// cli/shard.cpp -- `verify --shard K/N` and `certify --shard K/N` (shard.hpp): one slice of a
// verification, decided in this process; the parts of certify are merged and checked by
// impactcert-check PART...
#include "cli/common.hpp"

#include "prover/certificate.hpp"
#include "prover/shard.hpp"
#include "prover/verdict_output.hpp"

#include <fstream>
#include <iostream>

namespace impactcert::cli {

namespace {

// The obligations slice `shard` decides: its own, and nonexpansive (whose pair blocks every
// shard shares, unless it is decided before them: then it is its owner's).
std::vector<std::string> slice_ids(const Shard& shard) {
    std::vector<std::string> ids;
    for (std::size_t i = 0; i < std::size(kObligationIds); ++i)
        if (owns(shard, i) || std::string(kObligationIds[i]) == "nonexpansive")
            ids.push_back(kObligationIds[i]);
    return ids;
}

VerifyReport decide_slice(const Model& model, const Shard& shard, Limits limits) {
    limits.shard_index = shard.index;
    limits.shard_count = shard.count;
    const std::vector<std::string> ids = slice_ids(shard);
    TerminalProgress progress;
    return verify(model, limits, progress.callback(), &ids);
}

// The report of the slice alone: the obligations the part holds (make_certificate_part's rule).
VerifyReport slice_only(VerifyReport report, const Shard& shard) {
    VerifyReport out;
    out.law = report.law;
    for (std::size_t i = 0; i < report.obligations.size(); ++i) {
        auto& o = report.obligations[i];
        const bool slice = o.data.is_object() && o.data.contains("slice");
        if (slice || (owns(shard, i) && o.method != "not requested"))
            out.obligations.push_back(std::move(o));
    }
    return out;
}

} // namespace

int run_verify_shard(const std::string& law_path, const Shard& shard, bool json, Limits limits) {
    const Model model = load_model(law_path, limits);
    model.require_independent_columns("--shard");
    if (model.has_friction())
        throw InputError("--shard: laws with friction are not sharded yet (verify and certify them whole)");
    limits.evidence = false;
    const VerifyReport report = slice_only(decide_slice(model, shard, limits), shard);
    const std::string label = "shard " + std::to_string(shard.index + 1) + "/" + std::to_string(shard.count);
    if (json) {
        Json j = verdict_json(report);
        j["shard"] = Json{{"index", shard.index + 1}, {"count", shard.count}};
        write_stdout(j.dump(2) + "\n");
    } else {
        write_stdout(label + " of " + verdict_table(report, model));
    }
    return report.exit_status();
}

int run_certify_shard(const std::string& law_path, const Shard& shard, const std::string& out_path, Limits limits) {
    const Model model = load_model(law_path, limits);
    model.require_independent_columns("--shard");
    if (model.has_friction())
        throw InputError("--shard: laws with friction are not sharded yet (verify and certify them whole)");
    VerifyReport report = decide_slice(model, shard, limits);
    const Json part = make_certificate_part(model, std::move(report), shard);
    write_file(out_path, certificate_text(part));
    std::cerr << "impactcert: wrote " << out_path << " (" << model.law().name << ", shard " << shard.index + 1 << " of "
              << shard.count << ")\n";
    return kExitProved; // a part is not a verdict: impactcert-check PART... gives it
}

} // namespace impactcert::cli
