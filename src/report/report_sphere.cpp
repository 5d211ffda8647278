// SPDX-License-Identifier: GPL-3.0-or-later
// report_sphere.cpp -- the cones of a law with three contacts on the unit sphere: two orthographic
// hemispheres, every cone drawn as its spherical triangle (great-circle edges) clipped to the
// hemisphere (where it leaves it, along the rim), numbered where it shows best, with a key.
// Presentation only: doubles from exact rays (scaled_doubles), no verdict depends on them.
#include "report/report.hpp"

#include "report/report_draw.hpp"
#include "prover/verdict_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace impactcert::draw {

namespace {

using P3 = std::array<double, 3>;
using P2 = std::pair<double, double>;

P3 unit(P3 v) {
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(n > 0 && std::isfinite(n)))
        return {0, 0, 1};
    return {v[0] / n, v[1] / n, v[2] / n};
}
double dot3(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
P3 to_p3(const Vector& v) {
    const auto d = scaled_doubles(v);
    return unit({d[0], d[1], d[2]});
}

// Points of the shorter great-circle arc from u to v, u included, v not: `steps` of them.
void arc(std::vector<P3>& out, const P3& u, const P3& v, int steps) {
    for (int k = 0; k < steps; ++k) {
        const double t = k / static_cast<double>(steps);
        out.push_back(unit({u[0] * (1 - t) + v[0] * t, u[1] * (1 - t) + v[1] * t, u[2] * (1 - t) + v[2] * t}));
    }
}

// The spherical triangle of a cone's three rays as a dense closed polyline. The rays of a piece
// are linearly independent, so the triangle lies in an open hemisphere and each edge is the
// shorter arc.
std::vector<P3> spherical_triangle(const P3& a, const P3& b, const P3& c) {
    std::vector<P3> out;
    arc(out, a, b, 48);
    arc(out, b, c, 48);
    arc(out, c, a, 48);
    return out;
}

// The part of a closed spherical polyline in the hemisphere n . x >= 0: Sutherland-Hodgman against
// the plane, every crossing pushed onto the rim, and between a crossing that leaves the
// hemisphere and the next that enters it, the rim's arc (the visible part of a cone is convex and
// meets the rim in one arc shorter than a half circle).
std::vector<P3> clip_hemisphere(const std::vector<P3>& poly, const P3& n) {
    std::vector<P3> out;
    bool open_exit = false, first_entry_seen = false;
    P3 exit_point{}, first_entry{};
    auto on_rim = [&](const P3& p, const P3& q, double dp, double dq) {
        const double t = dp / (dp - dq);
        P3 x{p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t, p[2] + (q[2] - p[2]) * t};
        const double h = dot3(x, n);
        return unit({x[0] - h * n[0], x[1] - h * n[1], x[2] - h * n[2]});
    };
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const P3& p = poly[i];
        const P3& q = poly[(i + 1) % poly.size()];
        const double dp = dot3(n, p), dq = dot3(n, q);
        if (dp >= 0)
            out.push_back(p);
        if ((dp >= 0) == (dq >= 0))
            continue;
        const P3 x = on_rim(p, q, dp, dq);
        if (dp >= 0) { // leaving
            out.push_back(x);
            open_exit = true;
            exit_point = x;
        } else { // entering
            if (open_exit) {
                std::vector<P3> rim;
                arc(rim, exit_point, x, 48);
                out.insert(out.end(), rim.begin() + 1, rim.end());
                open_exit = false;
            } else if (!first_entry_seen) {
                first_entry_seen = true;
                first_entry = x;
            }
            out.push_back(x);
        }
    }
    if (open_exit && first_entry_seen) {
        std::vector<P3> rim;
        arc(rim, exit_point, first_entry, 48);
        out.insert(out.end(), rim.begin() + 1, rim.end());
    }
    return out;
}

bool inside(const std::vector<P2>& poly, double x, double y) {
    bool in = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const auto& [xi, yi] = poly[i];
        const auto& [xj, yj] = poly[j];
        if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi)
            in = !in;
    }
    return in;
}

