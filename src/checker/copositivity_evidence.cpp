// SPDX-License-Identifier: GPL-3.0-or-later
// Copositivity evidence: returns whether the evidence proves A copositive; rejects evidence
// that is wrong. For the KKT method the checker re-enumerates every face itself.
#include "copositivity_evidence.hpp"

#include <stdexcept>
#include <utility>
#include <vector>

namespace impactcert_check::detail {

namespace {

bool lower_unit(const Mat& L) {
    for (std::size_t i = 0; i < L.size(); ++i)
        for (std::size_t j = i; j < L.size(); ++j)
            if (L[i][j] != (i == j ? 1 : 0))
                return false;
    return true;
}

Mat ldlt(const Mat& L, const Vec& D) {
    Mat DL = zeros(D.size(), D.size());
    for (std::size_t i = 0; i < D.size(); ++i)
        DL[i][i] = D[i];
    return mul(mul(L, DL), tr(L));
}

// A matrix of the given shape (mat() has made it rectangular and non-empty).
Mat shaped(const Json& j, const std::string& path, std::size_t rows, std::size_t cols) {
    Mat m = mat(j, path);
    require(m.size() == rows && m[0].size() == cols, path,
            "expected " + std::to_string(rows) + " x " + std::to_string(cols) + ", got " + std::to_string(m.size()) +
                " x " + std::to_string(m[0].size()));
    return m;
}

// The prover's bound (src/exact/copositivity.cpp): 2^n - 1 faces, refused before the enumeration,
// and before 1 << n could overflow.
void check_face_limit(std::size_t n, std::size_t max_faces, const std::string& path) {
    if (n >= 63 || (std::size_t{1} << n) - 1 > max_faces)
        undecided("--max-faces", path,
                  "the KKT enumeration of a " + std::to_string(n) + "x" + std::to_string(n) + " form has 2^" +
                      std::to_string(n) + " - 1 faces, more than " + std::to_string(max_faces));
}

// A KKT face [[a_JJ, 1], [1^T, 0]] [x; y] = [0; 1] of the integer matrix a = d A: Bareiss's
// fraction-free forward elimination (every division exact), then back substitution over the
// rationals. The solution is the face's unique one; false when the system is singular.
bool kkt_face(const std::vector<std::vector<mpz_class>>& a, const std::vector<std::size_t>& J, Vec& x) {
    const std::size_t k = J.size(), n = k + 1;
    std::vector<std::vector<mpz_class>> m(n, std::vector<mpz_class>(n + 1, 0));
    for (std::size_t r = 0; r < k; ++r) {
        for (std::size_t c = 0; c < k; ++c)
            m[r][c] = a[J[r]][J[c]];
        m[r][k] = 1;
        m[k][r] = 1;
    }
    m[k][n] = 1;
    mpz_class prev = 1, t;
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t p = c;
        while (p < n && sgn(m[p][c]) == 0)
            ++p;
        if (p == n)
            return false;
        std::swap(m[p], m[c]);
        for (std::size_t r = c + 1; r < n; ++r) {
            for (std::size_t j = c + 1; j <= n; ++j) {
                t = m[c][c] * m[r][j] - m[r][c] * m[c][j];
                // Exact by Bareiss's theorem (the entries are minors); checked all the same.
                mpz_tdiv_qr(m[r][j].get_mpz_t(), t.get_mpz_t(), t.get_mpz_t(), prev.get_mpz_t());
                if (sgn(t) != 0)
                    throw std::logic_error("Bareiss elimination: inexact division");
            }
            m[r][c] = 0;
        }
        prev = m[c][c];
    }
    x.assign(n, Q(0));
    for (std::size_t i = n; i-- > 0;) {
        Q s = Q(m[i][n]);
        for (std::size_t j = i + 1; j < n; ++j)
            s -= Q(m[i][j]) * x[j];
        x[i] = s / Q(m[i][i]);
    }
    return true;
}

} // namespace

// L and D (keys checked by the caller) with L D L^T = B.
bool check_psd_evidence(const Mat& B, const Json& j, const std::string& path) {
    const std::size_t n = B.size();
    const Mat L = shaped(field(j, path, "L"), at(path, "L"), n, n);
    const Vec D = vec(field(j, path, "D"), at(path, "D"));
    require(D.size() == n, at(path, "D"), "L or D has the wrong size");
    require(lower_unit(L), at(path, "L"), "not unit lower triangular");
    require(nonneg(D), at(path, "D"), "negative entry in D");
    for (std::size_t k = 0; k < D.size(); ++k)
        for (std::size_t row = k + 1; row < D.size(); ++row)
            require(sgn(D[k]) != 0 || sgn(L[row][k]) == 0, at(path, "L"), "a zero pivot's column must be e_k");
    require(ldlt(L, D) == B, path, "L D L^T does not reproduce the matrix");
    return true;
}

