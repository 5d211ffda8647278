// SPDX-License-Identifier: GPL-3.0-or-later
// api/verify.cpp -- impactcert::api::verify, certify and check_certificate: `impactcert verify
// --json`, `impactcert certify` and impactcert-check, in-process.
#include "api/internal.hpp"

#include "base/limits.hpp"
#include "model/law_json.hpp"
#include "prover/certificate.hpp"
#include "prover/obligations.hpp"
#include "prover/verdict_output.hpp"

#include <impactcert_check.hpp>

#include <sstream>

namespace impactcert::api {

using detail::translated;

namespace {

Limits limits_of(const VerifyOptions& o) {
    Limits l;
    l.max_pieces = o.max_pieces;
    l.max_memory_mb = o.max_memory_mb;
    l.jobs = o.jobs == 0 ? 1 : o.jobs;
    return l;
}

Report report_of(const VerifyReport& r) {
    Report out;
    out.law = r.law;
    out.verdict = r.verdict();
    out.exit_status = r.exit_status();
    for (const auto& o : r.obligations) {
        Obligation ob;
        ob.id = o.id;
        ob.claimed = o.claimed;
        ob.verdict = to_string(o.verdict);
        ob.checks = o.checks;
        ob.method = o.method;
        ob.limit = o.limit;
        if (!o.counterexample.is_null())
            ob.counterexample = o.counterexample.dump();
        out.obligations.push_back(std::move(ob));
    }
    out.json = verdict_json(r).dump(2) + "\n";
    return out;
}

} // namespace

const Obligation& Report::at(const std::string& id) const {
    for (const auto& o : obligations)
        if (o.id == id)
            return o;
    throw std::out_of_range("no obligation \"" + id + "\" in the report of " + law);
}

Report verify(const Law& law, const VerifyOptions& options) {
    return translated([&] {
        const Model& model = law.impl().model;
        Limits limits = limits_of(options);
        limits.evidence = false; // a verdict needs no certificate
        return report_of(impactcert::verify(model, limits));
    });
}

std::string certify(const Law& law, const VerifyOptions& options, Report* report) {
    return translated([&] {
        const Model& model = law.impl().model;
        VerifyReport r = impactcert::verify(model, limits_of(options));
        if (report)
            *report = report_of(r);
        return certificate_text(make_certificate(model, std::move(r)));
    });
}

CheckResult check_certificate(const std::string& certificate_text) {
    const impactcert_check::Outcome o = impactcert_check::check_text(certificate_text);
    return CheckResult{o.status, o.message};
}

} // namespace impactcert::api
