// SPDX-License-Identifier: GPL-3.0-or-later
// api/derive.cpp -- impactcert::api::derive: `impactcert derive sequential | newton | poisson`
// on a System, with the command line's defaults, checks and claims.
#include "api/internal.hpp"

#include "derive/derive.hpp"
#include "derive/derived_law.hpp"

namespace impactcert::api {

using detail::translated;

namespace {

// One value for every contact, or one per contact (the command line's --restitution); empty: the
// system's own (a scene's), else 1.
std::vector<impactcert::Rational> restitution_of(const DeriveOptions& o, const impactcert::System& s, std::size_t contacts) {
    if (o.restitution.empty())
        return !s.restitution.empty() ? s.restitution : std::vector<impactcert::Rational>(contacts, impactcert::Rational(1));
    auto e = detail::to_internal(o.restitution, "restitution");
    if (e.size() == 1 && contacts > 1)
        e.assign(contacts, e[0]);
    if (e.size() != contacts)
        throw api::InputError("restitution: expected one value or " + std::to_string(contacts) + " (one per contact), got " +
                              std::to_string(e.size()));
    return e;
}

Law wrap(impactcert::Law law) {
    return Law(std::make_shared<Law::Impl>(Law::Impl{Model(std::move(law))}));
}

} // namespace

Derivation derive(const System& system, const DeriveOptions& options) {
    return translated([&]() -> Derivation {
        const impactcert::System& s = system.impl().system;
        const Mechanics mech = make_mechanics(s);
        const auto restitution = restitution_of(options, s, mech.normals);
        Derivation out;
        if (options.kind == LawKind::sequential) {
            impactcert::DeriveOptions o;
            static_cast<impactcert::System&>(o) = s;
            o.restitution = restitution;
            o.rule = parse_rule(options.rule);
            o.max_impacts = options.max_impacts;
            o.max_bits = options.max_bits;
            o.max_memory_mb = options.max_memory_mb;
            DeriveResult r = derive_sequential(o);
            if (r.not_a_function) {
                out.refutation = not_a_function_text(*r.not_a_function, r.not_a_function_reason);
                out.witness = not_a_function_json(*r.not_a_function, r.not_a_function_reason).dump(2);
                return out;
            }
            if (r.not_finite)
                throw api::LimitError("derive: gamma- = " + to_string(*r.not_finite) + " needs more than " +
                                      std::to_string(o.max_impacts) + " impacts (word " + r.word.substr(0, 60) +
                                      "...); raise the bound with --max-impacts");
            set_expected_claims(*r.law, restitution);
            out.law = wrap(std::move(*r.law));
            return out;
        }
        if (options.rule != "most-negative")
            throw api::InputError("rule: the simultaneous laws have no order of impacts (sequential only)");
        ClassicalOptions o;
        static_cast<impactcert::System&>(o) = s;
        o.restitution = restitution;
        o.max_bits = options.max_bits;
        o.max_memory_mb = options.max_memory_mb;
        if (mech.has_friction()) {
            if (options.kind == LawKind::poisson)
                throw api::InputError("derive poisson: the Poisson-type law with friction is not offered (proofs/README.md, "
                                      "\"Friction\": Glocker's Part II law needs the tangential state at the end of compression)");
            FrictionOptions fo;
            static_cast<ClassicalOptions&>(fo) = o;
            FrictionResult r = derive_newton_friction(fo);
            if (r.not_a_function) {
                out.refutation = not_a_function_text(*r.not_a_function);
                out.witness = not_a_function_json(*r.not_a_function).dump(2);
                return out;
            }
            set_expected_claims(*r.law, restitution);
            out.law = wrap(std::move(*r.law));
            return out;
        }
        impactcert::Law law = options.kind == LawKind::poisson ? derive_poisson(o) : derive_newton(o);
        set_expected_claims(law, restitution);
        out.law = wrap(std::move(law));
        return out;
    });
}

} // namespace impactcert::api