double distance_to_boundary(const std::vector<P2>& poly, double x, double y) {
    double best = 1e300;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const auto& [ax, ay] = poly[j];
        const auto& [bx, by] = poly[i];
        const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
        double t = len2 > 0 ? ((x - ax) * dx + (y - ay) * dy) / len2 : 0;
        t = std::clamp(t, 0.0, 1.0);
        best = std::min(best, std::hypot(x - ax - t * dx, y - ay - t * dy));
    }
    return best;
}

// The point of the polygon farthest from its boundary (on a grid of `step` pixels, then refined
// around the best point), and that distance: where a label fits best.
// Points in `avoid` (counterexamples, axes) count as boundary, 9 px wide.
std::pair<P2, double> label_spot(const std::vector<P2>& poly, const std::vector<P2>& avoid) {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto& [x, y] : poly) {
        x0 = std::min(x0, x), x1 = std::max(x1, x);
        y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    P2 best{(x0 + x1) / 2, (y0 + y1) / 2};
    double best_d = -1;
    auto try_at = [&](double x, double y) {
        if (!inside(poly, x, y))
            return;
        double d = distance_to_boundary(poly, x, y);
        for (const auto& [ax, ay] : avoid)
            d = std::min(d, std::hypot(x - ax, y - ay) - 9);
        if (d > best_d)
            best_d = d, best = {x, y};
    };
    const double step = std::max(2.0, std::max(x1 - x0, y1 - y0) / 24);
    for (double y = y0 + step / 2; y < y1; y += step)
        for (double x = x0 + step / 2; x < x1; x += step)
            try_at(x, y);
    const P2 coarse = best;
    for (int i = -4; i <= 4; ++i)
        for (int j = -4; j <= 4; ++j)
            try_at(coarse.first + i * step / 4, coarse.second + j * step / 4);
    return {best, std::max(best_d, 0.0)};
}

struct View {
    P3 n, a1, a2; // the hemisphere's pole and the picture's axes
    double cx, cy;
};

} // namespace