bool check_copositive_evidence(const Mat& A, const Json& j, const std::string& path, std::size_t max_faces) {
    const std::string method = str(field(j, path, "method"), at(path, "method"));
    const std::size_t n = A.size();
    if (method == "nonnegative-entries") {
        expect_keys(j, path, {"method"});
        for (const auto& row : A)
            require(nonneg(row), path, "matrix has a negative entry");
        return true;
    }
    if (method == "psd-ldlt") {
        expect_keys(j, path, {"method", "L", "D"});
        return check_psd_evidence(A, j, path);
    }
    if (method == "psd-plus-nonnegative") {
        expect_keys(j, path, {"method", "N", "L", "D"});
        const Mat N = shaped(field(j, path, "N"), at(path, "N"), n, n);
        for (const auto& row : N)
            require(nonneg(row), at(path, "N"), "negative entry in N");
        return check_psd_evidence(sub(A, N), j, path);
    }
    if (method == "kkt-enumeration") {
        expect_keys(j, path, {"method", "candidates", "minimum"});
        const Json& cands = field(j, path, "candidates");
        if (!cands.is_array())
            malformed(at(path, "candidates"), "expected an array");
        const Q listed_minimum = rat(field(j, path, "minimum"), at(path, "minimum"));
        check_face_limit(n, max_faces, path);
        // Re-enumerate every face and compare with the listed candidates.
        std::vector<std::pair<std::vector<std::size_t>, Vec>> mine;
        Q minimum;
        bool have = false;
        // d A with d the least common denominator: the same x on every face, y scaled by d.
        mpz_class d = 1;
        for (const auto& row : A)
            for (const auto& q : row)
                mpz_lcm(d.get_mpz_t(), d.get_mpz_t(), q.get_den_mpz_t());
        std::vector<std::vector<mpz_class>> dA(n, std::vector<mpz_class>(n));
        for (std::size_t r = 0; r < n; ++r)
            for (std::size_t c = 0; c < n; ++c)
                dA[r][c] = d / A[r][c].get_den() * A[r][c].get_num();
        for (std::size_t mask = 1; mask < (std::size_t{1} << n); ++mask) {
            std::vector<std::size_t> J;
            for (std::size_t i = 0; i < n; ++i)
                if (mask >> i & 1)
                    J.push_back(i);
            Vec y;
            if (!kkt_face(dA, J, y))
                continue;
            Vec x(y.begin(), y.end() - 1);
            if (!positive(x))
                continue;
            const Q value = -y.back() / Q(d);
            if (!have || value < minimum)
                minimum = value;
            have = true;
            mine.push_back({J, x});
        }
        require(cands.size() == mine.size(), at(path, "candidates"),
                "lists " + std::to_string(cands.size()) + " KKT candidates, there are " + std::to_string(mine.size()));
        for (std::size_t k = 0; k < mine.size(); ++k) {
            const std::string cp = at(at(path, "candidates"), k);
            expect_keys(cands[k], cp, {"support", "x", "value"});
            const Json& sj = field(cands[k], cp, "support");
            if (!sj.is_array())
                malformed(at(cp, "support"), "expected an array of indices");
            std::vector<std::size_t> support;
            for (std::size_t a = 0; a < sj.size(); ++a)
                support.push_back(natural(sj[a], at(at(cp, "support"), a)));
            require(support == mine[k].first, at(cp, "support"), "not the face it should be");
            require(vec(field(cands[k], cp, "x"), at(cp, "x")) == mine[k].second, at(cp, "x"), "not the face's KKT point");
            require(rat(field(cands[k], cp, "value"), at(cp, "value")) == form(A, [&] {
                        Vec z(n, Q(0));
                        for (std::size_t a = 0; a < support.size(); ++a)
                            z[support[a]] = mine[k].second[a];
                        return z;
                    }()),
                    at(cp, "value"), "not the form's value at x");
        }
        require(have && listed_minimum == minimum, at(path, "minimum"), "not the least candidate");
        return sgn(minimum) >= 0;
    }
    malformed(at(path, "method"), "unknown method \"" + method + "\"");
}

