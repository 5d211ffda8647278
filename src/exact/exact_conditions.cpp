// SPDX-License-Identifier: GPL-3.0-or-later
// exact_conditions.cpp -- the continuity set of a two-contact sweep, exactly (exact_conditions.hpp).
//
// The only translation unit with CGAL's polynomials and algebraic kernel (slow headers).
#include "exact/exact_conditions.hpp"

#include <CGAL/Algebraic_kernel_d_1.h>
#include <CGAL/Gmpz.h>
#include <CGAL/Polynomial.h>

#include <gmpxx.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace impactcert {

namespace {

using P1 = CGAL::Polynomial<Rational>; // in the first parameter x
using P2 = CGAL::Polynomial<P1>;       // in the second parameter y, coefficients in x
using AK = CGAL::Algebraic_kernel_d_1<CGAL::Gmpz>;
using ZPoly = AK::Polynomial_1;
using Root = AK::Algebraic_real_1;

struct Frac {
    P2 num, den;
};

P2 constant(const Rational& r) { return P2(P1(r)); }

bool is_constant(const P2& p) { return p.degree() == 0 && p[0].degree() == 0; }

Frac reduce(Frac f) {
    const P2 g = CGAL::gcd(f.num, f.den);
    if (!is_constant(g)) {
        f.num = CGAL::integral_division(f.num, g);
        f.den = CGAL::integral_division(f.den, g);
    }
    return f;
}
Frac operator+(const Frac& a, const Frac& b) { return reduce({a.num * b.den + b.num * a.den, a.den * b.den}); }
Frac operator*(const Frac& a, const Frac& b) { return reduce({a.num * b.num, a.den * b.den}); }
Frac operator-(const Frac& a) { return {-a.num, a.den}; }
Frac inverse(const Frac& a) { return {a.den, a.num}; }

Rational evaluate(const P2& p, const Rational& x, const Rational& y) {
    Rational r;
    for (int i = p.degree(); i >= 0; --i)
        r = r * y + p[i].evaluate(x);
    return r;
}
Rational evaluate(const Frac& f, const Rational& x, const Rational& y) {
    return evaluate(f.num, x, y) / evaluate(f.den, x, y);
}

// g on a line: parameter `fixed` at v (0: x = v, a polynomial in y; 1: y = v, in x).
P1 restrict(const P2& p, std::size_t fixed, const Rational& v) {
    if (fixed == 0) {
        std::vector<Rational> c;
        for (int i = 0; i <= p.degree(); ++i)
            c.push_back(p[i].evaluate(v));
        return P1(c.begin(), c.end());
    }
    P1 r;
    for (int i = p.degree(); i >= 0; --i)
        r = r * P1(v) + p[i];
    return r;
}

// A positive multiple with integer coefficients (the same roots and signs).
ZPoly integral(const P1& p) {
    CGAL::Gmpz l(1);
    for (int i = 0; i <= p.degree(); ++i) {
        const CGAL::Gmpz d = p[i].denominator();
        l = l / CGAL::gcd(l, d) * d;
    }
    std::vector<CGAL::Gmpz> c;
    for (int i = 0; i <= p.degree(); ++i)
        c.push_back(p[i].numerator() * (l / p[i].denominator()));
    return ZPoly(c.begin(), c.end());
}

// The simplest rational in [lo, hi] (Stern-Brocot: the continued fractions of the two ends), lo <= hi.
Rational simplest_between(const Rational& lo, const Rational& hi) {
    mpz_class q;
    mpz_fdiv_q(q.get_mpz_t(), mpq_numref(lo.mpq()), mpq_denref(lo.mpq()));
    const Rational fl{CGAL::Gmpz(q.get_mpz_t())};
    if (fl == lo)
        return lo;
    if (fl + Rational(1) <= hi)
        return fl + Rational(1);
    return fl + Rational(1) / simplest_between(Rational(1) / (hi - fl), Rational(1) / (lo - fl));
}

struct Condition {
    P2 poly;
    Sign sign; // required, never zero
};

struct Path {
    std::string word;
    std::vector<std::size_t> letters;
    std::vector<Rational> end; // numeric gamma+ at the sample
};

// The family at a point, symbolically: the two impact matrices' non-trivial entries.
struct Symbolic {
    Frac e[2];     // restitutions
    Frac ratio[2]; // G_lk / G_kk for contact k, l the other
};

class Family {
  public:
    explicit Family(const ConditionFamily& f) : f_(f) {
        auto item = [&](const std::string& text, const char* what) -> Frac {
            for (std::size_t p = 0; p < f.parameters.size(); ++p)
                if (text == f.parameters[p].name)
                    return {p == 0 ? P2(CGAL::shift(P1(1), 1)) : CGAL::shift(P2(1), 1), constant(Rational(1))};
            const auto v = parse_cli_number(text);
            if (!v)
                throw std::invalid_argument(std::string(what) + " item \"" + text + "\"");
            return {constant(*v), constant(Rational(1))};
        };
        if (f.masses.size() != 3)
            throw std::invalid_argument("three balls (two contacts) only");
        Frac inv[3];
        for (std::size_t i = 0; i < 3; ++i)
            inv[i] = inverse(item(f.masses[i], "mass"));
        const Frac G11 = inv[0] + inv[1], G22 = inv[1] + inv[2], G12 = -inv[1];
        s_.ratio[0] = G12 * inverse(G11);
        s_.ratio[1] = G12 * inverse(G22);
        if (f.restitution.size() != 1 && f.restitution.size() != 2)
            throw std::invalid_argument("one restitution or one per contact");
        for (std::size_t k = 0; k < 2; ++k)
            s_.e[k] = item(f.restitution[f.restitution.size() == 1 ? 0 : k], "restitution");
    }

