// SPDX-License-Identifier: GPL-3.0-or-later
#include "report/report_draw.hpp"

#include "report/report.hpp"
#include "model/law_json.hpp"
#include "exact/rational.hpp"
#include "prover/verdict_output.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>

namespace impactcert::draw {

// Okabe & Ito's colour-blind-safe palette (without black and vermillion, kept for the marks);
// grey as a seventh. Counterexamples are black on a white outline.
const char* const kPalette[7] = {"#E69F00", "#56B4E9", "#009E73", "#F0E442", "#0072B2", "#CC79A7", "#999999"};


std::string fmt(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", x);
    return buf;
}


std::string matrix_text(const Matrix& m) {
    std::string s = "[";
    for (std::size_t i = 0; i < m.rows(); ++i) {
        s += i ? ", [" : "[";
        for (std::size_t j = 0; j < m.cols(); ++j)
            s += (j ? ", " : "") + to_string(m(i, j));
        s += "]";
    }
    return s + "]";
}

std::string rays_text(const Piece& p) {
    std::string s;
    for (std::size_t k = 0; k < p.R.cols(); ++k)
        s += (k ? ", " : "") + to_string(p.R.column(k));
    return s;
}

// A non-negative rational as a double for drawing: beyond 2^1000 it is 2^1000, below 2^-1000 zero.
double display_double(const Rational& r) {
    const long bits = static_cast<long>(mpz_sizeinbase(mpq_numref(r.mpq()), 2)) -
                      static_cast<long>(mpz_sizeinbase(mpq_denref(r.mpq()), 2));
    if (sign_of(r) == Sign::zero || bits < -1000)
        return 0;
    if (bits > 1000)
        return std::ldexp(1.0, 1000);
    return mpq_get_d(r.mpq());
}

// The angle of gamma in the metric of the kinetic energy H = G^-1 (in (-pi, pi]): the Euclidean
// angle of L^T gamma, H = L L^T. With H = [[a, b], [b, c]], L^T gamma is proportional to
// (a g1 + b g2, sqrt(det H) g2), so the angle is atan2(sqrt(det H) g2, u), u = a g1 + b g2, taken
// from the exact ratio t = u / g2 as atan2(sign g2, sign(g2 t) sqrt(t^2 / det H)): no overflow at
// any scale. In this metric an elastic impact is a reflection, and the cones of a derived law of a
// heavy and a light ball, squeezed against one line in gamma coordinates, open up.
double h_angle(const Matrix& H, const Vector& g) {
    const double pi = std::acos(-1.0);
    const Rational u = H(0, 0) * g[0] + H(0, 1) * g[1];
    if (sign_of(g[1]) == Sign::zero)
        return sign_of(u) == Sign::negative ? pi : 0.0;
    const Rational det = H(0, 0) * H(1, 1) - H(0, 1) * H(0, 1);
    const Rational t = u / g[1];
    const double s = std::sqrt(display_double(t * t / det));
    const bool g2_positive = sign_of(g[1]) == Sign::positive;
    const bool x_positive = (sign_of(t) == Sign::positive) == g2_positive;
    return std::atan2(g2_positive ? 1.0 : -1.0, sign_of(t) == Sign::zero ? 0.0 : (x_positive ? s : -s));
}

Dir h_direction(const Matrix& H, const Vector& g) {
    const double a = h_angle(H, g);
    return {std::cos(a), std::sin(a)};
}

// Counter-clockwise span from a to b in radians, in [0, 2 pi).
double span(double a, double b) {
    const double two_pi = 2 * std::acos(-1.0);
    double d = b - a;
    while (d < 0)
        d += two_pi;
    while (d >= two_pi)
        d -= two_pi;
    return d;
}

std::string piece_title(const Piece& p) {
    return p.name + ": rays " + rays_text(p) + "; Q = " + matrix_text(p.Q);
}

// A direction in double at any scale: the vector is first multiplied exactly by the power of two
// that brings its largest component near 1 (the binary exponent from the bit lengths of numerator
// and denominator), so no component overflows and the direction is kept (a component below 2^-1074
// of the largest becomes 0). A zero vector gives zeros. (18.8: diag(2^1000, 2^-1000) drew "-nan".)
std::vector<double> scaled_doubles(const Vector& v) {
    long top = LONG_MIN;
    for (const auto& q : v)
        if (sign_of(q) != Sign::zero)
            top = std::max(top, static_cast<long>(mpz_sizeinbase(mpq_numref(q.mpq()), 2)) -
                                    static_cast<long>(mpz_sizeinbase(mpq_denref(q.mpq()), 2)));
    std::vector<double> out;
    for (const auto& q : v) {
        // A fresh number: a copy of q would share q's GMP value (CGAL's Gmpq is a reference-counted
        // handle), and writing into it would change the caller's law (it did: the rays of the
        // Model and, once H was drawn too, H itself, which verify then found non-symmetric).
        Rational r;
        if (top > 0)
            mpq_div_2exp(r.mpq(), q.mpq(), static_cast<mp_bitcnt_t>(top));
        else if (top != LONG_MIN && top < 0)
            mpq_mul_2exp(r.mpq(), q.mpq(), static_cast<mp_bitcnt_t>(-top));
        else
            mpq_set(r.mpq(), q.mpq());
        out.push_back(mpq_get_d(r.mpq())); // |r| < 4 for the largest: finite
    }
    return out;
}


std::vector<Marked> marked_points(const VerifyReport* report, std::size_t c) {
    std::vector<Marked> out;
    if (!report)
        return out;
    auto read = [&](const Json& j) {
        Vector v;
        for (const auto& x : j) {
            std::string why;
            const auto q = parse_rational(x.get<std::string>(), &why);
            v.push_back(q ? *q : Rational(0));
        }
        return v;
    };
    // The points of one mark scaled together (a pair keeps its relative lengths), exactly.
    auto scaled = [](const std::vector<Vector>& pts) {
        Vector all;
        for (const auto& p : pts)
            all.insert(all.end(), p.begin(), p.end());
        const auto d = scaled_doubles(all);
        std::vector<std::vector<double>> parts;
        std::size_t k = 0;
        for (const auto& p : pts) {
            parts.emplace_back(d.begin() + static_cast<std::ptrdiff_t>(k), d.begin() + static_cast<std::ptrdiff_t>(k + p.size()));
            k += p.size();
        }
        return parts;
    };
    for (const auto& o : report->obligations) {
        // Only what the law claims: a property it does not claim is no counterexample to it.
        if (o.verdict != Verdict::refuted || !o.claimed || !o.counterexample.is_object())
            continue;
        const Json& w = o.counterexample;
        Marked m{o.id, {}, {}};
        if (w.contains("gamma_a") && w.contains("gamma_b")) {
            m.exact = {read(w["gamma_a"]), read(w["gamma_b"])};
        } else if (w.contains("gamma") && w["gamma"].is_array()) {
            m.exact = {read(w["gamma"])};
        } else if (w.contains("ray") && w["ray"].is_array()) {
            m.exact = {read(w["ray"])};
        }
        if (!m.exact.empty())
            m.points = scaled(m.exact);
        if (!m.points.empty() && m.points[0].size() == c)
            out.push_back(std::move(m));
    }
    return out;
}

// Counterexample marks at picture coordinates: the points, joined when there are two.
// `labels` counts the labels already written at each (rounded) place: the next one there goes a
// line lower, so that several counterexamples at one point do not overwrite each other's names.
std::string marks_svg(const std::vector<std::pair<double, double>>& shown, const std::string& id,
                      std::map<std::pair<long, long>, int>& labels, double left_beyond) {
    std::string s;
    if (shown.size() == 2)
        s += "<line x1=\"" + fmt(shown[0].first) + "\" y1=\"" + fmt(shown[0].second) + "\" x2=\"" +
             fmt(shown[1].first) + "\" y2=\"" + fmt(shown[1].second) + "\" stroke=\"#000\" stroke-width=\"2\"/>\n";
    for (const auto& [px, py] : shown)
        s += "<circle cx=\"" + fmt(px) + "\" cy=\"" + fmt(py) + "\" r=\"4\" fill=\"#000\" stroke=\"#fff\" class=\"counterexample\"><title>" +
             xml_escape(id + " counterexample") + "</title></circle>\n";
    if (!shown.empty()) {
        int& line = labels[{std::lround(shown[0].first / 4), std::lround(shown[0].second / 4)}];
        const bool left = shown[0].first > left_beyond;
        s += "<text x=\"" + fmt(shown[0].first + (left ? -6 : 6)) + "\" y=\"" + fmt(shown[0].second + 12 + 11 * line) +
             "\"" + (left ? " text-anchor=\"end\"" : "") + " font-size=\"10\" fill=\"#000\" stroke=\"#fff\" "
             "stroke-width=\"2.5\" paint-order=\"stroke\">" + xml_escape(id) + "</text>\n";
        ++line;
    }
    return s;
}

} // namespace impactcert::draw

