// SPDX-License-Identifier: GPL-3.0-or-later
#include "sweep/threshold.hpp"

#include "sweep/sweep_point.hpp"

#include "exact/matrix.hpp"
#include "exact/upoly.hpp"
#include "model/law.hpp"
#include "prover/obligations.hpp"
#include "prover/worst_case.hpp"

#include <gmpxx.h>

#include <optional>
#include <string>
#include <vector>

namespace impactcert {

namespace {

using sweep_detail::law_at;
using sweep_detail::PointLaw;

mpz_class num_of(const Rational& x) { return mpz_class(mpq_numref(x.mpq())); }
mpz_class den_of(const Rational& x) { return mpz_class(mpq_denref(x.mpq())); }
Rational make_rational(const mpz_class& n, const mpz_class& d) {
    mpq_class q(n, d);
    q.canonicalize();
    return Rational(q.get_mpq_t());
}

// The decimal with the fewest digits within an eighth of the width of the middle of (lo, hi):
// the least j with (hi - lo) 10^j >= 4, then the middle rounded to j decimals.
Rational nice_middle(const Rational& lo, const Rational& hi) {
    const Rational width = hi - lo, mid = (lo + hi) / Rational(2);
    mpz_class scale = 1;
    while (width * Rational(CGAL::Gmpz(scale.get_mpz_t())) < Rational(4))
        scale *= 10;
    const Rational scaled = mid * Rational(CGAL::Gmpz(scale.get_mpz_t())) + Rational(1, 2);
    mpz_class k;
    mpz_fdiv_q(k.get_mpz_t(), mpq_numref(scaled.mpq()), mpq_denref(scaled.mpq()));
    return make_rational(k, scale);
}

Rational ten_to_minus(std::size_t digits) {
    mpz_class scale = 1;
    for (std::size_t i = 0; i < digits; ++i)
        scale *= 10;
    return make_rational(1, scale);
}

// A column's answer at one value of the parameter: the derivation's status ("derive"), or the
// obligation's verdict, or "no law (STATUS)".
std::string answer_at(const SweepSpec& spec, const std::string& column, const Rational& value) {
    const PointLaw d = law_at(spec, {value});
    if (column == "derive")
        return d.derive == "ok" ? "law" : d.derive;
    if (d.derive != "ok")
        return "no law (" + d.derive + ")";
    const Model model(*d.law);
    const VerifyReport r = verify(model, spec.limits);
    return to_string(r.at(column).verdict);
}

std::string answer_of(const Json& result, const std::string& column) {
    const std::string derive = result["derive"].get<std::string>();
    if (column == "derive")
        return derive == "ok" ? "law" : derive;
    if (derive != "ok")
        return "no law (" + derive + ")";
    return result["obligations"][column]["verdict"].get<std::string>();
}

// The energy balance of face J of a piece: det(P_JJ - N_JJ) / det(-N_JJ).
std::optional<Rational> face_balance(const Model& model, const std::string& piece, const std::vector<std::size_t>& face) {
    std::size_t index = 0;
    try {
        index = model.piece_index(piece);
    } catch (const std::out_of_range&) {
        return std::nullopt;
    }
    const Piece& p = model.pieces()[index];
    const std::size_t c = model.contacts(), k = face.size();
    Matrix RJ(c, k);
    for (std::size_t j = 0; j < k; ++j) {
        if (face[j] >= c)
            return std::nullopt;
        for (std::size_t i = 0; i < c; ++i)
            RJ(i, j) = p.R(i, face[j]);
    }
    const Matrix QR = p.Q * RJ;
    const Matrix P = transpose(QR) * model.H() * QR, N = transpose(RJ) * model.H() * RJ;
    const Rational below = determinant(Rational(-1) * N);
    if (sign_of(below) == Sign::zero)
        return std::nullopt;
    return determinant(P - N) / below;
}

UPoly poly_of(const Vector& coefficients) { return make_poly(coefficients); }

// Integer coefficients without a common factor, leading coefficient positive.
UPoly integer_primitive(const UPoly& p) {
    mpz_class l = 1, g = 0;
    for (const auto& x : p.c)
        mpz_lcm(l.get_mpz_t(), l.get_mpz_t(), den_of(x).get_mpz_t());
    std::vector<mpz_class> ints;
    for (const auto& x : p.c) {
        ints.push_back(num_of(x) * (l / den_of(x)));
        mpz_gcd(g.get_mpz_t(), g.get_mpz_t(), ints.back().get_mpz_t());
    }
    if (g < 0)
        g = -g;
    if (ints.back() < 0)
        g = -g;
    std::vector<Rational> out;
    for (const auto& z : ints)
        out.push_back(make_rational(z / g, 1));
    return make_poly(out);
}

std::string poly_text(const UPoly& p, const std::string& x) {
    std::string s;
    for (int d = p.degree(); d >= 0; --d) {
        const Rational& a = p.c[static_cast<std::size_t>(d)];
        if (sign_of(a) == Sign::zero)
            continue;
        const bool negative = sign_of(a) == Sign::negative;
        const Rational m = abs_of(a);
        std::string term = d == 0 || m != Rational(1) ? to_string(m) : "";
        if (d > 0)
            term += (term.empty() ? "" : " ") + x + (d > 1 ? "^" + std::to_string(d) : "");
        if (s.empty())
            s = (negative ? "-" : "") + term;
        else
            s += (negative ? " - " : " + ") + term;
    }
    return s.empty() ? "0" : s;
}

// N / D of degrees at most (k, k) through the first 2k + 1 samples, equal to every sample;
// the least such k up to (samples - 3) / 2.
std::optional<std::pair<UPoly, UPoly>> interpolate(const std::vector<Rational>& xs, const std::vector<Rational>& ys) {
    for (std::size_t k = 0; 2 * k + 3 <= xs.size(); ++k) {
        std::vector<Vector> rows;
        for (std::size_t i = 0; i < 2 * k + 1; ++i) {
            Vector row(2 * k + 2);
            Rational power(1);
            for (std::size_t j = 0; j <= k; ++j) {
                row[j] = power;
                row[k + 1 + j] = Rational(-1) * ys[i] * power;
                power = power * xs[i];
            }
            rows.push_back(row);
        }
        for (const Vector& v : null_space(rows, 2 * k + 2)) {
            const UPoly N = poly_of(Vector(v.begin(), v.begin() + static_cast<long>(k + 1)));
            const UPoly D = poly_of(Vector(v.begin() + static_cast<long>(k + 1), v.end()));
            if (D.zero())
                continue;
            bool all = true;
            for (std::size_t i = 0; i < xs.size() && all; ++i) {
                const Rational d = evaluate(D, xs[i]);
                all = sign_of(d) != Sign::zero && evaluate(N, xs[i]) == ys[i] * d;
            }
            if (all)
                return std::make_pair(N, D);
        }
    }
    return std::nullopt;
}

// The polynomial of an energetic threshold in [lo, hi] whose refuted end is `refuted_at`.
Json energetic_polynomial(const SweepSpec& spec, const Rational& lo, const Rational& hi, const Rational& refuted_at) {
    const std::string& name = spec.parameters[0].name;
    const PointLaw at = law_at(spec, {refuted_at});
    if (at.derive != "ok")
        return Json{{"why_not", "no law at the refuted end"}};
    const Model model(*at.law);
    const LawBound bound = energy_supremum(model, WorstCaseOptions{spec.limits.max_faces, true});
    if (!bound.decided)
        return Json{{"why_not", "the worst case at the refuted end is undecided: " + bound.limit}};
    const PieceBound& top = bound.pieces[bound.top];
    const std::string piece = model.pieces()[top.piece].name;
    std::vector<Rational> xs, ys;
    for (std::size_t i = 0; i < kThresholdSamples; ++i) {
        const Rational x = lo + (hi - lo) * Rational(static_cast<long>(i), static_cast<long>(kThresholdSamples - 1));
        const PointLaw d = law_at(spec, {x});
        if (d.derive != "ok")
            return Json{{"why_not", "no law at " + name + " = " + to_string(x)}};
        // The face where this law's worst case on the piece lies (the rays' order in a derived
        // piece is not tied to the parameter: the face is found again at each sample).
        const Model sample(*d.law);
        std::size_t index = 0;
        try {
            index = sample.piece_index(piece);
        } catch (const std::out_of_range&) {
            return Json{{"why_not", "piece " + piece + " is not in the law at " + name + " = " + to_string(x)}};
        }
        const LawBound b = energy_supremum(sample, WorstCaseOptions{spec.limits.max_faces, true});
        std::optional<Rational> y;
        if (b.decided)
            for (const auto& pb : b.pieces)
                if (pb.piece == index && pb.face.size() == top.face.size())
                    y = face_balance(sample, piece, pb.face);
        if (!y)
            return Json{{"why_not", "piece " + piece + " changes its form in the enclosure"}};
        xs.push_back(x);
        ys.push_back(*y);
    }
    Json out{{"piece", piece}, {"face", top.face}, {"samples", kThresholdSamples}};
    const auto fit = interpolate(xs, ys);
    if (!fit) {
        out["why_not"] = "the face's energy balance is no rational function of degree below " +
                         std::to_string((kThresholdSamples - 1) / 2) + " in " + name;
        return out;
    }
    if (fit->first.zero()) {
        out["why_not"] = "the face's energy balance is 0 throughout the enclosure";
        return out;
    }
    UPoly N = integer_primitive(fit->first);
    const UPoly D = integer_primitive(fit->second);
    out["degrees"] = Json::array({N.degree(), D.degree()});
    if (const std::size_t roots = count_roots(N, lo, hi); roots != 1) {
        out["why_not"] = "the energy balance's numerator has " + std::to_string(roots) + " roots in the enclosure, not one";
        return out;
    }
    // A rational root (a linear factor q x - p of N) is given exactly, with that factor.
    if (const auto r = rational_root(N, RootInterval{lo, hi}, 256)) {
        out["polynomial"] = poly_text(integer_primitive(make_poly({Rational(-1) * *r, Rational(1)})), name);
        out["root"] = to_string(*r);
        return out;
    }
    out["polynomial"] = poly_text(N, name);
    RootInterval root{lo, hi};
    if (sign_of(evaluate(N, lo)) == Sign::zero)
        root.hi = lo;
    else if (sign_of(evaluate(N, hi)) == Sign::zero)
        root.lo = hi;
    else
        root = refine(N, root, ten_to_minus(20)); // the only root of [lo, hi] stays inside
    if (root.lo == root.hi) {
        out["root"] = to_string(root.lo);
    } else {
        out["root_in"] = Json::array({to_string(root.lo), to_string(root.hi)});
        out["root_approx"] = readable_text(root.lo, 17);
    }
    return out;
}

} // namespace

Json find_thresholds(const SweepSpec& spec, const std::vector<Json>& results,
                     const std::function<void(const std::string&)>& progress) {
    Json out = Json::array();
    if (spec.parameters.size() != 1)
        return out;
    const SweepParameter& param = spec.parameters[0];
    const Rational width = ten_to_minus(spec.threshold_digits);
    std::vector<std::string> columns{"derive"};
    for (const char* id : obligation_ids(sweep_friction(spec)))
        columns.push_back(id);
    for (std::size_t i = 0; i + 1 < results.size(); ++i)
        for (const auto& column : columns) {
            const std::string a = answer_of(results[i], column), b = answer_of(results[i + 1], column);
            const bool change = column == "derive" ? (a == "law") != (b == "law") && a != "undecided" && b != "undecided"
                                                   : (a == "proved" && b == "refuted") || (a == "refuted" && b == "proved");
            if (!change)
                continue;
            if (progress)
                progress(column + " between " + param.name + " = " + to_string(param.values[i]) + " and " +
                         to_string(param.values[i + 1]));
            // The interval from its smaller end (a grid may run downwards): a is the answer at lo.
            Rational lo = param.values[i], hi = param.values[i + 1];
            std::string a_lo = a, b_hi = b;
            if (hi < lo) {
                std::swap(lo, hi);
                std::swap(a_lo, b_hi);
            }
            Json entry{{"column", column}, {"between", Json::array({to_string(lo), to_string(hi)})}};
            std::string stopped;
            std::size_t steps = 0;
            while (hi - lo > width) {
                const Rational mid = nice_middle(lo, hi);
                const std::string s = answer_at(spec, column, mid);
                ++steps;
                if (s == a_lo) {
                    lo = mid;
                } else if (s == b_hi) {
                    hi = mid;
                } else {
                    stopped = param.name + " = " + to_string(mid) + " gives " + s;
                    break;
                }
            }
            entry["in"] = Json::array({to_string(lo), to_string(hi)});
            entry["approx"] = readable_text(lo, 12);
            entry["below"] = a_lo;
            entry["above"] = b_hi;
            entry["bisection_steps"] = steps;
            if (!stopped.empty()) {
                entry["stopped"] = stopped;
            } else if (column == "energetic") {
                entry["boundary"] = energetic_polynomial(spec, lo, hi, a_lo == "refuted" ? lo : hi);
            }
            out.push_back(entry);
        }
    return out;
}

} // namespace impactcert