    // The numeric path from the tie forced to `first`, or nothing on a cell wall / beyond the bound.
    std::optional<Path> numeric(std::size_t first, const Rational& x, const Rational& y) const {
        Rational e[2], r[2];
        for (std::size_t k = 0; k < 2; ++k) {
            e[k] = evaluate(s_.e[k], x, y);
            r[k] = evaluate(s_.ratio[k], x, y);
        }
        std::vector<Rational> g{Rational(-1), Rational(-1)};
        Path p;
        std::size_t k = first;
        for (;;) {
            const std::size_t l = 1 - k;
            g[l] = g[l] - (Rational(1) + e[k]) * r[k] * g[k];
            g[k] = -e[k] * g[k];
            p.letters.push_back(k);
            p.word += static_cast<char>('1' + k);
            if (p.letters.size() > f_.max_impacts)
                return std::nullopt;
            const Sign s0 = sign_of(g[0]), s1 = sign_of(g[1]);
            if (s0 == Sign::zero || s1 == Sign::zero)
                return std::nullopt; // a boundary: the parameter point is on a cell wall
            if (s0 == Sign::positive && s1 == Sign::positive)
                break;
            if (s0 == Sign::negative && s1 == Sign::negative) {
                if (g[0] == g[1])
                    return std::nullopt; // a tie
                k = g[0] < g[1] ? 0 : 1;
            } else {
                k = s0 == Sign::negative ? 0 : 1;
            }
        }
        p.end = g;
        return p;
    }

    // The same path symbolically: gamma = N / D, and the cell's conditions (the signs at the sample).
    void symbolic(const Path& path, const Rational& x, const Rational& y, std::vector<P2>& N, P2& D,
                  std::vector<Condition>& cells) const {
        N = {constant(Rational(-1)), constant(Rational(-1))};
        D = constant(Rational(1));
        for (const std::size_t k : path.letters) {
            const std::size_t l = 1 - k;
            const Frac c = (Frac{constant(Rational(1)), constant(Rational(1))} + s_.e[k]) * s_.ratio[k];
            // e has denominator 1 (a number or a parameter).
            const P2 nl = N[l] * c.den - c.num * N[k];
            const P2 nk = -s_.e[k].num * N[k] * c.den;
            N[l] = nl;
            N[k] = nk;
            D = D * c.den;
            const Rational g0 = evaluate(N[0], x, y) / evaluate(D, x, y), g1 = evaluate(N[1], x, y) / evaluate(D, x, y);
            cells.push_back({N[0] * D, sign_of(g0)});
            cells.push_back({N[1] * D, sign_of(g1)});
            if (sign_of(g0) == Sign::negative && sign_of(g1) == Sign::negative)
                cells.push_back({(N[1] - N[0]) * D, sign_of(g1 - g0)});
        }
    }

