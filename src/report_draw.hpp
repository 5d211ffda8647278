// SPDX-License-Identifier: GPL-3.0-or-later
// report_draw.hpp -- drawing helpers shared by the report's pictures (report.cpp,
// report_planes.cpp). Drawing coordinates are doubles: presentation only, no verdict depends on
// them; every exact quantity is converted by display_double or an angle function that cannot
// overflow at any scale.
#pragma once

#include "law.hpp"

#include <string>

namespace impactcert::draw {

// Okabe & Ito's colour-blind-safe palette (without black and vermillion, kept for the marks),
// grey as an eighth, then repeating.
extern const char* const kPalette[10];

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

} // namespace impactcert::draw
