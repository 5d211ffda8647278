// SPDX-License-Identifier: GPL-3.0-or-later
// nonexpansive -- proofs/README.md, "nonexpansive (pairwise)", with "Exact copositivity",
// "S as a function", "Integer kernels" and "Symmetries".
// Claim: |S(a) - S(b)|_H <= |a - b|_H for all a, b in R^c.
// Check: S is a function (else the domain witness refutes it first), then for every ordered
// pair (i, j), i = j included, with a = R_i s, b = R_j t, z = (s, t) >= 0:
// A = B1^T H B1 - B2^T H B2 (B1 = [R_i, -R_j], B2 = [Q_i R_i, -Q_j R_j]) is copositive.
// With verified symmetries, i runs over one representative of each orbit of pieces (every
// ordered pair is the image of a checked one under the group). Each form is first decided by
// the integer kernel (pair_kernel.hpp); GMP decides whatever the kernel cannot, and always when
// evidence is built, so verdicts, methods, counts and witnesses never depend on the kernel.
// Pairs are decided in blocks, by `jobs` threads, and read in order: the first pair that is
// not copositive (or exceeds a limit) ends the obligation, whatever the number of threads.
// A discontinuity found by P1 comes first: the pair across it is refuted near P1's ray without
// any pair form (discontinuity_pair).
// Witness: a negative z moved into the open orthant (interior_witness), so that gamma_a and
// gamma_b are interior to their cones.
#include "exact/pair_kernel.hpp"
#include "base/parallel.hpp"
#include "prover/obligations/prover.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <cstddef>
#include <exception>
#include <optional>
#include <string>
#include <thread>