  private:
    const ConditionFamily& f_;
    Symbolic s_;
};

std::vector<Rational> probes(const ConditionParameter& p, std::size_t subdivisions, std::vector<bool>* on_grid) {
    std::vector<Rational> out;
    for (std::size_t i = 0; i < p.values.size(); ++i) {
        out.push_back(p.values[i]);
        if (on_grid)
            on_grid->push_back(true);
        if (i + 1 == p.values.size())
            break;
        for (std::size_t s = 1; s < subdivisions; ++s) {
            out.push_back(p.values[i] + (p.values[i + 1] - p.values[i]) * Rational(static_cast<long>(s)) /
                                            Rational(static_cast<long>(subdivisions)));
            if (on_grid)
                on_grid->push_back(false);
        }
    }
    return out;
}

// g as a primitive polynomial with integer coefficients, and its terms.
P2 primitive(const P2& g) {
    CGAL::Gmpz l(1);
    for (int i = 0; i <= g.degree(); ++i)
        for (int j = 0; j <= g[i].degree(); ++j) {
            const CGAL::Gmpz d = g[i][j].denominator();
            l = l / CGAL::gcd(l, d) * d;
        }
    CGAL::Gmpz content(0);
    for (int i = 0; i <= g.degree(); ++i)
        for (int j = 0; j <= g[i].degree(); ++j)
            if (!CGAL::is_zero(g[i][j]))
                content = CGAL::gcd(content, g[i][j].numerator() * (l / g[i][j].denominator()));
    return g * constant(Rational(l) / Rational(content));
}

std::vector<PolynomialTerm> terms_of(const P2& g) {
    std::vector<PolynomialTerm> t;
    for (int i = g.degree(); i >= 0; --i)
        for (int j = g[i].degree(); j >= 0; --j)
            if (!CGAL::is_zero(g[i][j]))
                t.push_back({static_cast<std::size_t>(j), static_cast<std::size_t>(i), g[i][j]});
    std::stable_sort(t.begin(), t.end(), [](const PolynomialTerm& a, const PolynomialTerm& b) {
        return a.ex + a.ey != b.ex + b.ey ? a.ex + a.ey > b.ex + b.ey : a.ex > b.ex;
    });
    return t;
}

std::string text_of(const std::vector<PolynomialTerm>& terms, const std::vector<ConditionParameter>& params) {
    std::string s;
    for (const auto& t : terms) {
        const bool negative = sign_of(t.coefficient) == Sign::negative;
        const Rational a = negative ? -t.coefficient : t.coefficient;
        s += s.empty() ? (negative ? "-" : "") : (negative ? " - " : " + ");
        std::string mono;
        auto power = [&](std::size_t p, std::size_t e) {
            if (e == 0 || p >= params.size())
                return;
            mono += (mono.empty() ? "" : "*") + params[p].name + (e > 1 ? "^" + std::to_string(e) : "");
        };
        power(0, t.ex);
        power(1, t.ey);
        if (mono.empty())
            s += to_string(a);
        else
            s += (a == Rational(1) ? "" : to_string(a) + "*") + mono;
    }
    return s.empty() ? "0" : s;
}

} // namespace

Rational evaluate_condition(const ConditionCurve& curve, const std::vector<Rational>& at) {
    Rational v;
    for (const auto& t : curve.terms) {
        Rational m = t.coefficient;
        for (std::size_t i = 0; i < t.ex; ++i)
            m = m * at.at(0);
        for (std::size_t i = 0; i < t.ey; ++i)
            m = m * at.at(1);
        v = v + m;
    }
    return v;
}

std::optional<std::pair<std::string, std::string>> tie_words(const ConditionFamily& family,
                                                             const std::vector<Rational>& at) {
    const Family f(family);
    const Rational x = at.at(0), y = at.size() > 1 ? at[1] : Rational(0);
    const auto a = f.numeric(0, x, y), b = f.numeric(1, x, y);
    if (!a || !b)
        return std::nullopt;
    return std::make_pair(a->word, b->word);
}

