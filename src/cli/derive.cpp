// SPDX-License-Identifier: GPL-3.0-or-later
// cli/derive.cpp -- `impactcert derive sequential | newton | poisson | cradle`.
#include "cli/tools.hpp"

#include "model/cradle.hpp"
#include "base/json.hpp"
#include "model/law_json.hpp"
#include "derive/derived_law.hpp"

#include <iostream>

namespace impactcert::cli {

namespace {

void emit(const std::string& out_path, const std::string& text, const std::string& summary) {
    if (out_path.empty() || out_path == "-") { // "-": standard output, as the default
        write_stdout(text);
        return;
    }
    write_file(out_path, text);
    std::cerr << "impactcert: wrote " << out_path << " (" << summary << ")\n";
}

std::vector<OutcomeDecl> outcomes_from(const std::string& path, std::size_t balls) {
    if (path.empty())
        return {};
    const Law source = load_law_file(path);
    if (source.outcomes.empty())
        throw InputError("--outcomes-from " + path + ": the law declares no outcomes");
    for (const auto& o : source.outcomes)
        if (o.u_minus.size() != balls)
            throw InputError("--outcomes-from " + path + ": outcome \"" + o.name + "\" has " +
                             std::to_string(o.u_minus.size()) + " ball velocities, the system " + std::to_string(balls));
    return source.outcomes;
}

} // namespace

int run_derive_sequential(const DeriveArgs& a) {
    DeriveOptions o;
    static_cast<System&>(o) = system_from(a.system);
    const Mechanics mech = make_mechanics(o);
    if (mech.has_friction() && a.rule == "any")
        throw InputError("--rule any: not with friction (give most-negative, left-first or right-first)");
    o.restitution = a.restitution.empty() && !o.System::restitution.empty()
                        ? o.System::restitution
                        : restitution_list(a.restitution.empty() ? "1" : a.restitution, mech.normals);
    const bool any_order = a.rule == "any";
    if (a.stream && (a.out.empty() || a.out == "-"))
        throw InputError("--stream: give the law file with -o FILE (the pieces are written as they are found)");
    if (a.stream && any_order)
        throw InputError("--stream: not with --rule any (every order is compared in memory)");
    if (a.stream && mech.has_friction())
        throw InputError("--stream: not with friction (the sequential law with friction is derived in memory)");
    o.rule = any_order ? ImpactRule::most_negative : parse_rule(a.rule);
    o.max_impacts = a.max_impacts;
    o.max_bits = a.max_bits;
    o.max_memory_mb = a.max_memory_mb;
    o.outcomes_override = outcomes_from(a.outcomes_from, mech.balls());
    TerminalProgress terminal; // on a terminal only, after a second
    if (const Progress show = terminal.callback())
        o.progress = [show](const char* phase, std::size_t done, std::size_t total) {
            show(std::string("derive ") + phase, std::to_string(done) + (total ? "/" + std::to_string(total) : ""));
        };
    std::string order_note;
    if (any_order) {
        const OrderResult order = order_independence(o, a.max_words);
        if (order.not_finite) {
            // A limit, not a proof that no finite law exists (issue 32): exit 3 naming the option.
            std::cerr << "impactcert: undecided: derive: at gamma- = " << short_text(*order.not_finite)
                      << " an admissible order takes more than " << o.max_impacts << " impacts (word "
                      << word_text(order.long_word, mech.contacts()).substr(0, 60)
                      << "...); raise the bound with --max-impacts\n";
            if (a.json) {
                Json j;
                j["format"] = "impactcert-derive/1";
                j["verdict"] = "undecided";
                j["limit"] = "--max-impacts";
                j["rule"] = "any";
                j["gamma_minus"] = to_json(*order.not_finite);
                j["max_impacts"] = o.max_impacts;
                j["word"] = word_text(order.long_word, mech.contacts()) + "...";
                write_stdout(j.dump(2) + "\n");
            }
            return kExitUndecided;
        }
        if (order.witness) {
            const OrderWitness& w = *order.witness;
            const std::size_t c = mech.contacts();
            std::cerr << "impactcert: derive: the order matters: at gamma- = " << short_text(w.gamma_minus)
                      << " the admissible words " << word_text(w.word_a, c) << " and " << word_text(w.word_b, c)
                      << " end at " << short_text(w.gamma_a) << " and " << short_text(w.gamma_b) << "\n";
            if (a.json) {
                Json j;
                j["format"] = "impactcert-derive/1";
                j["verdict"] = "order-dependent";
                j["rule"] = "any";
                j["gamma_minus"] = to_json(w.gamma_minus);
                j["words"] = Json::array({word_text(w.word_a, c), word_text(w.word_b, c)});
                j["gamma_plus"] = Json::array({to_json(w.gamma_a), to_json(w.gamma_b)});
                write_stdout(j.dump(2) + "\n");
            }
            return kExitRefuted;
        }
        order_note = "; order independent: every admissible order of impacts gives this law (" +
                     std::to_string(order.words) + " admissible words, the longest " + std::to_string(order.max_word) +
                     " impacts; impactcert derive sequential --rule any)";
    }
    DeriveResult r = a.stream ? derive_sequential_streamed(o, a.out) : derive_sequential(o);
    if (r.law && any_order)
        r.law->description += order_note;
    if (r.not_a_function) {
        std::cerr << "impactcert: derive: " << not_a_function_text(*r.not_a_function, r.not_a_function_reason) << "\n";
        if (a.json)
            write_stdout(not_a_function_json(*r.not_a_function, r.not_a_function_reason).dump(2) + "\n");
        return kExitRefuted;
    }
    if (r.not_finite) {
        // One line, shortened; the exact gamma- in full with --json. A sequence longer than the
        // bound is a limit, not a proof that none is finite (issue 32): exit 3 naming the option.
        std::string word = r.word.size() > 60 ? r.word.substr(0, 60) : r.word;
        std::cerr << "impactcert: undecided: derive: gamma- = " << short_text(*r.not_finite) << " needs more than "
                  << o.max_impacts << " impacts (word " << word << "...); raise the bound with --max-impacts"
                  << (a.json ? "" : " (the exact gamma- with --json)") << "\n";
        if (a.json) {
            Json j;
            j["format"] = "impactcert-derive/1";
            j["verdict"] = "undecided";
            j["limit"] = "--max-impacts";
            j["gamma_minus"] = to_json(*r.not_finite);
            j["max_impacts"] = o.max_impacts;
            j["word"] = r.word + "...";
            write_stdout(j.dump(2) + "\n");
        }
        return kExitUndecided;
    }
    if (a.stream) {
        std::cerr << "impactcert: wrote " << a.out << " (" << r.pieces << " pieces, " << r.regions
                  << " regions, longest word " << r.max_word << "; streamed)\n";
        return kExitProved;
    }
    set_expected_claims(*r.law, o.restitution);
    emit(a.out, law_file_text(*r.law),
         std::to_string(r.law->pieces.size()) + " pieces, " + std::to_string(r.regions) + " regions, longest word " +
             std::to_string(r.max_word));
    return kExitProved;
}

namespace {

// derive newton on a system with friction (SPEC section 9): the law, or exit 1 with the exact
// gamma- where it has two solutions (or none).
int run_derive_friction(const DeriveArgs& a, FrictionOptions o, const Mechanics& mech) {
    TerminalProgress terminal; // on a terminal only, after a second
    if (const Progress show = terminal.callback())
        o.progress = [show](const char* phase, std::size_t done, std::size_t total) {
            show(std::string("derive ") + phase, std::to_string(done) + (total ? "/" + std::to_string(total) : ""));
        };
    FrictionResult r = derive_newton_friction(o);
    if (r.not_a_function) {
        const NotAFunction& w = *r.not_a_function;
        std::cerr << "impactcert: derive: " << not_a_function_text(w)
                  << (w.none || a.json ? "" : "; the exact impulses with --json") << "\n";
        if (a.json)
            write_stdout(not_a_function_json(w).dump(2) + "\n");
        return kExitRefuted;
    }
    (void)mech;
    set_expected_claims(*r.law, o.restitution);
    emit(a.out, law_file_text(*r.law),
         std::to_string(r.law->pieces.size()) + " pieces, " + std::to_string(r.regions) + " mode regions, " +
             std::to_string(r.modes) + " modes, " + std::to_string(r.pairs) + " mode pairs without a second solution");
    return kExitProved;
}

} // namespace

int run_derive_classical(const DeriveArgs& a, bool poisson) {
    ClassicalOptions o;
    static_cast<System&>(o) = system_from(a.system);
    if (!a.restitution_tangential.empty()) {
        if (o.friction.empty())
            throw InputError("--restitution-tangential: the system has no friction");
        const auto e_t = parse_cli_number(a.restitution_tangential);
        if (!e_t || sign_of(*e_t) == Sign::negative || *e_t > Rational(1))
            throw InputError("--restitution-tangential: expected a rational in [0, 1], got \"" + a.restitution_tangential + "\"");
        for (auto& f : o.friction)
            f.restitution_tangential = *e_t;
    }
    const Mechanics mech = make_mechanics(o, poisson ? Dependent::refuse : Dependent::allow);
    if (mech.has_friction() && poisson)
        throw InputError("derive poisson: the Poisson-type law with friction is not offered (proofs/README.md, "
                         "\"Friction\": Glocker's Part II law needs the tangential state at the end of compression)");
    o.restitution = a.restitution.empty() && !o.System::restitution.empty()
                        ? o.System::restitution
                        : restitution_list(a.restitution.empty() ? "1" : a.restitution, mech.normals);
    o.on = parse_restitution_on(a.restitution_on);
    o.max_bits = a.max_bits;
    o.max_memory_mb = a.max_memory_mb;
    if (poisson && o.on != RestitutionOn::all)
        throw InputError("--restitution-on: the Poisson-type law has no such choice (its expansion phase acts only "
                         "where compression did)");
    o.outcomes_override = outcomes_from(a.outcomes_from, mech.balls());
    if (mech.has_friction() || mech.redundant()) { // dependent columns: by contact modes too (Lemma V)
        FrictionOptions fo;
        static_cast<ClassicalOptions&>(fo) = o;
        fo.max_modes = a.max_modes;
        return run_derive_friction(a, fo, mech);
    }
    Law law = poisson ? derive_poisson(o) : derive_newton(o);
    set_expected_claims(law, o.restitution);
    emit(a.out, law_file_text(law), std::to_string(law.pieces.size()) + " pieces");
    return kExitProved;
}

int run_derive_cradle(const CradleArgs& a) {
    if (a.pieces != "representatives" && a.pieces != "all")
        throw InputError("--pieces: expected representatives or all, got \"" + a.pieces + "\"");
    if (a.pieces == "all" && a.balls > 8)
        throw InputError("--pieces all: at most 8 balls (40,320 listed pieces); larger laws are written compactly");
    const Law law = cradle_law(a.balls, a.pieces == "all" ? CradleListing::all : CradleListing::representatives,
                               !a.no_symmetries);
    std::size_t cones = 1; // n! (not generated here: verify and certify expand the law)
    for (std::size_t k = 2; k <= a.balls; ++k)
        cones *= k;
    emit(a.out, law_file_text(law),
         std::to_string(law.pieces.size()) + " pieces listed, " + std::to_string(cones) + " in all, " +
             std::to_string(law.symmetries.size()) + " symmetries");
    // Never a law that verify cannot load within its default limits without saying so (18.2d):
    // the pieces, and their memory as Model counts it (c x c matrices Q, R, R^-1 of small
    // rationals, 96 bytes each, plus the piece's name and tables).
    const std::size_t c = a.balls - 1;
    const std::size_t mb = (cones * (3 * c * c * 104 + 512 + 2 * 16 * a.balls) >> 20) + 1;
    const Limits defaults;
    if (cones > defaults.max_pieces || mb > defaults.max_memory_mb)
        std::cerr << "impactcert: note: verify, certify and impactcert-check need --max-pieces " << cones
                  << " --max-memory " << mb * 3 / 2 << " or more for this law (" << cones << " pieces, about " << mb
                  << " MB of numbers; the defaults are " << defaults.max_pieces << " and " << defaults.max_memory_mb
                  << "); verify --stream needs --max-pieces " << cones << " and about "
                  << ((cones * ((2 * c + 4) * 4 + 8)) >> 20) + 1 << " MB (proofs/README.md, \"Streamed laws\")\n";
    return kExitProved;
}

} // namespace impactcert::cli
