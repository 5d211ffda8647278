// SPDX-License-Identifier: GPL-3.0-or-later
// report_planes.cpp -- the law along the unit circle of the metric H: for c = 2 the circle and
// its image under S; for c >= 3 small multiples, one per plane of two contacts.
#include "report/report.hpp"

#include "exact/rational.hpp"
#include "report/report_draw.hpp"
#include "prover/verdict_output.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <cmath>

namespace impactcert {
namespace {

using namespace draw;

constexpr double kPi = 3.14159265358979323846;

// g^T H g for the 2 x 2 metric of a plane (Model::energy is the law's own H).
Rational quadratic(const Matrix& H, const Vector& g) {
    Rational s(0);
    for (std::size_t i = 0; i < g.size(); ++i)
        for (std::size_t j = 0; j < g.size(); ++j)
            if (sign_of(g[i]) != Sign::zero && sign_of(g[j]) != Sign::zero)
                s += g[i] * H(i, j) * g[j];
    return s;
}

// |S(g)|_H / |g|_H for g in the piece's cone (exact ratio, shown as a double).
double norm_ratio(const Model& model, const Piece& piece, const Vector& g) {
    return std::sqrt(display_double(model.energy(piece.Q * g) / model.energy(g)));
}

std::string point(double cx, double cy, double r, double angle) {
    return fmt(cx + r * std::cos(angle)) + "," + fmt(cy - r * std::sin(angle));
}

// An annular sector from angle a counter-clockwise by d (< 2 pi), radii r0 < r1.
std::string ring_path(double cx, double cy, double r0, double r1, double a, double d) {
    const std::string large = d > kPi ? "1" : "0";
    return "M" + point(cx, cy, r1, a) + " A" + fmt(r1) + "," + fmt(r1) + " 0 " + large + " 0 " + point(cx, cy, r1, a + d) +
           " L" + point(cx, cy, r0, a + d) + " A" + fmt(r0) + "," + fmt(r0) + " 0 " + large + " 1 " + point(cx, cy, r0, a) + " Z";
}

Rational cross(const Vector& u, const Vector& v) { return u[0] * v[1] - u[1] * v[0]; }

// The cone of `piece` met by the plane of contacts i and j (other components 0), as its two
// extreme directions (x, y) counter-clockwise, exact; none when it meets the plane in a ray or
// not at all. The cone is {g : R^-1 g >= 0}; in the plane row k reads a_k x + b_k y >= 0, and
// the extreme directions are among the lines a_k x + b_k y = 0.
std::optional<std::pair<Vector, Vector>> plane_sector(const Piece& piece, std::size_t i, std::size_t j) {
    const std::size_t c = piece.R_inv.rows();
    std::vector<Vector> feasible;
    for (std::size_t k = 0; k < c; ++k) {
        const Rational& a = piece.R_inv(k, i);
        const Rational& b = piece.R_inv(k, j);
        if (sign_of(a) == Sign::zero && sign_of(b) == Sign::zero)
            continue;
        for (int s = 0; s < 2; ++s) {
            Vector u = s == 0 ? Vector{-b, a} : Vector{b, -a};
            bool inside = true;
            for (std::size_t m = 0; m < c && inside; ++m)
                inside = sign_of(piece.R_inv(m, i) * u[0] + piece.R_inv(m, j) * u[1]) != Sign::negative;
            if (inside)
                feasible.push_back(std::move(u));
        }
    }
    // The cone is pointed: its directions in the plane span less than pi, so the first extreme
    // has every other direction counter-clockwise from it, the last every other clockwise.
    const Vector* first = nullptr;
    const Vector* last = nullptr;
    for (const auto& u : feasible) {
        bool is_first = true, is_last = true;
        for (const auto& w : feasible) {
            const Sign s = sign_of(cross(u, w));
            is_first = is_first && s != Sign::negative;
            is_last = is_last && s != Sign::positive;
        }
        if (is_first && !first)
            first = &u;
        if (is_last && !last)
            last = &u;
    }
    if (!first || !last || sign_of(cross(*first, *last)) != Sign::positive)
        return std::nullopt;
    return std::make_pair(*first, *last);
}

Matrix block(const Matrix& H, std::size_t i, std::size_t j) {
    Matrix B(2, 2);
    B(0, 0) = H(i, i);
    B(0, 1) = H(i, j);
    B(1, 0) = H(j, i);
    B(1, 1) = H(j, j);
    return B;
}

Vector embed(const Vector& xy, std::size_t c, std::size_t i, std::size_t j) {
    Vector g(c, Rational(0));
    g[i] = xy[0];
    g[j] = xy[1];
    return g;
}

// Directions from u to v (counter-clockwise, spanning alpha < pi in the metric H2 of the plane),
// evenly spaced in that angle: g = p u + q v with p = sin(alpha (1 - s)) |v|_H2 / |u|_H2 and
// q = sin(alpha s) (the rotation of u' = u / |u| towards v' = v / |v|, scaled by |v|), s = k / m,
// with m from alpha (`per_turn` points per full turn, 2 to 64 per cone). p and q are doubles made
// exact rationals, so every g is a point of the cone and its ratio is computed exactly; only the
// spacing is approximate. (Equal steps of t in (1 - t) u + t v crowd next to the longer ray: a
// cone between (1000, 1) and (0, 1) was drawn as one chord, hiding a gain of 36/25.)
// A cone narrower than the doubles can tell (alpha 0 after rounding) is drawn by its two rays.
std::vector<Vector> arc_samples(const Matrix& H2, const Vector& u, const Vector& v, double alpha, int per_turn) {
    if (!(alpha > 0 && alpha < kPi))
        return {u, v};
    const int m = static_cast<int>(std::clamp(std::ceil(alpha / (2 * kPi) * per_turn), 2.0, 64.0));
    const double w = std::sqrt(display_double(quadratic(H2, v) / quadratic(H2, u)));
    std::vector<Vector> out = {u};
    for (int k = 1; k < m; ++k) {
        const double t = static_cast<double>(k) / m;
        const double dp = std::sin(alpha * (1 - t)) * w, dq = std::sin(alpha * t);
        if (!(dp >= 0 && dq >= 0 && dp + dq > 0))
            continue; // (rounding) not a point of the cone: left out
        const Rational p(dp), q(dq);
        out.push_back({p * u[0] + q * v[0], p * u[1] + q * v[1]});
    }
    out.push_back(v);
    return out;
}

// The drawn span of a sector whose rays are exactly counter-clockwise within pi: the angles are
// doubles, and two rays closer than their rounding could come out in the wrong order (a span
// near 2 pi); that is a span of 0.
double sector_span(double a, double b) {
    const double d = span(a, b);
    return d < kPi ? d : 0;
}

struct Sector {
    std::size_t piece;
    Vector u, v;       // exact extreme directions in the plane
    double a = 0, d = 0; // drawn: start angle and counter-clockwise span
    std::vector<std::size_t> also; // other pieces meeting the plane in exactly this sector
};

} // namespace

std::string unit_circle_svg(const Model& model) {
    if (model.contacts() != 2 || model.pieces().empty())
        return "";
    const auto& pieces = model.pieces();
    const auto colours = piece_colours(model);
    const Matrix& H = model.H();
    struct Samples {
        std::vector<std::pair<double, double>> image; // angle of S(g), |S(g)|_H / |g|_H
        std::vector<std::pair<double, double>> ratio; // angle of g, the same ratio
    };
    std::vector<Sector> sectors;
    std::vector<Samples> curves;
    double top = 1;
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        Vector u = pieces[p].R.column(0), v = pieces[p].R.column(1);
        if (sign_of(cross(u, v)) == Sign::negative)
            std::swap(u, v);
        Sector sec{p, u, v, h_angle(H, u), 0, {}};
        sec.d = sector_span(sec.a, h_angle(H, v));
        sectors.push_back(sec);
        Samples curve;
        for (const auto& g : arc_samples(H, u, v, sec.d, 360)) {
            const double r = norm_ratio(model, pieces[p], g);
            top = std::max(top, r);
            curve.image.push_back({h_angle(H, pieces[p].Q * g), r});
            curve.ratio.push_back({h_angle(H, g), r});
        }
        curves.push_back(std::move(curve));
    }
    const double size = 420, R = 140 / top;
    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(2 * size) + "\" height=\"" + fmt(size) +
                    "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    for (int panel = 0; panel < 2; ++panel) {
        const double cx = size / 2 + panel * size, cy = size / 2 + 8;
        s += "<text x=\"" + fmt(cx) + "\" y=\"14\" text-anchor=\"middle\" font-weight=\"bold\">" +
             std::string(panel == 0 ? "S(&#947;&#8315;) for &#947;&#8315; on the unit circle"
                                    : "&#8214;S(&#947;&#8315;)&#8214;_H / &#8214;&#947;&#8315;&#8214;_H in the direction of &#947;&#8315;") +
             "</text>\n";
        // The cones, lightly, out to the panel's edge.
        for (const auto& sec : sectors)
            s += "<path d=\"" + ring_path(cx, cy, 0.001, 185, sec.a, std::max(sec.d, 1e-6)) + "\" fill=\"" +
                 colours[sec.piece] + "\" fill-opacity=\"0.22\" stroke=\"#ffffff\" stroke-width=\"0.6\"><title>" +
                 xml_escape(piece_title(pieces[sec.piece])) + "</title></path>\n";
        // The axes of gamma1 and gamma2, drawn in the metric H.
        const std::vector<std::pair<Vector, std::string>> axes = {{{Rational(1), Rational(0)}, "+&#947;1"},
                                                                  {{Rational(0), Rational(1)}, "+&#947;2"},
                                                                  {{Rational(-1), Rational(0)}, "-&#947;1"},
                                                                  {{Rational(0), Rational(-1)}, "-&#947;2"}};
        for (const auto& [g, label] : axes) {
            const double a = h_angle(H, g);
            s += "<line x1=\"" + fmt(cx) + "\" y1=\"" + fmt(cy) + "\" x2=\"" + fmt(cx + 188 * std::cos(a)) + "\" y2=\"" +
                 fmt(cy - 188 * std::sin(a)) + "\" stroke=\"#777777\" stroke-width=\"0.7\"/><text x=\"" +
                 fmt(cx + 165 * std::cos(a) + 3) + "\" y=\"" + fmt(cy - 165 * std::sin(a) - 3) + "\" fill=\"#333333\">" + label +
                 "</text>\n";
        }
        s += "<circle cx=\"" + fmt(cx) + "\" cy=\"" + fmt(cy) + "\" r=\"" + fmt(R) +
             "\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1.2\" stroke-dasharray=\"5,4\"/>\n";
        // The curves: a black underlay, then the cone's colour (seen on any fill).
        for (std::size_t k = 0; k < curves.size(); ++k) {
            std::string pts;
            for (const auto& [a, r] : panel == 0 ? curves[k].image : curves[k].ratio)
                pts += point(cx, cy, R * r, a) + " ";
            s += "<g class=\"" + std::string(panel == 0 ? "image-curve" : "ratio-curve") + "\"><title>" +
                 xml_escape(pieces[k].name) + "</title><polyline points=\"" + pts +
                 "\" fill=\"none\" stroke=\"#000000\" stroke-width=\"3.6\" stroke-linejoin=\"round\"/><polyline points=\"" + pts +
                 "\" fill=\"none\" stroke=\"" + colours[k] + "\" stroke-width=\"2\" stroke-linejoin=\"round\"/></g>\n";
        }
        // Names at the middle of each cone wide enough for them.
        for (const auto& sec : sectors) {
            const std::string& name = pieces[sec.piece].name;
            const double mid = sec.a + sec.d / 2;
            if (sec.d * 70 < 7.0 * static_cast<double>(name.size()))
                continue;
            s += "<text x=\"" + fmt(cx + 70 * std::cos(mid)) + "\" y=\"" + fmt(cy - 70 * std::sin(mid) + 4) +
                 "\" text-anchor=\"middle\" fill=\"#000000\" stroke=\"#ffffff\" stroke-width=\"2.5\" paint-order=\"stroke\" "
                 "class=\"cone-label\">" + xml_escape(name) + "</text>\n";
        }
    }
    return s + "</svg>\n";
}

