// SPDX-License-Identifier: GPL-3.0-or-later
// api/law.cpp -- impactcert::api: errors, systems, laws and their exact evaluation.
#include "api/internal.hpp"

#include "base/json.hpp"
#include "base/limits.hpp"
#include "base/output_file.hpp"
#include "derive/derive.hpp"
#include "derive/derived_law.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "report/report.hpp"
#include "sweep/sweep.hpp"

namespace impactcert::api {

std::string version() { return IMPACTCERT_VERSION; }

Error::Error(int exit_status, const std::string& message) : std::runtime_error(message), exit_status_(exit_status) {}

namespace detail {

impactcert::Rational to_internal(const mpq_class& x) { return impactcert::Rational(x.get_mpq_t()); }

mpq_class to_public(const impactcert::Rational& x) { return mpq_class(x.mpq()); }

impactcert::Vector to_internal(const Vector& v, const std::string& where) {
    impactcert::Vector out;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (mpz_sgn(v[i].get_den_mpz_t()) == 0)
            throw api::InputError(where + "[" + std::to_string(i) + "]: zero denominator");
        mpq_class canonical = v[i];
        canonical.canonicalize();
        out.push_back(to_internal(canonical));
    }
    return out;
}

Vector to_public(const impactcert::Vector& v) {
    Vector out;
    out.reserve(v.size());
    for (const auto& x : v)
        out.push_back(to_public(x));
    return out;
}

void rethrow_as_api() {
    // Every message on one line, as the command line prints it.
    try {
        throw;
    } catch (const impactcert::InputError& e) {
        throw api::InputError(one_line_text(e.what()));
    } catch (const Json::exception& e) {
        throw api::InputError(one_line_text(e.what()));
    } catch (const DeriveLimit& e) {
        throw api::LimitError(one_line_text(std::string("derive: ") + e.what()));
    } catch (const SweepLimit& e) {
        throw api::LimitError(one_line_text(e.what()));
    } catch (const LimitExceeded& e) {
        throw api::LimitError(one_line_text(e.what()));
    }
}

} // namespace detail

using detail::translated;

Rational parse_exact(const std::string& text, const std::string& where) {
    std::string why;
    const auto x = parse_cli_number(text, &why);
    if (!x)
        throw api::InputError(one_line_text(where + ": \"" + text + "\" is not a number" + (why.empty() ? "" : " (" + why + ")")));
    return detail::to_public(*x);
}

// ---- System

System System::chain(const Vector& masses, const std::string& walls) {
    return translated([&] {
        auto impl = std::make_shared<Impl>();
        impl->system = chain_system(detail::to_internal(masses, "masses"), parse_walls(walls));
        make_mechanics(impl->system); // validated: positive masses, at least two balls
        return System(std::move(impl));
    });
}

System System::read(const std::string& path) {
    return translated([&] { return System(std::make_shared<Impl>(Impl{load_system_file(path)})); });
}

System System::parse(const std::string& json_text, const std::string& origin) {
    return translated([&] { return System(std::make_shared<Impl>(Impl{parse_system_text(json_text, origin)})); });
}

std::size_t System::velocities() const { return make_mechanics(impl_->system).balls(); }
std::size_t System::contacts() const { return make_mechanics(impl_->system).normals; }
bool System::friction() const { return make_mechanics(impl_->system).has_friction(); }
std::string System::describe() const { return describe_system(impl_->system); }

// ---- Law

Law Law::read(const std::string& path, const LawLimits& limits) {
    return translated([&] {
        Model model = load_model_file(path, limits.max_pieces, limits.max_memory_mb);
        model.require_independent_columns("the library");
        return Law(std::make_shared<Impl>(Impl{std::move(model)}));
    });
}

Law Law::parse(const std::string& json_text, const std::string& origin, const LawLimits& limits) {
    return translated([&] {
        impactcert::Law law = parse_law_text(json_text, origin, limits.max_pieces, limits.max_memory_mb);
        Model model(std::move(law), limits.max_pieces, limits.max_memory_mb);
        model.require_independent_columns("the library");
        return Law(std::make_shared<Impl>(Impl{std::move(model)}));
    });
}

Law Law::paper() {
    return translated([] { return Law(std::make_shared<Impl>(Impl{Model(paper_law())})); });
}

std::string Law::name() const { return impl_->model.law().name; }
std::size_t Law::contacts() const { return impl_->model.contacts(); }
std::size_t Law::velocities() const { return impl_->model.balls(); }
std::size_t Law::pieces() const { return impl_->model.pieces().size(); }

std::vector<std::string> Law::piece_names() const {
    std::vector<std::string> out;
    for (const auto& p : impl_->model.pieces())
        out.push_back(p.name);
    return out;
}

std::string Law::to_json() const { return law_file_text(impl_->model.law()); }

void Law::write(const std::string& path) const {
    translated([&] { write_file(path, to_json()); });
}

std::vector<Vector> Law::evaluate(const Vector& gamma_minus) const {
    return translated([&] {
        const Model& m = impl_->model;
        if (gamma_minus.size() != m.contacts())
            throw api::InputError("gamma-: expected " + std::to_string(m.contacts()) + " contact velocities, got " +
                                  std::to_string(gamma_minus.size()));
        const impactcert::Vector g = detail::to_internal(gamma_minus, "gamma-");
        const auto values = m.values_at(g);
        if (values.empty())
            throw api::InputError("gamma- = " + to_string(g) + " lies in no cone of law " + m.law().name);
        std::vector<Vector> out;
        for (const auto& v : values)
            out.push_back(detail::to_public(v));
        return out;
    });
}

std::vector<std::string> Law::pieces_at(const Vector& gamma_minus) const {
    return translated([&] {
        const Model& m = impl_->model;
        if (gamma_minus.size() != m.contacts())
            throw api::InputError("gamma-: expected " + std::to_string(m.contacts()) + " contact velocities, got " +
                                  std::to_string(gamma_minus.size()));
        std::vector<std::string> out;
        for (const auto p : m.pieces_containing(detail::to_internal(gamma_minus, "gamma-")))
            out.push_back(m.pieces()[p].name);
        return out;
    });
}

std::string Law::figure_svg() const {
    return translated([&] {
        const Model& m = impl_->model;
        if (m.contacts() <= 3)
            return cones_svg(m);
        return planes_svg(m); // "" where it does not fit
    });
}

Rational Law::energy(const Vector& gamma) const {
    return translated([&] {
        const Model& m = impl_->model;
        if (gamma.size() != m.contacts())
            throw api::InputError("gamma: expected " + std::to_string(m.contacts()) + " contact velocities, got " +
                                  std::to_string(gamma.size()));
        return detail::to_public(m.energy(detail::to_internal(gamma, "gamma")));
    });
}

} // namespace impactcert::api