// The canonical negative direction of a symmetric matrix (the congruence elimination of
// proofs/README.md, "Exact copositivity", step 2), or nothing when it is PSD.
std::optional<Vec> psd_witness(const Mat& A) {
    const std::size_t n = A.size();
    Mat C = A, X = eye(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Q p = C[k][k];
        if (sgn(p) < 0)
            return col(X, k);
        if (sgn(p) == 0) {
            for (std::size_t j = k + 1; j < n; ++j)
                if (sgn(C[k][j]) != 0) {
                    const Q t = -(abs(C[j][j]) + 1) / C[k][j];
                    Vec x = col(X, j);
                    for (std::size_t i = 0; i < n; ++i)
                        x[i] += t * X[i][k];
                    return x;
                }
            continue;
        }
        const Vec row = C[k];
        for (std::size_t j = k + 1; j < n; ++j) {
            if (sgn(row[j]) == 0)
                continue;
            const Q m = row[j] / p;
            for (std::size_t i = 0; i < n; ++i)
                X[i][j] -= m * X[i][k];
            for (std::size_t l = k + 1; l < n; ++l)
                C[j][l] -= m * row[l];
            C[j][k] = 0;
            C[k][j] = 0;
        }
    }
    return std::nullopt;
}

// The minimiser of a KKT certificate that evidence() has checked (so its keys, candidates
// and supports are the checker's own): the first candidate attaining the minimum, padded
// with zeros.
Vec kkt_minimiser(const Json& cert, const std::string& path, std::size_t n) {
    require(str(field(cert, path, "method"), path) == "kkt-enumeration", path,
            "the failing entry's certificate is not a KKT enumeration");
    const Json& cands = field(cert, path, "candidates");
    const Q minimum = rat(field(cert, path, "minimum"), at(path, "minimum"));
    for (std::size_t k = 0; k < cands.size(); ++k) {
        const std::string cp = at(at(path, "candidates"), k);
        if (rat(field(cands[k], cp, "value"), at(cp, "value")) != minimum)
            continue;
        Vec z(n, Q(0));
        const Vec x = vec(field(cands[k], cp, "x"), at(cp, "x"));
        const Json& support = field(cands[k], cp, "support");
        require(support.size() == x.size(), cp, "support and x differ in length");
        for (std::size_t a = 0; a < x.size(); ++a) {
            const std::size_t i = natural(support[a], at(at(cp, "support"), a));
            require(i < n, at(at(cp, "support"), a), "index out of range");
            z[i] = x[a];
        }
        return z;
    }
    reject(path, "no candidate attains the minimum");
}

// The prover's interior_witness (src/exact/copositivity.cpp): z + eps 1 for the first eps in
// 1, 1/2, 1/4, ... with f(z + eps 1) < 0, where f(x) = x^T A x and f(z) < 0. Halving one
// step at a time takes log2(1/eps) steps, which a law can make huge (Q = -(1 + 10^-10000)
// needs 33,000 halvings of 10,000-digit numbers). But g(eps) = f(z + eps 1) is a quadratic
// with g(0) < 0: when g(1) >= 0, g is negative on (0, r) and non-negative on [r, 1] for its
// least positive root r (a third sign change would need a third root). So "g(2^-k) < 0" is
// false and then true for good as k grows, and its first k is found by doubling and
// bisection: O(log k) evaluations, k bounded by the bit length of g's coefficients.
Vec moved_inside(const Mat& A, const Vec& z, const std::string& path) {
    require(sgn(form(A, z)) < 0, path, "the failing pair's KKT minimiser is not a negative point");
    auto moved = [&](unsigned long k) {
        const Q eps(mpz_class(1), mpz_class(1) << static_cast<mp_bitcnt_t>(k));
        Vec x = z;
        for (auto& v : x)
            v += eps;
        return x;
    };
    auto negative = [&](unsigned long k) { return sgn(form(A, moved(k))) < 0; };
    if (negative(0))
        return moved(0);
    unsigned long lo = 0, hi = 1; // negative(lo) is false; find a hi where it is true
    while (!negative(hi)) {
        lo = hi;
        hi *= 2;
    }
    while (hi - lo > 1) { // the first k in (lo, hi] with negative(k)
        const unsigned long mid = lo + (hi - lo) / 2;
        (negative(mid) ? hi : lo) = mid;
    }
    return moved(hi);
}

} // namespace impactcert_check::detail
