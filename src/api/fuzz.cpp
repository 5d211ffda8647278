// SPDX-License-Identifier: GPL-3.0-or-later
// api/fuzz.cpp -- impactcert::api::fuzz: `impactcert fuzz --law` with the implementation a C++
// callable in this process (fuzz::Implementation over a BatchFunction).
#include "api/internal.hpp"

#include "fuzz/consistency.hpp"
#include "fuzz/consistency_report.hpp"
#include "fuzz/fuzz.hpp"
#include "fuzz/fuzz_report.hpp"

#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>

namespace impactcert::api {

using detail::translated;

namespace {

// The first exception the callable throws ends the run: every later point is `skipped` without a
// call, and fuzz() rethrows it when the run is over (an exception is the caller's error, not a
// finding about the implementation).
struct Failure {
    std::mutex mutex;
    std::exception_ptr first;
    std::atomic<bool> failed{false};
};

class CallableImpl final : public fuzz::Implementation {
  public:
    CallableImpl(const BatchFunction& f, std::size_t in_dim, std::size_t out_dim, std::size_t batch, std::string name,
                 std::shared_ptr<Failure> failure)
        : f_(f), in_dim_(in_dim), out_dim_(out_dim), batch_(batch), name_(std::move(name)), failure_(std::move(failure)) {}
    void eval(const double* in, double* out, double*, std::size_t count, fuzz::ImplStatus* status) override {
        if (!failure_->failed.load()) {
            try {
                f_(in, out, count);
                for (std::size_t i = 0; i < count; ++i)
                    status[i] = fuzz::ImplStatus::ok;
                return;
            } catch (...) {
                const std::lock_guard<std::mutex> lock(failure_->mutex);
                if (!failure_->first)
                    failure_->first = std::current_exception();
                failure_->failed = true;
            }
        }
        for (std::size_t i = 0; i < count; ++i) {
            status[i] = fuzz::ImplStatus::skipped;
            for (std::size_t k = 0; k < out_dim_; ++k)
                out[i * out_dim_ + k] = 0;
        }
    }
    std::size_t batch_samples() const override { return batch_; }
    std::unique_ptr<fuzz::Implementation> clone() const override {
        return std::make_unique<CallableImpl>(f_, in_dim_, out_dim_, batch_, name_, failure_);
    }
    std::string describe() const override { return name_; }
    std::string replay_flags() const override { return ""; }

  private:
    const BatchFunction& f_;
    std::size_t in_dim_, out_dim_, batch_;
    std::string name_;
    std::shared_ptr<Failure> failure_;
};

} // namespace

FuzzResult fuzz(const Law& law, const BatchFunction& implementation, const FuzzOptions& o) {
    if (!implementation)
        throw api::InputError("fuzz: no implementation (an empty function)");
    auto failure = std::make_shared<Failure>();
    FuzzResult result = translated([&] {
        const Model& model = law.impl().model;
        if (o.max_ulps && o.max_rel_error)
            throw api::InputError("--max-ulps and --max-rel-error: give one tolerance");
        if (o.max_rel_error && !(*o.max_rel_error >= 0 && std::isfinite(*o.max_rel_error)))
            throw api::InputError("--max-rel-error: must be a finite number >= 0");
        if (!(o.seconds >= 0 && std::isfinite(o.seconds)))
            throw api::InputError("--seconds: must be a finite number >= 0");
        if (o.batch == 0 || o.batch > 65536)
            throw api::InputError("batch: expected 1..65536 points per call");
        const fuzz::LawFacts facts = fuzz::law_facts(model, o.velocities);
        const fuzz::LawReference reference(model, o.velocities, facts.continuous_tiling);
        fuzz::Options options;
        options.seed = o.seed;
        options.samples = o.samples;
        options.seconds = o.seconds;
        options.jobs = o.jobs == 0 ? 1 : o.jobs;
        options.allow_extreme = o.allow_extreme;
        if (o.max_rel_error) {
            options.tolerance = fuzz::Tolerance::relative;
            options.max_rel_error = *o.max_rel_error;
        } else {
            options.tolerance = fuzz::Tolerance::ulps;
            options.max_ulps = o.max_ulps.value_or(0);
        }
        if (!o.range.empty())
            std::tie(options.range_lo, options.range_hi) = fuzz::parse_range(o.range);
        options.replay_prefix = "the in-process implementation at";
        CallableImpl impl(implementation, reference.in_dim(), reference.in_dim(), o.batch, o.name, failure);
        const fuzz::Summary sum = fuzz::run(options, reference, impl, facts.properties, {});
        FuzzResult r;
        const bool fails = sum.fails(options.allow_extreme);
        r.verdict = fails ? "violations" : sum.samples == 0 ? "undecided" : "no violation";
        r.exit_status = fails ? 1 : sum.samples == 0 ? 3 : 0;
        r.samples = sum.samples;
        r.violating = sum.gated + (options.allow_extreme ? 0 : sum.extreme);
        r.json = fuzz::report_json(sum, options, facts.properties, model.law().name, impl.describe(), o.velocities,
                                   std::nullopt)
                     .dump(2) +
                 "\n";
        return r;
    });
    if (failure->first)
        std::rethrow_exception(failure->first);
    return result;
}

FuzzResult fuzz_consistency(const System& system, const BatchFunction& implementation, const ConsistencyOptions& o) {
    if (!implementation)
        throw api::InputError("fuzz: no implementation (an empty function)");
    auto failure = std::make_shared<Failure>();
    FuzzResult result = translated([&] {
        if (!(o.seconds >= 0 && std::isfinite(o.seconds)))
            throw api::InputError("--seconds: must be a finite number >= 0");
        if (o.batch == 0 || o.batch > 65536)
            throw api::InputError("batch: expected 1..65536 points per call");
        fuzz::ConsistencyRequest q;
        q.system = system.impl().system;
        q.velocities = o.velocities;
        q.max_rel_error = o.max_rel_error;
        if (o.restitution)
            q.restitution = detail::to_internal(*o.restitution, "--restitution");
        q.reference = o.reference;
        q.reference_given = !o.reference.empty();
        q.require = o.require;
        q.range = o.range;
        q.seed = o.seed;
        q.samples = o.samples;
        q.seconds = o.seconds;
        q.jobs = o.jobs == 0 ? 1 : o.jobs;
        fuzz::ConsistencyPlan plan = fuzz::plan_consistency(q);
        plan.options.replay_prefix = "the in-process implementation at --";
        const std::size_t dim = o.velocities ? plan.mech.balls() : plan.mech.contacts();
        CallableImpl impl(implementation, dim, dim, o.batch, o.name, failure);
        const fuzz::ConsistencySummary sum = fuzz::run_consistency(plan.mech, plan.options, impl, nullptr);
        const auto checked = fuzz::checked_properties(plan, false);
        FuzzResult r;
        const bool nothing = sum.samples == 0;
        r.verdict = sum.violations() ? "violations" : nothing ? "undecided" : "no violation";
        r.exit_status = sum.violations() ? 1 : nothing ? 3 : 0;
        r.samples = sum.samples;
        r.violating = sum.violations();
        r.json = fuzz::consistency_report_json(sum, plan, impl.describe(), checked, fuzz::reference_supremum(sum, plan),
                                               nullptr, std::nullopt)
                     .dump(2) +
                 "\n";
        return r;
    });
    if (failure->first)
        std::rethrow_exception(failure->first);
    return result;
}

} // namespace impactcert::api
