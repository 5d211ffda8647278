// SPDX-License-Identifier: GPL-3.0-or-later
#include "report_draw.hpp"

#include "report.hpp"

#include <cmath>
#include <cstdio>

namespace impactcert::draw {

// Okabe & Ito's colour-blind-safe palette (without black and vermillion, kept for the marks);
// grey as an eighth. Counterexamples are black on a white outline.
const char* const kPalette[10] = {"#E69F00", "#56B4E9", "#009E73", "#F0E442", "#0072B2", "#CC79A7", "#999999",
                                "#E69F00", "#56B4E9", "#009E73"};

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

} // namespace impactcert::draw

namespace impactcert {
std::string draw_palette(std::size_t p) { return draw::kPalette[p % 10]; }
} // namespace impactcert
