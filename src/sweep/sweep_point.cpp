// SPDX-License-Identifier: GPL-3.0-or-later
#include "sweep/sweep_point.hpp"

#include "base/errors.hpp"
#include "derive/derived_law.hpp"
#include "model/law_json.hpp"

#include <algorithm>
#include <cctype>

namespace impactcert {

SweepLaw parse_sweep_law(const std::string& text) {
    if (text == "sequential")
        return SweepLaw::sequential;
    if (text == "newton")
        return SweepLaw::newton;
    if (text == "poisson")
        return SweepLaw::poisson;
    throw InputError("--law: expected sequential, newton or poisson, got \"" + text + "\"");
}

const char* to_string(SweepLaw law) {
    return law == SweepLaw::sequential ? "sequential" : law == SweepLaw::newton ? "newton" : "poisson";
}

bool sweep_friction(const SweepSpec& spec) { return spec.system && !spec.system->friction.empty(); }

namespace sweep_detail {

bool is_name(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_'))
        return false;
    return std::all_of(s.begin(), s.end(), [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; });
}

Rational number(const std::string& text, const std::string& where) {
    std::string why;
    const auto x = parse_cli_number(text, &why);
    if (!x)
        throw InputError(where + ": \"" + text + "\" is not a number" + (why.empty() ? "" : " (" + why + ")"));
    return *x;
}

const char* detail_key(const std::string& derive) {
    return derive == "not-finite" ? "not_finite" : derive == "not-a-function" ? "not_a_function" : "limit";
}

namespace {

// A system parameter: mu / muK (friction), e / eK (restitution); K from 1, 0 for "every contact".
struct SystemParameter {
    bool friction = false;
    std::size_t contact = 0;
};

std::optional<SystemParameter> system_parameter(const std::string& name) {
    for (const auto& [prefix, friction] : {std::pair<std::string, bool>{"mu", true}, {"e", false}}) {
        if (name.rfind(prefix, 0) != 0)
            continue;
        const std::string rest = name.substr(prefix.size());
        if (rest.empty())
            return SystemParameter{friction, 0};
        if (rest.size() > 6 || rest[0] == '0' || !std::all_of(rest.begin(), rest.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
            continue;
        return SystemParameter{friction, static_cast<std::size_t>(std::stoul(rest))};
    }
    return std::nullopt;
}

bool used_in_restitution(const SweepSpec& spec, const std::string& name) {
    return std::find(spec.restitution.begin(), spec.restitution.end(), name) != spec.restitution.end();
}

Rational value_of(const SweepSpec& spec, const std::vector<Rational>& values, const std::string& item, const std::string& option) {
    for (std::size_t p = 0; p < spec.parameters.size(); ++p)
        if (spec.parameters[p].name == item)
            return values[p];
    return number(item, option);
}

std::size_t normal_contacts(const System& s) { return make_mechanics(s).normals; }

// The system and restitution at a point.
std::pair<System, std::vector<Rational>> system_at(const SweepSpec& spec, const std::vector<Rational>& values) {
    System s;
    if (spec.system) {
        s = *spec.system;
    } else {
        for (const auto& m : spec.masses)
            s.masses.push_back(value_of(spec, values, m, "--masses"));
    }
    const std::size_t c = spec.system ? normal_contacts(s) : s.masses.size() - 1;
    std::vector<Rational> e;
    for (const auto& item : spec.restitution)
        e.push_back(value_of(spec, values, item, "--restitution"));
    if (e.empty())
        e = !s.restitution.empty() ? s.restitution : std::vector<Rational>(c, Rational(1));
    if (e.size() == 1 && c > 1)
        e.assign(c, e[0]);
    if (spec.system)
        for (std::size_t p = 0; p < spec.parameters.size(); ++p) {
            const std::string& name = spec.parameters[p].name;
            if (used_in_restitution(spec, name))
                continue;
            const auto sp = system_parameter(name);
            if (!sp)
                continue; // refused by validate_parameters
            if (sp->friction) {
                for (auto& f : s.friction)
                    if (sp->contact == 0 || f.contact + 1 == sp->contact)
                        f.mu = values[p];
            } else {
                for (std::size_t k = 0; k < e.size(); ++k)
                    if (sp->contact == 0 || k + 1 == sp->contact)
                        e[k] = values[p];
            }
        }
    return {s, e};
}

} // namespace

void validate_parameters(const SweepSpec& spec) {
    if (!spec.system) {
        // A chain: every name used must be varied, every varied name used.
        std::vector<std::string> used;
        for (const auto* list : {&spec.masses, &spec.restitution})
            for (const auto& item : *list)
                if (is_name(item)) {
                    bool known = false;
                    for (const auto& p : spec.parameters)
                        known = known || p.name == item;
                    if (!known)
                        throw InputError("\"" + item + "\" is not a number and not a --vary parameter");
                    used.push_back(item);
                }
        for (const auto& p : spec.parameters)
            if (std::find(used.begin(), used.end(), p.name) == used.end())
                throw InputError("--vary " + p.name + ": the parameter appears in neither --masses nor --restitution");
        return;
    }
    const System& s = *spec.system;
    const std::size_t c = normal_contacts(s);
    if (spec.law == SweepLaw::poisson && !s.friction.empty())
        throw InputError("--law poisson: the Poisson-type law with friction is not offered (proofs/README.md, \"Friction\")");
    for (const auto& item : spec.restitution)
        if (is_name(item)) {
            bool known = false;
            for (const auto& p : spec.parameters)
                known = known || p.name == item;
            if (!known)
                throw InputError("--restitution: \"" + item + "\" is not a number and not a --vary parameter");
        }
    if (!spec.restitution.empty() && spec.restitution.size() != 1 && spec.restitution.size() != c)
        throw InputError("--restitution: expected one value or one per contact (" + std::to_string(c) + ")");
    for (const auto& p : spec.parameters) {
        if (used_in_restitution(spec, p.name))
            continue;
        const auto sp = system_parameter(p.name);
        if (!sp)
            throw InputError("--vary " + p.name + ": with --system or --scene a parameter is mu, muK (contact K's friction), e or "
                             "eK (contact K's restitution), or a name used in --restitution");
        if (sp->contact > c)
            throw InputError("--vary " + p.name + ": the system has " + std::to_string(c) + " contacts");
        if (sp->friction) {
            bool found = false;
            for (const auto& f : s.friction)
                found = found || sp->contact == 0 || f.contact + 1 == sp->contact;
            if (!found)
                throw InputError("--vary " + p.name + ": " +
                                 (sp->contact == 0 ? std::string("the system has no friction")
                                                   : "contact " + std::to_string(sp->contact) + " has no friction"));
        } else if (!spec.restitution.empty()) {
            throw InputError("--vary " + p.name + ": --restitution is given; name the parameter there instead");
        }
        for (const auto& v : p.values) {
            if (sp->friction && sign_of(v) == Sign::negative)
                throw InputError("--vary " + p.name + ": mu = " + to_string(v) + " is negative");
            if (!sp->friction && (sign_of(v) == Sign::negative || v > Rational(1)))
                throw InputError("--vary " + p.name + ": e = " + to_string(v) + " is outside [0, 1]");
        }
    }
    for (const auto& p : spec.parameters)
        if (used_in_restitution(spec, p.name))
            for (const auto& v : p.values)
                if (sign_of(v) == Sign::negative || v > Rational(1))
                    throw InputError("--restitution: " + p.name + " = " + to_string(v) + " is outside [0, 1]");
    for (const auto& item : spec.restitution)
        if (!is_name(item)) {
            const Rational e = number(item, "--restitution");
            if (sign_of(e) == Sign::negative || e > Rational(1))
                throw InputError("--restitution: " + item + " is outside [0, 1]");
        }
}

PointLaw law_at(const SweepSpec& spec, const std::vector<Rational>& values) {
    auto [s, e] = system_at(spec, values);
    PointLaw out;
    try {
        if (spec.law == SweepLaw::sequential) {
            DeriveOptions o;
            static_cast<System&>(o) = s;
            o.restitution = e;
            o.rule = spec.rule;
            o.max_impacts = spec.max_impacts;
            o.max_memory_mb = spec.limits.max_memory_mb; // --max-memory bounds the derivation too
            DeriveResult d = derive_sequential(o);
            if (d.not_a_function) {
                out.derive = "not-a-function";
                out.detail = not_a_function_json(*d.not_a_function, d.not_a_function_reason);
                return out;
            }
            if (!d.law) {
                out.derive = "not-finite";
                out.detail = Json{{"gamma", to_json(*d.not_finite)}, {"word", d.word + "..."}};
                return out;
            }
            out.derive = "ok";
            out.max_word = d.max_word;
            out.law = std::move(d.law);
            if (s.friction.empty())
                out.sequential = o;
            return out;
        }
        ClassicalOptions o;
        static_cast<System&>(o) = s;
        o.restitution = e;
        o.on = spec.on;
        o.max_memory_mb = spec.limits.max_memory_mb;
        if (!s.friction.empty()) {
            FrictionOptions fo;
            static_cast<ClassicalOptions&>(fo) = o;
            FrictionResult r = derive_newton_friction(fo);
            if (r.not_a_function) {
                out.derive = "not-a-function";
                out.detail = not_a_function_json(*r.not_a_function);
                return out;
            }
            out.derive = "ok";
            out.law = std::move(r.law);
            return out;
        }
        out.derive = "ok";
        out.law = spec.law == SweepLaw::poisson ? derive_poisson(o) : derive_newton(o);
        return out;
    } catch (const DeriveLimit& x) {
        out = PointLaw{};
        out.derive = "undecided";
        out.detail = x.what();
        return out;
    }
}

} // namespace sweep_detail

} // namespace impactcert
