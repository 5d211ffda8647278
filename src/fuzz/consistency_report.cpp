// SPDX-License-Identifier: GPL-3.0-or-later
// consistency_report.cpp -- a consistency run's plan and report (consistency_report.hpp).
#include "fuzz/consistency_report.hpp"

#include "derive/derive.hpp"
#include "model/law_json.hpp"
#include "prover/verdict_output.hpp"

#include <cmath>
#include <cstdio>

namespace impactcert::fuzz {

ConsistencyPlan plan_consistency(const ConsistencyRequest& a, const std::function<void(PlanStage)>& between) {
    ConsistencyPlan s;
    ConsistencyOptions& o = s.options;
    for (const auto& item : a.require) {
        if (item == "nonexpansive")
            o.nonexpansive = true;
        else if (item == "continuity")
            o.continuity = true;
        else if (item == "restitution" && !a.restitution && !a.restitution_text)
            throw InputError("--require restitution: give the restitution with --restitution E");
        else if (item != "kinematic" && item != "kinetic" && item != "momentum" && item != "energy" &&
                 item != "friction_cone" && item != "coulomb" && item != "at-rest" && item != "restitution" &&
                 item != "nondeterministic")
            throw InputError("--require: unknown property \"" + item +
                             "\" (nonexpansive, continuity; kinematic, kinetic, momentum and energy are always checked, "
                             "friction_cone and coulomb with friction)");
    }
    if (!a.range.empty())
        std::tie(o.range_lo, o.range_hi) = parse_range(a.range);
    if (between)
        between(PlanStage::options);
    s.system = a.system_source ? a.system_source() : a.system;
    s.mech = make_mechanics(s.system, Dependent::allow);
    if (s.mech.redundant() && s.mech.has_polygons())
        throw InputError("--system: friction polygons on dependent contact columns are not fuzzed yet (derive newton and "
                         "verify read them)");
    if (s.mech.redundant() && !a.velocities)
        throw InputError("--velocities: the system's contact columns are dependent (rank " +
                         std::to_string(s.mech.basis.size()) + " of " + std::to_string(s.mech.contacts()) +
                         "), so contact velocities are not free inputs; give the implementation ball velocities");
    // --restitution: the restitution property (frictionless: wherever every impact law agrees;
    // with friction: Newton's, at every approaching contact that pushes) and the restitution of a
    // reference law named (approaching, newton).
    std::vector<Rational> restitution;
    if (a.restitution || a.restitution_text) {
        if (a.restitution_text ? a.restitution_text->empty() : a.restitution->empty())
            throw InputError("--restitution: expected E or one value per contact, got an empty text");
        // With friction the property is Newton's: against a reference law file (which may be a
        // sequential or Poisson-type law) it would contradict the reference the user declares.
        if (s.mech.has_friction() && !a.reference.empty() && a.reference != "approaching" && a.reference != "newton")
            throw InputError("--restitution: with friction the restitution property is Newton's, which a reference law "
                             "file need not be; give --reference approaching or newton, or no --restitution");
        restitution = a.restitution_text ? parse_number_list("--restitution", *a.restitution_text) : *a.restitution;
        if (restitution.size() == 1 && s.mech.normals > 1)
            restitution.assign(s.mech.normals, restitution[0]);
        if (restitution.size() != s.mech.normals)
            throw InputError("--restitution: expected one value or " + std::to_string(s.mech.normals) +
                             " (one per contact), got " + std::to_string(restitution.size()));
        for (std::size_t k = 0; k < restitution.size(); ++k)
            if (sign_of(restitution[k]) == Sign::negative || restitution[k] > Rational(1))
                throw InputError("--restitution: contact " + std::to_string(k + 1) + " must be in [0, 1], got " +
                                 to_string(restitution[k]));
    }
    // --cone circular (proofs/README.md, "Consistency with a circular friction cone"): the
    // tangents of a rough contact (one friction declaration: one mu, one e_T) share one disk
    // |Lambda_T| <= mu Lambda_N.
    if (!a.cone.empty() && a.cone != "box" && a.cone != "circular")
        throw InputError("--cone: expected box or circular, got \"" + a.cone + "\"");
    if (a.cone == "circular") {
        if (!s.mech.has_friction())
            throw InputError("--cone circular: the system has no friction");
        if (s.mech.has_polygons())
            throw InputError("--cone circular: the system declares friction polygons (facets)");
        if (s.mech.redundant())
            throw InputError("--cone circular: the system's contact columns are dependent (rank " +
                             std::to_string(s.mech.basis.size()) + " of " + std::to_string(s.mech.contacts()) +
                             "); the circular cone is checked on independent columns only");
        if (!a.reference.empty())
            throw InputError("--reference: impactcert's laws bound each tangent on its own (the friction box); with "
                             "--cone circular there is no reference law (the circular law is not cone-wise linear)");
        o.cone = Cone::circular;
    }
    if (a.max_ulps_given)
        throw InputError("--max-ulps: consistency fuzzing has no exact law to count ulps against; give --max-rel-error");
    if (a.max_rel_error) {
        if (!(*a.max_rel_error >= 0 && std::isfinite(*a.max_rel_error)))
            throw InputError("--max-rel-error: must be a finite number >= 0");
        s.R = *a.max_rel_error;
    }
    s.R_text = shortest_decimal(s.R);
    if (between)
        between(PlanStage::tolerance);
    const std::size_t dim = a.velocities ? s.mech.balls() : s.mech.contacts();
    if (dim > kMaxDim)
        throw InputError("fuzz: at most " + std::to_string(kMaxDim) + " input components, the system has " +
                         std::to_string(dim));
    if (a.reference_given && a.reference.empty())
        throw InputError("--reference: expected a law file or approaching, newton, poisson; got an empty text");
    if (!a.reference.empty()) {
        // The exact law the implementation means to compute: a law file of this system, or the
        // classical law by name, derived here with the restitution given (--restitution, else
        // the system's): "approaching" (Newton, restitution on approaching contacts only, what
        // sequential-impulse engines converge to), "newton" (on all), "poisson".
        const std::string& r = a.reference;
        if (r == "approaching" || r == "newton" || r == "poisson") {
            if ((s.mech.has_friction() || s.mech.redundant()) && r == "poisson")
                throw InputError("--reference poisson: the Poisson-type law with friction is not offered; give "
                                 "approaching or newton, or a law file");
            ClassicalOptions co;
            static_cast<System&>(co) = s.system;
            co.restitution = !restitution.empty() ? restitution : s.system.restitution;
            if (co.restitution.empty())
                throw InputError("--reference " + r + ": needs the restitution (give --restitution E)");
            co.on = r == "approaching" ? RestitutionOn::approaching : RestitutionOn::all;
            if (s.mech.has_friction() || s.mech.redundant()) {
                // The Newton law with Coulomb friction (or on dependent columns), derived here as `derive newton --system`
                // does; a system where it is not a function has no reference by name.
                FrictionOptions fo;
                static_cast<ClassicalOptions&>(fo) = co;
                FrictionResult fr = derive_newton_friction(fo);
                if (fr.not_a_function)
                    throw InputError("--reference " + r + ": the Newton law with friction of this system is not a function "
                                     "at gamma- = " + short_text(fr.not_a_function->gamma_minus) +
                                     " (impactcert derive newton --system shows both answers)");
                s.reference = std::make_unique<Model>(std::move(*fr.law));
            } else {
                s.reference = std::make_unique<Model>(r == "poisson" ? derive_poisson(co) : derive_newton(co));
            }
            std::string e;
            for (std::size_t k = 0; k < co.restitution.size(); ++k)
                e += (k ? "," : "") + to_string(co.restitution[k]);
            s.reference_name = (r == "approaching" ? "the Newton law, restitution on approaching contacts"
                                : r == "newton"    ? "the Newton law"
                                                   : "the Poisson law") +
                               std::string(s.mech.has_friction() ? " with Coulomb friction" : "") +
                               std::string(", e = ") + e;
        } else {
            s.reference = std::make_unique<Model>(load_model_file(r));
            if (s.reference->M() != s.mech.M || s.reference->full_W() != s.mech.W)
                throw InputError("--reference " + r + ": the law's system (M, W) is not the one given");
            s.reference_name = r;
        }
    }
    o.seed = a.seed;
    o.samples = a.samples;
    o.seconds = a.seconds;
    o.jobs = a.jobs;
    o.keep = a.keep;
    o.max_rel_error = s.R;
    o.velocities = a.velocities;
    o.restitution = restitution;
    o.reference = s.reference.get();
    return s;
}

std::array<bool, kProperties> checked_properties(const ConsistencyPlan& plan, bool nondeterminism) {
    std::array<bool, kProperties> checked{};
    for (auto p : {Property::kinematic, Property::kinetic, Property::energy, Property::at_rest, Property::non_finite})
        checked[static_cast<std::size_t>(p)] = true;
    checked[static_cast<std::size_t>(Property::momentum)] = plan.options.velocities;
    checked[static_cast<std::size_t>(Property::friction_cone)] = plan.mech.has_friction();
    checked[static_cast<std::size_t>(Property::coulomb)] = plan.mech.has_friction();
    checked[static_cast<std::size_t>(Property::nonexpansive)] = plan.options.nonexpansive;
    // Newton's restitution with friction asks which contacts push: not decided on dependent columns.
    checked[static_cast<std::size_t>(Property::restitution)] =
        !plan.options.restitution.empty() && !(plan.mech.redundant() && plan.mech.has_friction());
    checked[static_cast<std::size_t>(Property::nondeterministic)] = nondeterminism;
    checked[static_cast<std::size_t>(Property::continuity)] = plan.options.continuity;
    checked[static_cast<std::size_t>(Property::reference)] = plan.reference != nullptr;
    return checked;
}

Json finding_json(const Finding& f) {
    auto hexes = [](const std::vector<double>& v) {
        Json j = Json::array();
        for (double x : v)
            j.push_back(hex(x));
        return j;
    };
    Json e = {{"index", f.index}, {"what", property_id(f.property)}, {"detail", f.detail}, {"input", hexes(f.input)}};
    if (!f.exact.empty()) {
        Json x = Json::object();
        for (const auto& [name, value] : f.exact)
            x[name] = value;
        e["exact"] = x;
    }
    if (f.level)
        e["level"] = f.level == 1 ? "law" : "solver";
    if (f.level == 2)
        e["off"] = f.off;
    if (f.projection)
        e["projection"] = true;
    if (!f.input_b.empty())
        e["input_b"] = hexes(f.input_b);
    e["output"] = hexes(f.output);
    if (!f.output_b.empty())
        e["output_b"] = hexes(f.output_b);
    e["replay"] = f.replay;
    return e;
}

// The coverage line (text, JSON and JUnit alike), and what the checked inputs never had.
std::string coverage_text(const ConsistencySummary& sum) {
    auto u = [](std::uint64_t x) { return std::to_string(x); };
    std::string s = "approach patterns " + u(sum.patterns_hit) +
                    (sum.patterns ? "/" + u(sum.patterns) : std::string()) + " (which contacts approach)";
    if (sum.reference_pieces)
        s += ", reference pieces " + u(sum.reference_pieces_hit) + "/" + u(sum.reference_pieces) + " hit";
    if (sum.decades)
        s += ", scales 1e" + std::to_string(sum.decade_lo) + "..1e" + std::to_string(sum.decade_hi) + " (" +
             u(sum.decades) + (sum.decades == 1 ? " decade)" : " decades)");
    return s;
}

std::vector<std::string> coverage_gaps(const ConsistencySummary& sum) {
    auto u = [](std::uint64_t x) { return std::to_string(x); };
    std::vector<std::string> out;
    if (sum.patterns && sum.patterns_hit < sum.patterns)
        out.push_back(u(sum.patterns - sum.patterns_hit) + " of " + u(sum.patterns) +
                      " patterns of approaching contacts never checked (raise --samples)");
    if (sum.reference_pieces_hit < sum.reference_pieces)
        out.push_back(u(sum.reference_pieces - sum.reference_pieces_hit) + " of " + u(sum.reference_pieces) +
                      " pieces of the reference law never held a checked input");
    return out;
}

std::optional<LawBound> reference_supremum(const ConsistencySummary& sum, const ConsistencyPlan& plan) {
    // With a reference law, its exact sup T+/T- beside the worst energy gain found (proofs/README.md,
    // "The exact worst case of a law"); laws of more than six contacts are left out (2^c faces).
    // Only when energy gains were found, and for laws of at most 20,000 faces in all (the 7-ball
    // law has 1,922 pieces of 63 faces: `verify --worst-case` is the command for it).
    const auto& gains = sum.properties[static_cast<std::size_t>(Property::energy)];
    const Model* r = plan.reference.get();
    if (r && gains.count && r->contacts() <= 14 && !r->has_friction() &&
        r->pieces().size() * ((std::size_t{1} << r->contacts()) - 1) <= 20000)
        return energy_supremum(*r, WorstCaseOptions{});
    return std::nullopt;
}

Json consistency_report_json(const ConsistencySummary& sum, const ConsistencyPlan& plan, const std::string& implementation,
                             const std::array<bool, kProperties>& checked, const std::optional<LawBound>& reference_sup,
                             const Json& effort, const std::optional<StderrSummary>& stderr_summary) {
    const ConsistencyOptions& o = plan.options;
    const bool nothing = sum.samples == 0;
    char range[96];
    std::snprintf(range, sizeof range, "%.6g..%.6g", o.range_lo, o.range_hi);
    Json j;
    j["format"] = "impactcert-fuzz/1";
    j["mode"] = "consistency";
    j["system"] = plan.system.name;
    j["space"] = o.velocities ? "ball velocities" : "contact velocities";
    j["implementation"] = implementation;
    j["tolerance"] = "--max-rel-error " + plan.R_text;
    if (plan.mech.has_friction())
        j["cone"] = o.cone == Cone::circular ? "circular" : "box";
    j["range"] = range;
    j["seed"] = o.seed;
    j["jobs"] = o.jobs;
    j["samples"] = sum.samples;
    j["pairs"] = sum.pairs;
    j["skipped_not_approaching"] = sum.skipped;
    j["seconds"] = sum.seconds;
    j["samples_per_second"] = sum.seconds > 0 ? static_cast<double>(sum.samples) / sum.seconds : 0;
    Json gaps = Json::array();
    for (const auto& gap : coverage_gaps(sum))
        gaps.push_back(gap);
    j["coverage"] = {{"patterns_hit", sum.patterns_hit}, {"patterns", sum.patterns},
                     {"reference_pieces_hit", sum.reference_pieces_hit}, {"reference_pieces", sum.reference_pieces},
                     {"decades", sum.decades}, {"decade_lo", sum.decade_lo}, {"decade_hi", sum.decade_hi},
                     {"text", coverage_text(sum)}, {"not_tested", gaps}};
    Json props = Json::object(), violations = Json::object(), worst = Json::object();
    for (std::size_t p = 0; p < kProperties; ++p) {
        const char* id = property_id(static_cast<Property>(p));
        props[id] = checked[p];
        violations[id] = sum.properties[p].count;
        if (sum.properties[p].worst)
            worst[id] = finding_json(*sum.properties[p].worst);
    }
    violations["crashed"] = sum.crashed;
    violations["hung"] = sum.hung;
    violations["malformed"] = sum.malformed;
    violations["refused"] = sum.refused;
    j["checked_properties"] = props;
    j["violations"] = violations;
    Json projections = Json::object();
    for (std::size_t p = 0; p < kProperties; ++p)
        if (sum.properties[p].projections)
            projections[property_id(static_cast<Property>(p))] = sum.properties[p].projections;
    if (!projections.empty())
        j["projections"] = projections;
    j["worst"] = worst;
    if (plan.reference) {
        Json levels = Json::object(), worst_solver = Json::object();
        for (std::size_t p = 0; p < kProperties; ++p) {
            const auto& slot = sum.properties[p];
            if (!slot.count)
                continue;
            const char* id = property_id(static_cast<Property>(p));
            levels[id] = Json{{"law", slot.law}, {"solver", slot.solver},
                              {"unclassified", slot.count - slot.law - slot.solver}};
            if (slot.worst_solver)
                worst_solver[id] = finding_json(*slot.worst_solver);
        }
        j["reference"] = plan.reference_name;
        if (reference_sup && reference_sup->decided)
            j["reference_sup_energy_ratio"] = to_json(reference_sup->value);
        j["levels"] = levels;
        j["worst_solver"] = worst_solver;
        if (!effort.is_null())
            j["effort"] = effort;
    }
    Json examples = Json::array();
    for (const auto& f : sum.examples)
        examples.push_back(finding_json(f));
    j["examples"] = examples;
    if (const auto& e = stderr_summary)
        j["stderr"] = Json{{"lines", e->lines}, {"bytes", e->bytes}, {"first", e->first}};
    j["verdict"] = sum.violations() ? "violations" : nothing ? "undecided" : "no violation";
    return j;
}

} // namespace impactcert::fuzz
