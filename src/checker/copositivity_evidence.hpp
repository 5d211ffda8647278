// SPDX-License-Identifier: GPL-3.0-or-later
// copositivity_evidence.hpp -- the copositivity certificates of a certificate (proofs/README.md,
// "Exact copositivity"), re-checked: A >= 0 entrywise, an LDL^T factorisation (PSD), PSD plus a
// non-negative N, or a KKT enumeration that the checker redoes face by face; and the canonical
// negative points the prover derives from them for its witnesses.
//
// Contract: the check_* functions return whether the evidence proves the matrix copositive
// (PSD) and reject evidence that is wrong; a KKT enumeration beyond `max_faces` faces is
// Undecided (--max-faces), refused before it starts, as the prover refuses it.
#pragma once

#include "linalg.hpp"
#include "reading.hpp"

#include <cstddef>
#include <optional>
#include <string>

namespace impactcert_check::detail {

// L and D (keys checked by the caller) with L D L^T = B, L unit lower triangular, D >= 0.
bool check_psd_evidence(const Mat& B, const Json& j, const std::string& path);

// Any of the four methods; `j` is the certificate object {"method": ..., ...}.
bool check_copositive_evidence(const Mat& A, const Json& j, const std::string& path, std::size_t max_faces);

// The canonical negative direction of a symmetric matrix, or nothing when it is PSD.
std::optional<Vec> psd_witness(const Mat& A);

// The first KKT candidate attaining the minimum, padded with zeros to length n.
Vec kkt_minimiser(const Json& cert, const std::string& path, std::size_t n);

// The prover's interior_witness: z + 2^-k 1 for the least k where the form is negative.
Vec moved_inside(const Mat& A, const Vec& z, const std::string& path);

} // namespace impactcert_check::detail