bool planes_svg_fits(const Model& model, std::string* why_not) {
    const std::size_t c = model.contacts(), P = model.pieces().size();
    std::string reason;
    if (c < 3)
        reason = "the plane view is for three or more contacts";
    else if (c > 10)
        reason = std::to_string(c) + " contacts make " + std::to_string(c * (c - 1) / 2) +
                 " planes of two contacts; the plane view draws up to 10 contacts (45 panels)";
    else if (static_cast<double>(P) * static_cast<double>(c * (c - 1) / 2) * static_cast<double>(2 * c * c) > 2e7)
        reason = std::to_string(P) + " cones in " + std::to_string(c * (c - 1) / 2) +
                 " planes of two contacts are beyond the plane view's budget (2 * 10^7 sign tests)";
    if (why_not)
        *why_not = reason;
    return reason.empty();
}

std::string planes_svg(const Model& model, std::string* why_not) {
    if (!planes_svg_fits(model, why_not))
        return "";
    const std::size_t c = model.contacts(), P = model.pieces().size();
    const std::size_t planes = c * (c - 1) / 2;
    const auto& pieces = model.pieces();
    const auto colours = piece_colours(model);
    const int per_row = static_cast<int>(std::min<std::size_t>(planes, c <= 4 ? 3 : 5));
    const double cell = 200, radius = 58;
    struct Panel {
        std::size_t i, j;
        std::vector<Sector> sectors;
        std::vector<std::vector<std::pair<double, double>>> curves;
    };
    std::vector<Panel> panels;
    double top = 1;
    for (std::size_t i = 0; i < c; ++i)
        for (std::size_t j = i + 1; j < c; ++j) {
            Panel panel{i, j, {}, {}};
            const Matrix B = block(model.H(), i, j);
            // Where the plane lies in a face shared by several cones, they meet it in the same
            // sector: the first of them is drawn (one colour, one name per sector; on a face the
            // continuous law's pieces agree), the others are named in its tooltip.
            auto same_direction = [](const Vector& a, const Vector& b) {
                return sign_of(cross(a, b)) == Sign::zero && sign_of(a[0] * b[0] + a[1] * b[1]) == Sign::positive;
            };
            for (std::size_t p = 0; p < P; ++p) {
                auto sector = plane_sector(pieces[p], i, j);
                if (!sector)
                    continue;
                bool seen = false;
                for (auto& other : panel.sectors)
                    if (same_direction(other.u, sector->first) && same_direction(other.v, sector->second)) {
                        other.also.push_back(p);
                        seen = true;
                    }
                if (seen)
                    continue;
                Sector sec{p, sector->first, sector->second, 0, 0, {}};
                sec.a = h_angle(B, sec.u);
                sec.d = sector_span(sec.a, h_angle(B, sec.v));
                std::vector<std::pair<double, double>> curve;
                for (const auto& xy : arc_samples(B, sec.u, sec.v, sec.d, 180)) {
                    const double r = norm_ratio(model, pieces[p], embed(xy, c, i, j));
                    top = std::max(top, r);
                    curve.push_back({h_angle(B, xy), r});
                }
                panel.sectors.push_back(std::move(sec));
                panel.curves.push_back(std::move(curve));
            }
            panels.push_back(std::move(panel));
        }
    const int rows = (static_cast<int>(planes) + per_row - 1) / per_row;
    const double width = per_row * cell, height = rows * cell;
    const double R = radius / top;
    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(width) + "\" height=\"" + fmt(height) +
                    "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    for (std::size_t k = 0; k < panels.size(); ++k) {
        const Panel& panel = panels[k];
        const double x0 = static_cast<double>(static_cast<int>(k) % per_row) * cell;
        const double y0 = static_cast<double>(static_cast<int>(k) / per_row) * cell;
        const double cx = x0 + cell / 2, cy = y0 + cell / 2 + 8;
        s += "<g class=\"plane\"><rect x=\"" + fmt(x0 + 2) + "\" y=\"" + fmt(y0 + 2) + "\" width=\"" + fmt(cell - 4) +
             "\" height=\"" + fmt(cell - 4) + "\" fill=\"#ffffff\" stroke=\"#cccccc\"/>\n";
        s += "<text x=\"" + fmt(x0 + 8) + "\" y=\"" + fmt(y0 + 16) + "\" font-weight=\"bold\">" + coordinate_svg(model, panel.i) +
             ", " + coordinate_svg(model, panel.j) + "</text>\n";
        // Where no cone meets the plane in a sector: a grey ring underneath shows the gap.
        s += "<circle cx=\"" + fmt(cx) + "\" cy=\"" + fmt(cy) + "\" r=\"" + fmt(radius + 10) +
             "\" fill=\"none\" stroke=\"#dddddd\" stroke-width=\"12\"/>\n";
        for (const auto& sec : panel.sectors) {
            std::string title = piece_title(pieces[sec.piece]);
            for (std::size_t q : sec.also)
                title += "\nalso on this sector: " + pieces[q].name;
            s += "<path d=\"" + ring_path(cx, cy, radius + 4, radius + 16, sec.a, std::max(sec.d, 1e-6)) + "\" fill=\"" +
                 colours[sec.piece] + "\" stroke=\"#ffffff\" stroke-width=\"0.5\"><title>" + xml_escape(title) +
                 "</title></path>\n";
        }
        // Names outside the ring where the arc has room for them and no name is near (cones that
        // meet the plane in a common face would write over each other).
        std::vector<std::pair<double, double>> placed;
        for (const auto& sec : panel.sectors) {
            const std::string& name = pieces[sec.piece].name;
            const double mid = sec.a + sec.d / 2;
            if (sec.d * (radius + 24) < 5.5 * static_cast<double>(name.size()) + 4)
                continue;
            const double lx = cx + (radius + 23) * std::cos(mid), ly = cy - (radius + 23) * std::sin(mid) + 3;
            bool room = true;
            for (const auto& [px, py] : placed)
                room = room && (std::abs(px - lx) > 5.5 * static_cast<double>(name.size()) || std::abs(py - ly) > 10);
            if (!room)
                continue;
            placed.push_back({lx, ly});
            s += "<text x=\"" + fmt(lx) + "\" y=\"" + fmt(ly) +
                 "\" text-anchor=\"middle\" font-size=\"8\" class=\"cone-label\">" + xml_escape(name) + "</text>\n";
        }
        s += "<circle cx=\"" + fmt(cx) + "\" cy=\"" + fmt(cy) + "\" r=\"" + fmt(R) +
             "\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1\" stroke-dasharray=\"4,3\"/>\n";
        for (std::size_t q = 0; q < panel.curves.size(); ++q) {
            std::string pts;
            for (const auto& [a, r] : panel.curves[q])
                pts += point(cx, cy, R * r, a) + " ";
            s += "<polyline points=\"" + pts + "\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1.6\" stroke-linejoin=\"round\"><title>" +
                 xml_escape(pieces[panel.sectors[q].piece].name) + "</title></polyline>\n";
        }
        s += "</g>\n";
    }
    return s + "</svg>\n";
}