std::string sphere_svg(const Model& model, const VerifyReport* report) {
    const auto& pieces = model.pieces();
    const std::size_t P = pieces.size();
    const auto colours = piece_colours(model);
    // Numbers and a key up to 120 cones (kConesCaption3 says so); beyond, the cones alone (names on hover).
    const bool numbered = P <= 120;
    const double r = 170, margin = 40, gap = 2 * margin, key_columns = 3;
    const double width = 4 * r + gap + 2 * margin, disks = 30 + 2 * margin + 2 * r;
    const std::size_t key_rows = numbered ? (P + 2) / 3 : 0;
    const double key_top = disks + 6, height = key_top + 16.0 * static_cast<double>(key_rows) + (numbered ? 8 : 0);
    // Views from (1,1,1) and from (-1,-1,-1); a1 is mirrored for the back, so that it is seen
    // from behind, as on a globe.
    const P3 front = unit({1, 1, 1}), e1 = unit({1, -1, 0}), e2 = unit({-1, -1, 2});
    std::array<View, 2> views{};
    for (std::size_t v = 0; v < 2; ++v) {
        const double sign = v == 0 ? 1.0 : -1.0;
        views[v] = {{front[0] * sign, front[1] * sign, front[2] * sign},
                    {e1[0] * sign, e1[1] * sign, e1[2] * sign},
                    e2,
                    margin + r + static_cast<double>(v) * (2 * r + gap),
                    30 + margin + r};
    }
    auto project = [&](const View& v, const P3& x) { return P2{v.cx + dot3(x, v.a1) * r, v.cy - dot3(x, v.a2) * r}; };

    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(width) + "\" height=\"" + fmt(height) +
                    "\" viewBox=\"0 0 " + fmt(width) + " " + fmt(height) +
                    "\" font-family=\"sans-serif\" role=\"img\" aria-label=\"cones of " + xml_escape(model.law().name) +
                    "\">\n<title>" + xml_escape(model.law().name) +
                    ": the cones C_i on the unit sphere of (gamma1-, gamma2-, gamma3-), two hemispheres</title>\n<defs>";
    for (std::size_t v = 0; v < 2; ++v)
        s += "<clipPath id=\"hemisphere" + std::to_string(v) + "\"><circle cx=\"" + fmt(views[v].cx) + "\" cy=\"" +
             fmt(views[v].cy) + "\" r=\"" + fmt(r) + "\"/></clipPath>";
    s += "</defs>\n";

    // The visible part of every cone in each view, in picture coordinates.
    std::vector<std::array<std::vector<P2>, 2>> shown(P);
    for (std::size_t p = 0; p < P; ++p) {
        const auto tri = spherical_triangle(to_p3(pieces[p].R.column(0)), to_p3(pieces[p].R.column(1)),
                                            to_p3(pieces[p].R.column(2)));
        for (std::size_t v = 0; v < 2; ++v) {
            const auto part = clip_hemisphere(tri, views[v].n);
            if (part.size() >= 3)
                for (const auto& x : part)
                    shown[p][v].push_back(project(views[v], x));
        }
    }
    const char* const headings[2] = {"seen from (1, 1, 1)", "seen from (\xe2\x88\x92" "1, \xe2\x88\x92" "1, \xe2\x88\x92" "1)"};
    for (std::size_t v = 0; v < 2; ++v) {
        const View& view = views[v];
        s += "<text x=\"" + fmt(view.cx) + "\" y=\"18\" text-anchor=\"middle\" font-size=\"14\">" + headings[v] + "</text>\n";
        s += "<circle cx=\"" + fmt(view.cx) + "\" cy=\"" + fmt(view.cy) + "\" r=\"" + fmt(r) + "\" fill=\"#fafafa\"/>\n";
        s += "<g clip-path=\"url(#hemisphere" + std::to_string(v) + ")\">\n";
        for (std::size_t p = 0; p < P; ++p) {
            if (shown[p][v].empty())
                continue;
            std::string pts;
            for (const auto& [px, py] : shown[p][v])
                pts += fmt(px) + "," + fmt(py) + " ";
            s += "<polygon points=\"" + pts + "\" fill=\"" + colours[p] +
                 "\" fill-opacity=\"0.75\" stroke=\"#222\" stroke-width=\"0.7\" stroke-linejoin=\"round\"><title>" +
                 xml_escape(std::to_string(p + 1) + ". " + piece_title(pieces[p])) + "</title></polygon>\n";
        }
        s += "</g>\n<circle cx=\"" + fmt(view.cx) + "\" cy=\"" + fmt(view.cy) + "\" r=\"" + fmt(r) +
             "\" fill=\"none\" stroke=\"#555\" stroke-width=\"1.2\"/>\n";
    }

    // Where the counterexamples and the axes are drawn: no number there.
    std::array<std::vector<P2>, 2> avoid;
    for (std::size_t v = 0; v < 2; ++v) {
        for (std::size_t k = 0; k < 3; ++k) {
            P3 axis{0, 0, 0};
            axis[k] = 1;
            if (dot3(axis, views[v].n) > 0)
                avoid[v].push_back(project(views[v], axis));
        }
        for (const auto& mk : marked_points(report, 3))
            for (const auto& pt : mk.points) {
                const P3 x = unit({pt[0], pt[1], pt[2]});
                if (dot3(x, views[v].n) > 0)
                    avoid[v].push_back(project(views[v], x));
            }
    }
    // Numbers: each cone's in the view where it has most room, inside it when the number fits,
    // else outside the disk with a leader line (outside labels spread along the rim).
    struct Outside {
        double angle;
        P2 from;
        std::string text;
    };
    std::array<std::vector<Outside>, 2> outside;
    if (numbered)
        for (std::size_t p = 0; p < P; ++p) {
            const std::string text = std::to_string(p + 1);
            const double need = std::hypot(3.2 * static_cast<double>(text.size()) + 1.5, 5.5);
            std::size_t best_view = 0;
            std::pair<P2, double> best{{0, 0}, -1};
            for (std::size_t v = 0; v < 2; ++v) {
                if (shown[p][v].empty())
                    continue;
                const auto spot = label_spot(shown[p][v], avoid[v]);
                if (spot.second > best.second)
                    best = spot, best_view = v;
            }
            if (best.second < 0)
                continue; // not visible at all (cannot happen for a cone with an interior)
            const View& view = views[best_view];
            if (best.second >= need) {
                s += "<text x=\"" + fmt(best.first.first) + "\" y=\"" + fmt(best.first.second + 3.8) +
                     "\" text-anchor=\"middle\" font-size=\"11\" class=\"cone-label\">" + text + "</text>\n";
            } else {
                const double angle = std::atan2(best.first.second - view.cy, best.first.first - view.cx);
                outside[best_view].push_back({angle, best.first, text});
            }
        }
    for (std::size_t v = 0; v < 2; ++v) {
        auto& list = outside[v];
        if (list.empty())
            continue;
        std::sort(list.begin(), list.end(), [](const Outside& a, const Outside& b) { return a.angle < b.angle; });
        // At least 15 px apart along a circle of radius r + 18: push forward, then back if the
        // last ones wrapped into the first.
        const double R = r + 18, min_gap = 15 / R, two_pi = 2 * std::acos(-1.0);
        for (std::size_t i = 1; i < list.size(); ++i)
            list[i].angle = std::max(list[i].angle, list[i - 1].angle + min_gap);
        const double overflow = list.back().angle - (list.front().angle + two_pi - min_gap);
        if (overflow > 0)
            for (auto& o : list)
                o.angle -= overflow / 2;
        const View& view = views[v];
        for (const auto& o : list) {
            const double x = view.cx + R * std::cos(o.angle), y = view.cy + R * std::sin(o.angle);
            const double xr = view.cx + (r + 7) * std::cos(o.angle), yr = view.cy + (r + 7) * std::sin(o.angle);
            s += "<polyline points=\"" + fmt(o.from.first) + "," + fmt(o.from.second) + " " + fmt(xr) + "," + fmt(yr) +
                 "\" fill=\"none\" stroke=\"#333\" stroke-width=\"0.6\"/><circle cx=\"" + fmt(o.from.first) + "\" cy=\"" +
                 fmt(o.from.second) + "\" r=\"1.3\" fill=\"#333\"/><text x=\"" + fmt(x) + "\" y=\"" + fmt(y + 3.8) +
                 "\" text-anchor=\"middle\" font-size=\"11\" class=\"cone-label\">" + o.text + "</text>\n";
        }
    }

    // The axes gamma_k- (positive directions) where visible, and the counterexamples.
    for (std::size_t v = 0; v < 2; ++v) {
        const View& view = views[v];
        for (std::size_t k = 0; k < 3; ++k) {
            P3 axis{0, 0, 0};
            axis[k] = 1;
            if (dot3(axis, view.n) <= 0)
                continue;
            const auto [px, py] = project(view, axis);
            s += "<circle cx=\"" + fmt(px) + "\" cy=\"" + fmt(py) + "\" r=\"2.5\" fill=\"#000\"/><text x=\"" + fmt(px + 4) +
                 "\" y=\"" + fmt(py - 5) + "\" font-size=\"11\" stroke=\"#fff\" stroke-width=\"2.5\" paint-order=\"stroke\">" +
                 coordinate_svg(model, k) + "-</text>\n";
        }
        std::map<std::pair<long, long>, int> labels;
        for (const auto& mk : marked_points(report, 3)) {
            std::vector<P2> at;
            for (const auto& pt : mk.points) {
                const P3 x = unit({pt[0], pt[1], pt[2]});
                if (dot3(x, view.n) > 0)
                    at.push_back(project(view, x));
            }
            s += marks_svg(at, mk.id, labels, view.cx); // names towards the disk's centre
        }
    }

    // The key: number, colour and name, in three columns (names cut at 36 characters; the full
    // name and rays on hover).
    if (numbered) {
        const double column = (width - 2 * margin) / key_columns;
        for (std::size_t p = 0; p < P; ++p) {
            const double x = margin + column * static_cast<double>(p / key_rows),
                         y = key_top + 16.0 * static_cast<double>(p % key_rows);
            const std::string name = pieces[p].name.size() > 36 ? shortened(pieces[p].name, 33) : pieces[p].name;
            s += "<g class=\"key\"><title>" + xml_escape(piece_title(pieces[p])) + "</title><rect x=\"" + fmt(x) +
                 "\" y=\"" + fmt(y) + "\" width=\"11\" height=\"11\" fill=\"" + colours[p] +
                 "\" fill-opacity=\"0.75\" stroke=\"#222\" stroke-width=\"0.5\"/><text x=\"" + fmt(x + 16) + "\" y=\"" +
                 fmt(y + 9.5) + "\" font-size=\"11\">" + std::to_string(p + 1) + "  " + xml_escape(name) + "</text></g>\n";
        }
    }
    return s + "</svg>\n";
}

} // namespace impactcert::draw