ConditionsResult continuity_conditions(const ConditionFamily& family) {
    ConditionsResult result;
    if (family.parameters.empty() || family.parameters.size() > 2) {
        result.why_not = "one or two parameters";
        return result;
    }
    for (const auto& p : family.parameters)
        if (p.values.empty()) {
            result.why_not = "parameter " + p.name + " has no values";
            return result;
        }
    std::optional<Family> f;
    try {
        f.emplace(family);
    } catch (const std::invalid_argument& e) {
        result.why_not = e.what();
        return result;
    }
    const bool two = family.parameters.size() == 2;
    std::vector<bool> grid_x, grid_y;
    // Probe points between grid values, fewer on large grids: at most about 250,000 probes (each
    // runs both continuations), down to the grid points alone.
    std::size_t subdivisions = std::max<std::size_t>(family.subdivisions, 1);
    auto lines = [&](std::size_t sub, const ConditionParameter& p) { return sub * (p.values.size() - 1) + 1; };
    while (subdivisions > 1 && lines(subdivisions, family.parameters[0]) *
                                       (two ? lines(subdivisions, family.parameters[1]) : 1) > 250000)
        --subdivisions;
    result.subdivisions = subdivisions;
    const std::vector<Rational> xs = probes(family.parameters[0], subdivisions, &grid_x);
    const std::vector<Rational> ys = two ? probes(family.parameters[1], subdivisions, &grid_y)
                                         : std::vector<Rational>{Rational(0)};
    if (!two)
        grid_y.push_back(true);

    // Cells, by their two words, each with a sample point.
    std::map<std::pair<std::string, std::string>, std::pair<Rational, Rational>> cells;
    std::map<std::pair<std::string, std::string>, std::vector<std::pair<Rational, Rational>>> members;
    for (const auto& x : xs)
        for (const auto& y : ys) {
            const auto a = f->numeric(0, x, y), b = f->numeric(1, x, y);
            if (!a || !b)
                continue;
            if (!cells.count({a->word, b->word}))
                cells[{a->word, b->word}] = {x, y};
            members[{a->word, b->word}].push_back({x, y});
        }
    result.cells = cells.size();
    AK ak;
    for (const auto& [words, sample] : cells) {
        const auto& [x0, y0] = sample;
        const auto a = f->numeric(0, x0, y0), b = f->numeric(1, x0, y0);
        if (a->letters.size() > family.max_word || b->letters.size() > family.max_word) {
            ++result.cells_not_computed;
            continue;
        }
        std::vector<P2> Na, Nb;
        P2 Da, Db;
        std::vector<Condition> conditions;
        f->symbolic(*a, x0, y0, Na, Da, conditions);
        f->symbolic(*b, x0, y0, Nb, Db, conditions);
        // The sample's numbers and the symbolic path agree (a second route through the algebra).
        for (std::size_t j = 0; j < 2; ++j)
            if (evaluate(Na[j], x0, y0) / evaluate(Da, x0, y0) != a->end[j] ||
                evaluate(Nb[j], x0, y0) / evaluate(Db, x0, y0) != b->end[j])
                throw std::logic_error("exact conditions: the symbolic path disagrees with the numeric one");
        const P2 J0 = Na[0] * Db - Nb[0] * Da, J1 = Na[1] * Db - Nb[1] * Da;
        ConditionCurve curve;
        curve.word_a = words.first;
        curve.word_b = words.second;
        if (CGAL::is_zero(J0) && CGAL::is_zero(J1)) {
            curve.whole_cell = true;
            result.curves.push_back(curve);
            continue;
        }
        const P2 g = primitive(CGAL::is_zero(J0) ? J1 : CGAL::is_zero(J1) ? J0 : CGAL::gcd(J0, J1));
        if (is_constant(g)) {
            // No common curve. Both components may still vanish at isolated points (the 1,1,1
            // chain with two restitutions e, f at (1, 1)); those among the probes are listed.
            bool j0_constant = true, j1_constant = true;
            for (int i = 0; i <= J0.degree(); ++i)
                j0_constant = j0_constant && (i == 0 ? J0[0].degree() == 0 : CGAL::is_zero(J0[i]));
            for (int i = 0; i <= J1.degree(); ++i)
                j1_constant = j1_constant && (i == 0 ? J1[0].degree() == 0 : CGAL::is_zero(J1[i]));
            if (j0_constant || j1_constant)
                continue; // one component is a non-zero constant: J never vanishes in this cell
            curve.isolated = true;
            for (const auto& [px, py] : members[words])
                if (CGAL::is_zero(evaluate(J0, px, py)) && CGAL::is_zero(evaluate(J1, px, py)))
                    curve.points.push_back(two ? std::vector<Rational>{px, py} : std::vector<Rational>{px});
            result.curves.push_back(std::move(curve));
            continue;
        }
        curve.terms = terms_of(g);
        curve.polynomial = text_of(curve.terms, family.parameters);
        for (const auto& t : curve.terms)
            curve.degree = std::max(curve.degree, t.ex + t.ey);
        // Crossings with the lines x = const (roots in y) and, for two parameters, y = const.
        auto scan = [&](std::size_t fixed, const Rational& v, bool grid, const Rational& lo, const Rational& hi) {
            const P1 u = two ? restrict(g, fixed, v) : restrict(g, 1, Rational(0));
            if (two && CGAL::is_zero(u)) {
                // The whole line lies on the curve (g has the factor of the line, e.g. (1 - e^2)):
                // its probe points inside the cell (every condition's sign exact there) are listed.
                const std::vector<Rational>& ts = fixed == 0 ? ys : xs;
                const std::vector<bool>& on_grid = fixed == 0 ? grid_y : grid_x;
                for (std::size_t i = 0; i < ts.size(); ++i) {
                    const Rational px = fixed == 0 ? v : ts[i], py = fixed == 0 ? ts[i] : v;
                    bool inside = true;
                    for (const auto& c : conditions)
                        inside = inside && sign_of(evaluate(c.poly, px, py)) == c.sign;
                    if (!inside)
                        continue;
                    Crossing x;
                    x.varies = 1 - fixed;
                    x.at = v;
                    x.lo = x.hi = ts[i];
                    x.exact = ts[i];
                    x.along = true;
                    x.grid_line = grid && on_grid[i];
                    curve.crossings.push_back(x);
                }
                return;
            }
            if (CGAL::is_zero(u) || u.degree() == 0)
                return;
            std::vector<std::pair<Root, AK::Multiplicity_type>> roots;
            ak.solve_1_object()(integral(u), std::back_inserter(roots));
            for (const auto& [root, multiplicity] : roots) {
                if (ak.compare_1_object()(root, Root(lo)) == CGAL::SMALLER ||
                    ak.compare_1_object()(root, Root(hi)) == CGAL::LARGER)
                    continue;
                bool inside = true;
                for (const auto& c : conditions) {
                    const P1 cu = two ? restrict(c.poly, fixed, v) : restrict(c.poly, 1, Rational(0));
                    const CGAL::Sign s = CGAL::is_zero(cu) ? CGAL::ZERO : ak.sign_at_1_object()(integral(cu), root);
                    if (static_cast<int>(s) != static_cast<int>(c.sign)) {
                        inside = false;
                        break;
                    }
                }
                if (!inside)
                    continue;
                // An enclosure of width 2^-48 that holds no other root of u (refined further if needed).
                auto box = ak.approximate_absolute_1_object()(root, 48);
                for (int bits = 48;; bits *= 2) {
                    bool alone = true;
                    for (const auto& other : roots) {
                        if (ak.compare_1_object()(other.first, root) == CGAL::EQUAL)
                            continue;
                        if (ak.compare_1_object()(other.first, Root(box.first)) != CGAL::SMALLER &&
                            ak.compare_1_object()(other.first, Root(box.second)) != CGAL::LARGER)
                            alone = false;
                    }
                    if (alone)
                        break;
                    if (bits > 4096)
                        throw std::logic_error("exact conditions: a root that no enclosure separates");
                    box = ak.approximate_absolute_1_object()(root, bits * 2);
                }
                Crossing x;
                x.varies = two ? 1 - fixed : 0;
                x.at = two ? v : Rational(0);
                x.lo = box.first;
                x.hi = box.second;
                x.grid_line = grid;
                const Rational r = simplest_between(x.lo, x.hi);
                if (CGAL::is_zero(u.evaluate(r))) {
                    x.exact = r;
                    x.lo = x.hi = r;
                }
                curve.crossings.push_back(x);
            }
        };
        // The range of each parameter (a grid may run either way).
        auto range = [](const std::vector<Rational>& v) {
            return std::make_pair(std::min(v.front(), v.back()), std::max(v.front(), v.back()));
        };
        const auto [x_lo, x_hi] = range(family.parameters[0].values);
        if (!two) {
            scan(1, Rational(0), true, x_lo, x_hi);
        } else {
            const auto [y_lo, y_hi] = range(family.parameters[1].values);
            for (std::size_t i = 0; i < xs.size(); ++i)
                scan(0, xs[i], grid_x[i], y_lo, y_hi);
            for (std::size_t j = 0; j < ys.size(); ++j)
                scan(1, ys[j], grid_y[j], x_lo, x_hi);
        }
        result.curves.push_back(std::move(curve));
    }
    result.computed = true;
    return result;
}

} // namespace impactcert
