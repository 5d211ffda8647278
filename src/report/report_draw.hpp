// SPDX-License-Identifier: GPL-3.0-or-later
// report_draw.hpp -- drawing helpers shared by the report's pictures (report.cpp,
// report_planes.cpp). Drawing coordinates are doubles: presentation only, no verdict depends on
// them; every exact quantity is converted by display_double or an angle function that cannot
// overflow at any scale.
#pragma once

#include "model/law.hpp"
#include "prover/obligations.hpp"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace impactcert::draw {

// Okabe & Ito's colour-blind-safe palette (without black and vermillion, kept for the marks),
// and grey: seven colours.
extern const char* const kPalette[7];

// The colour of each piece in every picture of a law (report_planes.cpp): neighbours get
// different colours wherever seven suffice. Neighbours are the cones that touch in a picture:
// for c <= 3 cones that share a facet (c - 1 rays: on the circle or the sphere) and, for c >= 3
// where the plane view is drawn, cones whose sectors follow each other on one of its rings. The pieces are coloured greedily in a smallest-last order, which needs at most one
// colour more than the graph's degeneracy (3 for the ring of a law with 2 contacts; the facet
// graph of a law with 3 contacts is planar, at most 6). Where a larger law needs more, a piece
// takes the colour least used among its neighbours. Beyond 20,000 pieces, the palette in order.
std::vector<std::string> piece_colours(const Model& model);

std::string fmt(double x); // two decimals

struct Dir {
    double x, y; // unit vector
};

std::string matrix_text(const Matrix& m); // [[a, b], [c, d]], exact
std::string rays_text(const Piece& p);    // the rays, exact
std::string piece_title(const Piece& p);  // "name: rays ...; Q = ..."

// A non-negative rational as a double for drawing: beyond 2^1000 it is 2^1000, below 2^-1000 zero.
double display_double(const Rational& r);

// The angle in (-pi, pi] of a 2-vector g in the metric of the 2 x 2 positive definite H (the
// Euclidean angle of L^T g, H = L L^T), and its unit direction.
double h_angle(const Matrix& H, const Vector& g);
Dir h_direction(const Matrix& H, const Vector& g);

double span(double a, double b); // counter-clockwise from a to b, in [0, 2 pi)

// A direction in double at any scale: the vector is first multiplied exactly by the power of two
// that brings its largest component near 1, so no component overflows and the direction is kept
// (a component below 2^-1074 of the largest becomes 0). A zero vector gives zeros.
std::vector<double> scaled_doubles(const Vector& v);

// The points of a claimed, refuted obligation's counterexample in c coordinates: one point, or a
// pair (to be joined), scaled together.
struct Marked {
    std::string id;
    std::vector<std::vector<double>> points;
    std::vector<Vector> exact; // the same points, exactly
};
std::vector<Marked> marked_points(const VerifyReport* report, std::size_t c);

// Counterexample marks at picture coordinates: the points, joined when there are two.
// `labels` counts the labels already written at each (rounded) place: the next one there goes a
// line lower, so that several counterexamples at one point do not overwrite each other's names.
// A name is written to the right of its point, or to the left where the point lies right of
// `left_beyond`.
std::string marks_svg(const std::vector<std::pair<double, double>>& shown, const std::string& id,
                      std::map<std::pair<long, long>, int>& labels, double left_beyond = 1e300);

// c = 3 (report_sphere.cpp): the cones on the unit sphere in two orthographic hemispheres, each
// cone clipped to the hemisphere along great-circle arcs and the rim, numbered where it shows
// best (inside it, or by a leader line outside the disk), with a key of the numbers.
std::string sphere_svg(const Model& model, const VerifyReport* report);

} // namespace impactcert::draw
