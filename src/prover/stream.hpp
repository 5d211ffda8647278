// SPDX-License-Identifier: GPL-3.0-or-later
// stream.hpp -- `impactcert verify --stream`: the obligations of a compact law decided without
// its matrices (proofs/README.md, "Streamed laws").
//
// Contract: verify_stream(law, limits) decides every obligation of a law given by orbit
// representatives ("pieces_listed": "orbit-representatives") and its symmetries. It expands the
// law exactly as Model does (the same pieces, in the same order, with the same names, and the
// same input errors for --max-pieces, names and growth), but keeps of each piece only the ids
// of its primitive rays and of their images (in two tables of distinct exact vectors), about
// 8c + 16 bytes, counted against --max-memory. Every obligation is then decided by passes over
// these ids, through the reductions of proofs/README.md ("Symmetries", "Streamed laws").
//   - Verdicts are those of verify() whenever both decide: a claim proved here is proved; a
//     refutation carries an exact witness in the shape verify() gives (the per-piece ones are
//     verify()'s own, on a model of the pieces involved), re-validated before it is returned.
//   - What the streamed checks cannot decide is `undecided`, with a limit that names --stream
//     (verify without it decides it, memory permitting): a fan that is not matched facet to
//     facet, nonexpansive for a law that does not conserve energy, and every reduced obligation
//     when the symmetries are refuted.
//   - StreamRefused: the law is outside what the streamed store holds (a law listing every
//     piece -- after Model has validated it --, rays or images of P beyond int64, two listed
//     pieces with one cone, symmetry names with ".", more than 64 orbits or 250 contacts): the
//     CLI reports it in one line with exit status 3, naming --stream.
//   - InputError: as Model for the same law, in Model's order, except that a law the stream
//     refuses is refused before the declarations that name pieces are validated.
//   - Threads (limits.jobs) split the symmetry expansion (a block of pieces mapped and looked up
//     on threads, added in order: stream_store.hpp) and the exact membership solves; the report
//     does not depend on their number.
#pragma once

#include "model/law.hpp"
#include "base/limits.hpp"
#include "prover/obligations.hpp"

#include <cstddef>
#include <stdexcept>

namespace impactcert {

struct StreamRefused : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct StreamResult {
    VerifyReport report;
    std::size_t balls = 0, contacts = 0, pieces = 0;
    std::size_t rays = 0, images = 0; // distinct primitive rays and images of rays
    std::size_t bytes = 0;            // what the store counted against --max-memory
};

StreamResult verify_stream(const Law& law, const Limits& limits = {}, const Progress& progress = {});

} // namespace impactcert