namespace impactcert::detail {

Json Prover::pair_witness(std::size_t i, std::size_t j, const Vector& gamma_a, const Vector& gamma_b) {
    const Rational lhs = m_.energy(pieces_[i].Q * gamma_a - pieces_[j].Q * gamma_b);
    const Rational rhs = m_.energy(gamma_a - gamma_b);
    ensure(lhs > rhs, "nonexpansive lhs > rhs");
    ensure(m_.in_interior(i, gamma_a) && m_.in_interior(j, gamma_b), "nonexpansive interiors");
    return Json{{"piece_a", name(i)},         {"piece_b", name(j)},
                {"gamma_a", to_json(gamma_a)}, {"gamma_b", to_json(gamma_b)},
                {"lhs", to_json(lhs)},         {"rhs", to_json(rhs)}};
}

// Near a ray v where Q_a v != Q_b v: gamma_a = v + eps R_a 1, gamma_b = v + eps R_b 1 lie in
// the interiors of C_a and C_b (R^-1 gamma = R^-1 v + eps 1 > 0), and as eps -> 0 the left side
// tends to |Q_a v - Q_b v|_H^2 > 0 while the right side is eps^2 |R_a 1 - R_b 1|_H^2: the first
// eps = 1/2, 1/4, ... with lhs > rhs gives the witness (it exists). lhs - rhs is the quadratic
// A + B eps + C eps^2 (A = |D|^2 > 0, B = 2 <D, delta>, C = |delta|^2 - |rho|^2 with D = Q_a v - Q_b v,
// delta = Q_a d_a - Q_b d_b, rho = d_a - d_b, in H), so the first k with A 4^k + B 2^k + C > 0 is
// found in integers, each step a few shifts and additions (not two matrix products).
Json Prover::discontinuity_pair(const Discontinuity& d) {
    const Vector ones(c_, Rational(1));
    const Vector da = pieces_[d.a].R * ones, db = pieces_[d.b].R * ones;
    const Vector D = pieces_[d.a].Q * d.ray - pieces_[d.b].Q * d.ray;
    const Vector delta = pieces_[d.a].Q * da - pieces_[d.b].Q * db, rho = da - db;
    const Rational A = m_.energy(D), B = 2 * bilinear(D, m_.H(), delta), C = m_.energy(delta) - m_.energy(rho);
    ensure(sign_of(A) == Sign::positive, "Lemma D: the values differ");
    mpz_class L = 1;
    for (const Rational* x : {&A, &B, &C})
        mpz_lcm(L.get_mpz_t(), L.get_mpz_t(), mpq_denref(x->mpq()));
    auto scaled = [&](const Rational& x) -> mpz_class { // evaluated here (gmpxx's expressions are lazy)
        return mpz_class(L / mpz_class(mpq_denref(x.mpq()))) * mpz_class(mpq_numref(x.mpq()));
    };
    const mpz_class a = scaled(A), b = scaled(B), c = scaled(C);
    std::size_t k = 1;
    for (mpz_class value, term;; ++k) {
        mpz_mul_2exp(value.get_mpz_t(), a.get_mpz_t(), 2 * k);
        mpz_mul_2exp(term.get_mpz_t(), b.get_mpz_t(), k);
        value += term + c;
        if (sgn(value) > 0)
            break;
    }
    mpz_class denominator;
    mpz_ui_pow_ui(denominator.get_mpz_t(), 2, k);
    const Rational eps(CGAL::Gmpz(1), CGAL::Gmpz(denominator.get_mpz_t()));
    Json w = pair_witness(d.a, d.b, d.ray + eps * da, d.ray + eps * db);
    w["discontinuity"] = to_json(d.ray);
    return w;
}

Matrix Prover::pair_form(std::size_t i, std::size_t j) const {
    // z = (s, t): a = R_i s, b = R_j t;  a - b = B1 z,  S(a) - S(b) = B2 z.
    Matrix B1(c_, 2 * c_), B2(c_, 2 * c_);
    const Matrix QRi = pieces_[i].Q * pieces_[i].R, QRj = pieces_[j].Q * pieces_[j].R;
    for (std::size_t r = 0; r < c_; ++r)
        for (std::size_t k = 0; k < c_; ++k) {
            B1(r, k) = pieces_[i].R(r, k);
            B1(r, c_ + k) = -pieces_[j].R(r, k);
            B2(r, k) = QRi(r, k);
            B2(r, c_ + k) = -QRj(r, k);
        }
    return transpose(B1) * m_.H() * B1 - transpose(B2) * m_.H() * B2;
}

namespace {

// What one pair's decision left for the in-order reading.
struct PairOutcome {
    CopositivityMethod method = CopositivityMethod::nonnegative_entries;
    std::size_t checks = 0;
    bool copositive = false; // until a decision says so: an undecided pair is never read as copositive
    std::optional<LimitExceeded> limit;
    Json evidence; // with evidence: the certificate's entry
    Vector witness; // not copositive: z >= 0 with z^T A z < 0
    Matrix A;       // not copositive: the form
};

} // namespace

Outcome Prover::nonexpansive() {
    Outcome o;
    o.method = "S a function, then copositive pair forms";
    // Where S is undefined or two-valued on an open set it is not non-expansive: that
    // witness comes first, and spares the pair forms. A fan beyond its limit leaves the
    // pairs to decide a refutation.
    std::optional<LimitExceeded> fan_limit;
    try {
        if (auto w = domain_witness())
            return refute(o, std::move(*w));
    } catch (const LimitExceeded& e) {
        fan_limit = e;
    }
    // A discontinuity refutes the claim at once (proofs/README.md, "nonexpansive (pairwise)",
    // Lemma D): the pair of pieces across P1's ray comes before every pair form. P1 beyond its
    // limit leaves the pairs to decide.
    try {
        if (!p1().proved && p1_discontinuity_) {
            o.method = "the pieces across P1's discontinuity";
            o.checks = 1;
            return refute(o, discontinuity_pair(*p1_discontinuity_));
        }
    } catch (const LimitExceeded&) {
    }
    std::size_t by_method[4] = {0, 0, 0, 0};
    const std::vector<std::size_t> firsts = orbit_representatives();
    const std::size_t P = pieces_.size(), total = firsts.size() * P;
    if (symmetry())
        o.data["first_pieces"] = names_of(firsts);
    const PairKernel kernel(m_, limits_.integer_kernels);

    auto decide_pair = [&](std::size_t k, PairKernel::Scratch& scratch, PairOutcome& out) {
        const std::size_t i = firsts[k / P], j = k % P;
        if (!limits_.evidence) {
            if (auto method = kernel.decide(i, j, scratch)) {
                out.method = *method;
                out.checks = 1;
                out.copositive = true; // the kernel decides copositive pairs only
                return;
            }
        }
        try {
            Matrix A = pair_form(i, j);
            auto cop = decide_copositivity(A, limits_.max_faces, limits_.integer_kernels);
            out.method = cop.method;
            out.checks = cop.method == CopositivityMethod::kkt_enumeration ? cop.faces : 1;
            out.copositive = cop.copositive;
            if (limits_.evidence) {
                // The kernel must agree with GMP wherever it decides.
                if (auto method = kernel.decide(i, j, scratch))
                    ensure(cop.copositive && *method == cop.method, "integer kernel agrees with GMP");
                // A itself is not listed: the checker recomputes it from the law.
                out.evidence = Json{{"piece_a", name(i)}, {"piece_b", name(j)}, {"certificate", certificate_json(cop)}};
            }
            if (!cop.copositive) {
                out.witness = std::move(cop.witness);
                out.A = std::move(A);
            }
        } catch (const LimitExceeded& e) {
            out.limit = e;
        }
    };

    // The pairs [begin, end) in order, in sub-blocks decided by `jobs` threads and read in order:
    // counts and evidence go to `checks`, `counts` and `pairs`; the first pair that is not
    // copositive gives the witness, the first beyond a limit throws it.
    const std::size_t jobs = std::max<std::size_t>(1, limits_.jobs);
    // Blocks grow from 64 pairs (a refuted law is usually refuted early: the first block need
    // not decide thousands of pairs past its witness) to 1024, or 4096 per thread. The outcome is
    // read in order and does not depend on the blocks.
    const std::size_t full_block = jobs == 1 ? 1024 : 4096 * jobs;
    std::vector<PairOutcome> outcomes;
    std::vector<PairKernel::Scratch> scratch(jobs);
    auto run_range = [&](std::size_t begin, std::size_t end, std::size_t& checks, std::size_t (&counts)[4],
                         Json& pairs) -> std::optional<Json> {
        std::size_t block = std::min<std::size_t>(64, full_block);
        for (std::size_t start = begin; start < end; start += block, block = std::min(full_block, block * 4)) {
            report_progress("nonexpansive", start, total);
            const std::size_t count = std::min(block, end - start);
            outcomes.assign(count, PairOutcome{});
            if (jobs == 1) {
                for (std::size_t k = 0; k < count; ++k)
                    decide_pair(start + k, scratch[0], outcomes[k]);
            } else {
                // Thread t takes the pairs t, t + jobs, ... of the block; results land in place.
                // (Each outcome reset first: run_shares may run a share again, parallel.hpp.)
                run_shares(jobs, [&](std::size_t t) {
                    for (std::size_t k = t; k < count; k += jobs) {
                        outcomes[k] = PairOutcome{};
                        decide_pair(start + k, scratch[t], outcomes[k]);
                    }
                });
            }
            for (std::size_t k = 0; k < count; ++k) {
                PairOutcome& r = outcomes[k];
                if (r.limit)
                    throw *r.limit;
                checks += r.checks;
                ++counts[static_cast<int>(r.method)];
                if (limits_.evidence)
                    pairs.push_back(std::move(r.evidence));
                if (r.copositive)
                    continue;
                const std::size_t i = firsts[(start + k) / P], j = (start + k) % P;
                const Vector z = interior_witness(r.A, r.witness);
                const Vector s(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(c_));
                const Vector t(z.begin() + static_cast<std::ptrdiff_t>(c_), z.end());
                return pair_witness(i, j, pieces_[i].R * s, pieces_[j].R * t);
            }
        }
        return std::nullopt;
    };

    if (limits_.shard_count <= 1) {
        Json pairs = Json::array();
        std::optional<Json> witness = run_range(0, total, o.checks, by_method, pairs);
        if (limits_.evidence)
            o.data["pairs"] = std::move(pairs);
        o.method = method_summary(by_method);
        if (witness)
            return refute(o, std::move(*witness));
        if (fan_limit)
            throw *fan_limit;
        return o;
    }
    // One shard (--shard K/N, shard.hpp): the blocks b = K-1, K-1+N, ... of B = --shard-block
    // pairs, each with its own counts and evidence, until one fails or reaches a limit (the
    // later blocks cannot come first in the merged order). The slice is undecided when a block
    // stopped at a limit, refuted when one failed.
    const std::size_t B = std::max<std::size_t>(1, limits_.shard_block_pairs);
    o.data.erase("pairs");
    o.data["slice"] = Json{{"shard", limits_.shard_index + 1}, {"of", limits_.shard_count},
                           {"block_pairs", B}, {"pairs", total},
                           {"method_suffix", by_symmetries()}};
    o.data["blocks"] = Json::array();
    const std::size_t all_blocks = (total + B - 1) / B;
    std::size_t mine = 0;
    for (std::size_t b = limits_.shard_index; b < all_blocks; b += limits_.shard_count)
        ++mine;
    // The slice's own method line (the merged certificate's is recomputed by the checker).
    auto slice_method = [&] {
        return method_summary(by_method) + "; shard " + std::to_string(limits_.shard_index + 1) + "/" +
               std::to_string(limits_.shard_count) + ": " + std::to_string(o.data["blocks"].size()) + " of its " +
               std::to_string(mine) + " pair blocks (" + std::to_string(all_blocks) + " in all)";
    };
    for (std::size_t b = limits_.shard_index; b * B < total; b += limits_.shard_count) {
        std::size_t checks = 0, counts[4] = {0, 0, 0, 0};
        Json entry = Json{{"block", b}};
        Json pairs = Json::array();
        std::optional<Json> witness;
        std::optional<LimitExceeded> limit;
        try {
            witness = run_range(b * B, std::min(total, (b + 1) * B), checks, counts, pairs);
        } catch (const LimitExceeded& e) {
            limit = e;
        }
        for (int m = 0; m < 4; ++m)
            by_method[m] += counts[m];
        o.checks += checks;
        entry["checks"] = checks;
        entry["by_method"] = Json{counts[0], counts[1], counts[2], counts[3]};
        if (limits_.evidence)
            entry["pairs"] = std::move(pairs);
        if (limit)
            entry["limit"] = std::string(limit->what()) + " (raise it with " + limit->option + ")";
        if (witness)
            entry["counterexample"] = *witness;
        o.data["blocks"].push_back(std::move(entry));
        o.method = slice_method();
        if (limit) {
            o.limit = std::string(limit->what()) + " (raise it with " + limit->option + ")";
            return o;
        }
        if (witness)
            return refute(o, std::move(*witness));
    }
    o.method = slice_method();
    if (fan_limit) {
        // After every pair (a failing pair of any shard comes first when merged).
        o.data["fan_limit"] = std::string(fan_limit->what()) + " (raise it with " + fan_limit->option + ")";
        o.limit = o.data["fan_limit"].get<std::string>();
    }
    return o;
}

std::string Prover::method_summary(const std::size_t (&by_method)[4]) {
    std::string s = "copositive pair forms: " + std::to_string(by_method[0]) + " A>=0, " +
                    std::to_string(by_method[1]) + " PSD, " + std::to_string(by_method[2]) + " PSD+N, " +
                    std::to_string(by_method[3]) + " KKT";
    return s + by_symmetries();
}

} // namespace impactcert::detail
