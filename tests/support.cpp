// SPDX-License-Identifier: GPL-3.0-or-later
#include "support.hpp"

#include "prover/certificate.hpp"
#include "impactcert_check.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace impactcert::test {

Rational q(const std::string& text) {
    auto r = parse_rational(text);
    if (!r)
        throw std::invalid_argument("bad rational in a test fixture: " + text);
    return *r;
}

Vector vec(std::initializer_list<const char*> xs) {
    Vector v;
    for (const char* x : xs)
        v.push_back(q(x));
    return v;
}

Vector vec_of(const Json& j) {
    Vector v;
    for (const auto& x : j)
        v.push_back(q(x.get<std::string>()));
    return v;
}

std::string source_path(const std::string& relative) {
    return std::string(IMPACTCERT_SOURCE_DIR) + "/" + relative;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

ScratchDir::ScratchDir(const std::string& name)
    : path((std::filesystem::temp_directory_path() / ("impactcert-" + name + "-" + std::to_string(::getpid()))).string()) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
}

ScratchDir::~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
}

Law sorting_law(std::size_t n) {
    Law law;
    law.name = "sort-" + std::to_string(n);
    law.masses = Vector(n, Rational(1));
    const std::size_t c = n - 1;
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    do {
        // order[0] is the slowest ball. Ray k (k = 1..c) is the contact-velocity image of the
        // step velocity that is 1 on the n-k fastest balls and 0 on the others.
        std::vector<Vector> rays;
        for (std::size_t k = 1; k <= c; ++k) {
            Vector u(n, Rational(0));
            for (std::size_t i = k; i < n; ++i)
                u[order[i]] = 1;
            Vector gamma(c);
            for (std::size_t j = 0; j < c; ++j)
                gamma[j] = u[j + 1] - u[j];
            rays.push_back(gamma);
        }
        // Sorting sends step k to the sorted step, whose only non-zero contact velocity is e_k.
        const Matrix Q = *inverse(Matrix::from_columns(rays));
        std::string name;
        for (std::size_t i = 0; i < n; ++i)
            name += (i ? "<=u" : "u") + std::to_string(order[i] + 1);
        law.pieces.push_back(PieceDecl{name, Q, rays});
    } while (std::next_permutation(order.begin(), order.end()));
    return law;
}