std::vector<std::string> draw::piece_colours(const Model& model) {
    using draw::kPalette;
    const auto& pieces = model.pieces();
    const std::size_t P = pieces.size(), c = model.contacts(), K = 7;
    std::vector<std::string> out(P);
    if (P > 20000 || c < 2) {
        for (std::size_t p = 0; p < P; ++p)
            out[p] = kPalette[p % K];
        return out;
    }
    // Neighbours in a picture: for c <= 3 pieces sharing c - 1 rays (a facet of simplicial cones:
    // touching on the circle or the sphere). Beyond, no picture shows facets, and a cone has
    // dozens of facet neighbours; only the rings below count.
    std::map<std::size_t, std::vector<std::size_t>> by_ray;
    for (std::size_t p = 0; p < P && c <= 3; ++p)
        for (const auto id : pieces[p].ray_ids)
            by_ray[id].push_back(p);
    std::vector<std::map<std::size_t, std::size_t>> shared(P);
    for (const auto& [id, list] : by_ray)
        for (std::size_t i = 0; i < list.size(); ++i)
            for (std::size_t j = i + 1; j < list.size(); ++j) {
                ++shared[list[i]][list[j]];
                ++shared[list[j]][list[i]];
            }
    std::vector<std::set<std::size_t>> near(P);
    for (std::size_t p = 0; p < P; ++p)
        for (const auto& [q, n] : shared[p])
            if (n + 1 >= c)
                near[p].insert(q);
    // And pieces whose sectors follow each other on a ring of the plane view (c >= 3): there
    // they touch although they may share only a lower face.
    if (c >= 3 && planes_svg_fits(model)) {
        // A direction of the plane as a key: divided exactly by its largest |component|.
        auto key = [](const Vector& u) {
            const Rational top = abs_of(u[0]) > abs_of(u[1]) ? abs_of(u[0]) : abs_of(u[1]);
            return to_string(u[0] / top) + " " + to_string(u[1] / top);
        };
        for (std::size_t i = 0; i < c; ++i)
            for (std::size_t j = i + 1; j < c; ++j) {
                std::map<std::string, std::vector<std::size_t>> starting; // sectors by their first direction
                std::vector<std::pair<std::size_t, std::string>> ending;
                for (std::size_t p = 0; p < P; ++p)
                    if (auto sector = plane_sector(pieces[p], i, j)) {
                        starting[key(sector->first)].push_back(p);
                        ending.emplace_back(p, key(sector->second));
                    }
                for (const auto& [p, end] : ending)
                    if (const auto it = starting.find(end); it != starting.end())
                        for (const auto q : it->second)
                            if (q != p) {
                                near[p].insert(q);
                                near[q].insert(p);
                            }
            }
    }
    std::vector<std::vector<std::size_t>> adj(P);
    for (std::size_t p = 0; p < P; ++p)
        adj[p].assign(near[p].begin(), near[p].end());
    // Smallest-last order: repeatedly remove a piece of least remaining degree; colour in reverse.
    std::vector<std::size_t> degree(P), order;
    std::vector<bool> removed(P, false);
    for (std::size_t p = 0; p < P; ++p)
        degree[p] = adj[p].size();
    std::map<std::pair<std::size_t, std::size_t>, bool> queue; // (degree, piece)
    for (std::size_t p = 0; p < P; ++p)
        queue[{degree[p], p}] = true;
    while (!queue.empty()) {
        const std::size_t p = queue.begin()->first.second;
        queue.erase(queue.begin());
        removed[p] = true;
        order.push_back(p);
        for (const auto q : adj[p])
            if (!removed[q]) {
                queue.erase({degree[q], q});
                queue[{--degree[q], q}] = true;
            }
    }
    std::vector<int> colour(P, -1);
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
        const std::size_t p = *it;
        std::vector<std::size_t> used(K, 0);
        for (const auto q : adj[p])
            if (colour[q] >= 0)
                ++used[static_cast<std::size_t>(colour[q])];
        // The first free colour, counted from the piece's own index so that laws without
        // neighbours (or with few) keep the palette's order; else the least used.
        std::size_t best = p % K;
        for (std::size_t k = 0; k < K; ++k)
            if (used[(p + k) % K] < used[best])
                best = (p + k) % K;
        colour[p] = static_cast<int>(best);
    }
    for (std::size_t p = 0; p < P; ++p)
        out[p] = kPalette[static_cast<std::size_t>(colour[p])];
    return out;
}

} // namespace impactcert