namespace {

bool nonneg(const Vector& v) {
    return std::all_of(v.begin(), v.end(), [](const Rational& x) { return sign_of(x) != Sign::negative; });
}

std::size_t piece_named(const Model& m, const Json& j) { return m.piece_index(j.get<std::string>()); }

// A ray of piece p: R^-1 r has exactly one non-zero coordinate, and it is positive.
bool is_ray_of(const Model& m, std::size_t p, const Vector& r) {
    const Vector s = m.pieces()[p].R_inv * r;
    std::size_t positive = 0;
    for (const auto& x : s) {
        if (sign_of(x) == Sign::negative)
            return false;
        positive += sign_of(x) == Sign::positive ? 1 : 0;
    }
    return positive == 1;
}

// A fan witness: a point in no closed cone, or in two interiors. With "via": "fan" (S must be
// a function), a point in no closed cone, or in two interiors whose matrices differ there.
void revalidate_fan(const Model& m, const Json& w, bool needs_two_values) {
    INFO("fan witness " << w.dump());
    const Vector g = vec_of(w["gamma"]);
    std::vector<std::size_t> interiors;
    for (std::size_t p = 0; p < m.pieces().size(); ++p)
        if (m.in_interior(p, g))
            interiors.push_back(p);
    REQUIRE(interiors.size() == w["interior_of"].size());
    for (std::size_t k = 0; k < interiors.size(); ++k)
        REQUIRE(m.pieces()[interiors[k]].name == w["interior_of"][k].get<std::string>());
    if (interiors.empty()) {
        // In no closed cone: check each cone's coordinates directly, by solving R s = gamma.
        for (const auto& piece : m.pieces()) {
            const auto s = solve(piece.R, g);
            REQUIRE(s);
            REQUIRE_FALSE(nonneg(*s));
        }
        return;
    }
    REQUIRE(interiors.size() >= 2);
    if (needs_two_values) {
        bool differ = false;
        for (auto a : interiors)
            for (auto b : interiors)
                differ = differ || m.pieces()[a].Q * g != m.pieces()[b].Q * g;
        REQUIRE(differ);
    }
}

void revalidate_pair(const Model& m, const Json& w) {
    const std::size_t a = piece_named(m, w["piece_a"]), b = piece_named(m, w["piece_b"]);
    const Vector ga = vec_of(w["gamma_a"]), gb = vec_of(w["gamma_b"]);
    INFO("pair witness " << w.dump());
    REQUIRE(m.in_interior(a, ga));
    REQUIRE(m.in_interior(b, gb));
    // Recompute S through the evaluator (single-valued in a cone's interior once fan holds).
    const auto sa = m.values_at(ga), sb = m.values_at(gb);
    REQUIRE(std::find(sa.begin(), sa.end(), m.pieces()[a].Q * ga) != sa.end());
    REQUIRE(std::find(sb.begin(), sb.end(), m.pieces()[b].Q * gb) != sb.end());
    const Rational lhs = m.energy(m.pieces()[a].Q * ga - m.pieces()[b].Q * gb);
    const Rational rhs = m.energy(ga - gb);
    REQUIRE(to_string(lhs) == w["lhs"].get<std::string>());
    REQUIRE(to_string(rhs) == w["rhs"].get<std::string>());
    REQUIRE(lhs > rhs);
}

void revalidate_p1(const Model& m, const Json& w) {
    const std::size_t a = piece_named(m, w["piece_a"]), b = piece_named(m, w["piece_b"]);
    const Vector v = vec_of(w["gamma"]);
    // In both closed cones (coordinates by an independent solve).
    for (auto p : {a, b}) {
        const auto s = solve(m.pieces()[p].R, v);
        REQUIRE(s);
        REQUIRE(nonneg(*s));
    }
    REQUIRE(m.pieces()[a].Q * v == vec_of(w["image_a"]));
    REQUIRE(m.pieces()[b].Q * v == vec_of(w["image_b"]));
    REQUIRE(m.pieces()[a].Q * v != m.pieces()[b].Q * v);
}

} // namespace

void revalidate(const Model& m, const ObligationResult& r) {
    REQUIRE(r.verdict == Verdict::refuted);
    const Json& w = r.counterexample;
    INFO(r.id << " witness " << w.dump());
    REQUIRE(w.is_object());
    const std::string via = w.contains("via") ? w["via"].get<std::string>() : "";
    if (!via.empty()) {
        // Borrowed witnesses only where SPEC section 3 allows them.
        const bool allowed = (via == "fan" && (r.id == "kinematic" || r.id == "nonexpansive" ||
                                               r.id == "nonexpansive-lemma")) ||
                             (via == "P1" && r.id == "nonexpansive-lemma");
        REQUIRE(allowed);
    }
    if (r.id == "fan" || via == "fan") {
        revalidate_fan(m, w, via == "fan");
    } else if (r.id == "P1" || via == "P1") {
        revalidate_p1(m, w);
    } else if (r.id == "nonexpansive" || r.id == "nonexpansive-lemma") {
        revalidate_pair(m, w);
    } else if (r.id == "P2" || r.id == "energetic") {
        const std::size_t p = piece_named(m, w["piece"]);
        const Vector g = vec_of(w["gamma"]);
        const Rational lhs = m.energy(m.pieces()[p].Q * g), rhs = m.energy(g);
        REQUIRE(to_string(lhs) == w["lhs"].get<std::string>());
        REQUIRE(to_string(rhs) == w["rhs"].get<std::string>());
        if (r.id == "P2") {
            REQUIRE(lhs != rhs);
        } else {
            REQUIRE(nonneg(m.pieces()[p].R_inv * g)); // gamma in the closed cone
            REQUIRE(lhs > rhs);
        }
    } else if (r.id == "P3" || r.id == "kinematic" || r.id == "kinetic") {
        const std::size_t p = piece_named(m, w["piece"]);
        const Vector ray = vec_of(w["ray"]);
        REQUIRE(is_ray_of(m, p, ray));
        const Matrix& Q = m.pieces()[p].Q;
        if (r.id == "kinetic") {
            const Vector impulse = m.H() * (Q * ray - ray);
            REQUIRE(impulse == vec_of(w["impulse"]));
            REQUIRE_FALSE(nonneg(impulse));
        } else {
            const Vector img = Q * ray;
            REQUIRE(img == vec_of(w["image"]));
            if (r.id == "kinematic") {
                REQUIRE_FALSE(nonneg(img));
            } else {
                std::size_t nonzero = 0;
                for (const auto& x : img)
                    nonzero += sign_of(x) != Sign::zero ? 1 : 0;
                const bool on_positive_axis = nonzero == 1 && nonneg(img);
                if (on_positive_axis) {
                    // Then another ray of the same piece must reach the same axis.
                    bool clash = false;
                    for (std::size_t k = 0; k < m.contacts(); ++k) {
                        const Vector other = m.pieces()[p].R.column(k);
                        if (primitive_ray(other) != primitive_ray(ray) &&
                            primitive_ray(Q * other) == primitive_ray(img))
                            clash = true;
                    }
                    REQUIRE(clash);
                }
            }
        }
    } else if (r.id == "identities") {
        const auto& decl = m.law().identities.at(w["identity"].get<std::size_t>());
        const Vector e = vec_of(w["gamma"]);
        Vector rhs = e;
        for (auto it = decl.product.rbegin(); it != decl.product.rend(); ++it)
            rhs = m.pieces()[m.piece_index(*it)].Q * rhs;
        const Vector lhs = m.pieces()[m.piece_index(decl.lhs)].Q * e;
        REQUIRE(lhs == vec_of(w["lhs_image"]));
        REQUIRE(rhs == vec_of(w["product_image"]));
        REQUIRE(lhs != rhs);
    } else if (r.id == "single-impacts") {
        // Two-ball impact at contact k with restitution e, from the impact equations directly:
        // gamma+_k = -e gamma-_k with an impulse along W e_k only.
        const std::size_t p = piece_named(m, w["piece"]);
        const std::size_t k = w["contact"].get<std::size_t>() - 1;
        const Rational e = q(w["restitution"].get<std::string>());
        const Vector g = vec_of(w["gamma"]);
        const Rational lambda = -(Rational(1) + e) * g[k] / m.G()(k, k);
        Vector impact = g;
        for (std::size_t i = 0; i < m.contacts(); ++i)
            impact[i] += m.G()(i, k) * lambda;
        REQUIRE(impact == vec_of(w["impact_image"]));
        REQUIRE(m.pieces()[p].Q * g == vec_of(w["piece_image"]));
        REQUIRE(impact != m.pieces()[p].Q * g);
    } else if (r.id == "outcomes") {
        const Vector u = vec_of(w["u_minus"]);
        const Vector gamma = m.contact_velocities(u);
        if (w.contains("piece")) {
            const std::size_t p = piece_named(m, w["piece"]);
            const auto containing = m.pieces_containing(gamma);
            REQUIRE(std::find(containing.begin(), containing.end(), p) != containing.end());
            const Vector u_plus = m.post_impact_velocities(u, gamma, m.pieces()[p].Q * gamma);
            REQUIRE(u_plus == vec_of(w["u_plus"]));
            REQUIRE(u_plus != vec_of(w["u_plus_declared"]));
        } else {
            REQUIRE(m.pieces_containing(gamma).empty());
        }
    } else if (r.id == "symmetries") {
        // By the declaration, not by the prover's tables: find the symmetry by name.
        const SymmetryDecl* sym = nullptr;
        for (const auto& d : m.law().symmetries)
            if (d.name == w["symmetry"].get<std::string>())
                sym = &d;
        REQUIRE(sym != nullptr);
        if (w.contains("matrix")) {
            // |M x|_H != |x|_H: M is no H-isometry.
            const Matrix& M = w["matrix"] == "P" ? sym->P : sym->P_prime;
            const Vector x = vec_of(w["gamma"]);
            REQUIRE(m.energy(M * x) != m.energy(x));
            REQUIRE(to_string(m.energy(M * x)) == w["lhs"].get<std::string>());
            REQUIRE(to_string(m.energy(x)) == w["rhs"].get<std::string>());
        } else if (w.contains("image_rays")) {
            // P C_p is no cone of the law: no piece has these rays (as a set of directions).
            const std::size_t p = piece_named(m, w["piece"]);
            std::vector<Vector> image;
            for (std::size_t k = 0; k < m.contacts(); ++k)
                image.push_back(primitive_ray(sym->P * m.pieces()[p].R.column(k)));
            std::vector<Vector> listed;
            for (const auto& v : w["image_rays"])
                listed.push_back(vec_of(v));
            REQUIRE(listed == image);
            std::sort(image.begin(), image.end());
            for (const auto& piece : m.pieces()) {
                std::vector<Vector> rays;
                for (std::size_t k = 0; k < m.contacts(); ++k)
                    rays.push_back(piece.R.column(k));
                std::sort(rays.begin(), rays.end());
                REQUIRE(rays != image);
            }
        } else {
            // A ray r of C_p with Q_q P r != P' Q_p r, q the piece whose cone is P C_p.
            const std::size_t p = piece_named(m, w["piece"]), q = piece_named(m, w["image_piece"]);
            const Vector ray = vec_of(w["gamma"]);
            REQUIRE(is_ray_of(m, p, ray));
            for (std::size_t k = 0; k < m.contacts(); ++k)
                REQUIRE(is_ray_of(m, q, sym->P * m.pieces()[p].R.column(k)));
            const Vector lhs = m.pieces()[q].Q * (sym->P * ray), rhs = sym->P_prime * (m.pieces()[p].Q * ray);
            REQUIRE(lhs == vec_of(w["lhs"]));
            REQUIRE(rhs == vec_of(w["rhs"]));
            REQUIRE(lhs != rhs);
        }
    } else {
        FAIL("no re-validation for obligation " << r.id);
    }
}

void require_sound(const Model& m, const VerifyReport& r) {
    for (const auto& o : r.obligations)
        if (o.verdict == Verdict::refuted)
            revalidate(m, o);
    const auto outcome = impactcert_check::check_text(make_certificate(m, r).dump());
    INFO(outcome.message);
    REQUIRE(outcome.status == impactcert_check::kVerified);
}

CliRun run_cli(const std::string& args, const std::string& stdin_text) { return run_program(IMPACTCERT_CLI, args, stdin_text); }

CliRun run_replay(const std::string& replay) {
    INFO("replay: " << replay);
    REQUIRE(replay.rfind("cd ", 0) == 0);
    REQUIRE(replay.find(" && " + std::string(IMPACTCERT_CLI) + " eval ") != std::string::npos);
    std::string quoted = "'";
    for (char ch : "cd / && " + replay)
        quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return run_program("/bin/sh", "-c " + quoted + "'");
}

CliRun run_program(const std::string& program, const std::string& args, const std::string& stdin_text) {
    char in_name[] = "/tmp/impactcert-test-in-XXXXXX";
    char err_name[] = "/tmp/impactcert-test-err-XXXXXX";
    const int in_fd = mkstemp(in_name), err_fd = mkstemp(err_name);
    REQUIRE(in_fd >= 0);
    REQUIRE(err_fd >= 0);
    REQUIRE(write(in_fd, stdin_text.data(), stdin_text.size()) == static_cast<ssize_t>(stdin_text.size()));
    close(in_fd);
    close(err_fd);
    const std::string cmd = "'" + program + "' " + args + " <" + in_name + " 2>" + err_name;
    CliRun run;
    FILE* pipe = popen(cmd.c_str(), "r");
    REQUIRE(pipe != nullptr);
    char buf[4096];
    std::size_t got;
    while ((got = fread(buf, 1, sizeof buf, pipe)) > 0)
        run.out.append(buf, got);
    const int status = pclose(pipe);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.err = read_file(err_name);
    unlink(in_name);
    unlink(err_name);
    return run;
}

impactcert_check::Outcome check_certificate(const Json& cert) { return impactcert_check::check_text(cert.dump()); }

} // namespace impactcert::test
