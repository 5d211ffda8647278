// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/copositivity.hpp"

#include "exact/int_kernel.hpp"

#include <optional>
#include <stdexcept>

namespace impactcert {

const char* to_string(CopositivityMethod m) {
    switch (m) {
    case CopositivityMethod::nonnegative_entries: return "nonnegative-entries";
    case CopositivityMethod::psd: return "psd-ldlt";
    case CopositivityMethod::psd_plus_nonnegative: return "psd-plus-nonnegative";
    case CopositivityMethod::kkt_enumeration: return "kkt-enumeration";
    }
    return "?";
}

namespace {
void require_symmetric(const Matrix& A) {
    if (A.rows() != A.cols())
        throw std::logic_error("quadratic form of a non-square matrix");
    for (std::size_t i = 0; i < A.rows(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (A(i, j) != A(j, i))
                throw std::logic_error("quadratic form of a non-symmetric matrix");
}
} // namespace

// Symmetric elimination kept as a congruence: C = X^T A X with X unit upper triangular, so a
// negative diagonal entry of C, or a zero one with a non-zero off-diagonal entry, yields an exact
// negative direction of A built from the columns of X.
LdlResult ldl_psd(const Matrix& A) {
    require_symmetric(A);
    const std::size_t n = A.rows();
    Matrix C = A, X = Matrix::identity(n);
    LdlResult out;
    out.L = Matrix::identity(n);
    out.D = Vector(n, Rational(0));
    for (std::size_t k = 0; k < n; ++k) {
        const Rational p = C(k, k);
        switch (sign_of(p)) {
        case Sign::negative:
            out.witness = X.column(k); // X_k^T A X_k = C_kk < 0
            return out;
        case Sign::zero:
            for (std::size_t j = k + 1; j < n; ++j) {
                if (sign_of(C(k, j)) == Sign::zero)
                    continue;
                // (t X_k + X_j)^T A (t X_k + X_j) = 2 t C_kj + C_jj < 0 for this t.
                const Rational t = -(abs_of(C(j, j)) + 1) / C(k, j);
                out.witness = t * X.column(k) + X.column(j);
                return out;
            }
            break; // zero row: nothing to eliminate, L column stays e_k
        case Sign::positive: {
            const Vector pivot_row = C.row(k);
            for (std::size_t j = k + 1; j < n; ++j) {
                if (sign_of(pivot_row[j]) == Sign::zero)
                    continue;
                const Rational m = pivot_row[j] / p;
                out.L(j, k) = m;
                for (std::size_t i = 0; i < n; ++i)
                    X(i, j) -= m * X(i, k);
                for (std::size_t l = k + 1; l < n; ++l)
                    C(j, l) -= m * pivot_row[l];
                C(j, k) = 0;
                C(k, j) = 0;
            }
            break;
        }
        }
        out.D[k] = p;
    }
    out.psd = true;
    return out;
}

namespace {

bool all_nonnegative(const Matrix& A) {
    for (std::size_t i = 0; i < A.rows(); ++i)
        for (std::size_t j = 0; j < A.cols(); ++j)
            if (sign_of(A(i, j)) == Sign::negative)
                return false;
    return true;
}

// One face of the KKT enumeration in machine integers (proofs/README.md, "Integer kernels",
// Lemma K3): the bordered system [[a_JJ, 1], [1^T, 0]] [x; y'] = [0; 1] of a = den A, reduced by
// fraction-free Gauss-Jordan elimination to det I [x; y'] = num. Every division is checked to be
// exact and every value to fit int64; when one is not, the face is solved over GMP instead.
intk::Elimination solve_face_int(const intk::IntMatrix& a, const std::vector<std::size_t>& J,
                                 std::vector<intk::i64>& m, intk::i64& det) {
    const std::size_t k = J.size(), n = k + 1, w = n + 1; // n x (n + 1), the last column the rhs
    m.assign(n * w, 0);
    for (std::size_t r = 0; r < k; ++r) {
        for (std::size_t c = 0; c < k; ++c)
            m[r * w + c] = a(J[r], J[c]);
        m[r * w + k] = 1;
        m[k * w + r] = 1;
    }
    m[k * w + n] = 1;
    return intk::gauss_jordan(m, n, w, det);
}

// The same elimination over GMP integers, for the faces whose minors leave int64: no gcd per
// operation, and the scratch integers keep their limbs from face to face.
class MpzFaces {
  public:
    explicit MpzFaces(const Matrix& A) : n_(A.rows()), a_(n_ * n_), m_((n_ + 1) * (n_ + 2)) {
        mpz_init_set_ui(den_, 1);
        mpz_inits(t_, prev_, nullptr);
        for (std::size_t i = 0; i < n_ * n_; ++i)
            mpz_lcm(den_, den_, mpq_denref(A(i / n_, i % n_).mpq()));
        for (std::size_t i = 0; i < n_ * n_; ++i) {
            mpz_divexact(a_[i].z, den_, mpq_denref(A(i / n_, i % n_).mpq()));
            mpz_mul(a_[i].z, a_[i].z, mpq_numref(A(i / n_, i % n_).mpq()));
        }
    }
    ~MpzFaces() { mpz_clears(den_, t_, prev_, nullptr); }
    MpzFaces(const MpzFaces&) = delete;
    MpzFaces& operator=(const MpzFaces&) = delete;

    // Solves the face J; false when its system is singular. Then x_a = num(a) / det() and
    // mu = -num(k) / (det() den()).
    bool solve(const std::vector<std::size_t>& J) {
        const std::size_t k = J.size(), n = k + 1;
        w_ = n + 1;
        for (std::size_t r = 0; r < n; ++r)
            for (std::size_t c = 0; c < w_; ++c)
                mpz_set_ui(at(r, c), 0);
        for (std::size_t r = 0; r < k; ++r) {
            for (std::size_t c = 0; c < k; ++c)
                mpz_set(at(r, c), a_[J[r] * n_ + J[c]].z);
            mpz_set_ui(at(r, k), 1);
            mpz_set_ui(at(k, r), 1);
        }
        mpz_set_ui(at(k, n), 1);
        mpz_set_ui(prev_, 1);
        for (std::size_t col = 0; col < n; ++col) {
            std::size_t pivot = col;
            while (pivot < n && mpz_sgn(at(pivot, col)) == 0)
                ++pivot;
            if (pivot == n)
                return false;
            if (pivot != col)
                for (std::size_t j = 0; j < w_; ++j)
                    mpz_swap(at(pivot, j), at(col, j));
            for (std::size_t r = 0; r < n; ++r) {
                if (r == col)
                    continue;
                for (std::size_t j = 0; j < w_; ++j) {
                    if (j == col)
                        continue;
                    mpz_mul(t_, at(col, col), at(r, j));
                    mpz_submul(t_, at(r, col), at(col, j));
                    // Exact (the entries are minors, Lemma K3); checked all the same.
                    mpz_tdiv_qr(at(r, j), t_, t_, prev_);
                    if (mpz_sgn(t_) != 0)
                        throw std::logic_error("fraction-free elimination: inexact division");
                }
                mpz_set_ui(at(r, col), 0);
            }
            mpz_set(prev_, at(col, col));
        }
        return true;
    }
    mpz_srcptr num(std::size_t a) const { return m_[a * w_ + w_ - 1].z; }
    mpz_srcptr det() const { return prev_; }
    mpz_srcptr den() const { return den_; }

  private:
    struct Z {
        mpz_t z;
        Z() { mpz_init(z); }
        ~Z() { mpz_clear(z); }
        Z(const Z&) = delete;
        Z& operator=(const Z&) = delete;
    };
    std::size_t n_, w_ = 0;
    std::vector<Z> a_, m_;
    mpz_t den_, t_, prev_;
    mpz_ptr at(std::size_t r, std::size_t c) { return m_[r * w_ + c].z; }
};

} // namespace

CopositivityResult decide_copositivity(const Matrix& A, std::size_t max_faces, bool integer_kernel) {
    require_symmetric(A);
    const std::size_t n = A.rows();
    CopositivityResult out;
    if (all_nonnegative(A)) {
        out.copositive = true;
        out.method = CopositivityMethod::nonnegative_entries;
        return out;
    }
    if (auto ldl = ldl_psd(A); ldl.psd) {
        out.copositive = true;
        out.method = CopositivityMethod::psd;
        out.ldl = std::move(ldl);
        return out;
    }
    Matrix N(n, n), P = A;
    bool any_positive_off_diagonal = false;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (i != j && sign_of(A(i, j)) == Sign::positive) {
                N(i, j) = A(i, j);
                P(i, j) = 0;
                any_positive_off_diagonal = true;
            }
    if (any_positive_off_diagonal) {
        if (auto ldl = ldl_psd(P); ldl.psd) {
            out.copositive = true;
            out.method = CopositivityMethod::psd_plus_nonnegative;
            out.ldl = std::move(ldl);
            out.N = std::move(N);
            return out;
        }
    }

    // Complete decision: the minimum of z^T A z over the simplex is the least KKT candidate.
    out.method = CopositivityMethod::kkt_enumeration;
    bool have_minimum = false;
    // 2^n - 1 faces: refuse before exceeding the limit (and before 1 << n could overflow).
    if (n >= 63 || (std::size_t{1} << n) - 1 > max_faces)
        throw LimitExceeded("copositivity of a " + std::to_string(n) + "x" + std::to_string(n) +
                                " form needs the KKT enumeration of 2^" + std::to_string(n) +
                                " - 1 faces, more than " + std::to_string(max_faces),
                            "--max-faces");
    const std::size_t subsets = std::size_t{1} << n;
    const auto A_int = integer_kernel ? intk::to_int(A) : std::nullopt;
    std::vector<intk::i64> scratch;
    std::optional<MpzFaces> big; // made at the first face that leaves int64
    for (std::size_t mask = 1; mask < subsets; ++mask) {
        std::vector<std::size_t> J;
        for (std::size_t i = 0; i < n; ++i)
            if (mask & (std::size_t{1} << i))
                J.push_back(i);
        const std::size_t k = J.size();
        ++out.faces;
        KktCandidate cand;
        cand.support = J;
        bool fast = false;
        if (A_int) {
            intk::i64 det = 0;
            const auto f = solve_face_int(*A_int, J, scratch, det);
            if (f == intk::Elimination::singular)
                continue;
            if (f == intk::Elimination::solved) {
                // x = num / det (the same for a and A), y' = den y: mu = -num_k / (det den).
                fast = true;
                const std::size_t w = k + 2;
                bool positive = true; // x_a > 0: num_a != 0 with the sign of det (det != 0)
                for (std::size_t a = 0; a < k && positive; ++a)
                    positive = scratch[a * w + k + 1] != 0 && (scratch[a * w + k + 1] > 0) == (det > 0);
                if (!positive)
                    continue;
                const Rational d(det);
                for (std::size_t a = 0; a < k; ++a)
                    cand.x.push_back(Rational(scratch[a * w + k + 1]) / d);
                cand.value = -Rational(scratch[k * w + k + 1]) / (d * Rational(A_int->den));
            }
        }
        if (!fast && integer_kernel) {
            if (!big)
                big.emplace(A);
            if (!big->solve(J))
                continue;
            const int det_sign = mpz_sgn(big->det());
            bool positive = true;
            for (std::size_t a = 0; a < k && positive; ++a)
                positive = mpz_sgn(big->num(a)) == det_sign;
            if (!positive)
                continue;
            const CGAL::Gmpz d(big->det());
            for (std::size_t a = 0; a < k; ++a)
                cand.x.push_back(Rational(CGAL::Gmpz(big->num(a)), d));
            cand.value = -Rational(CGAL::Gmpz(big->num(k)), d * CGAL::Gmpz(big->den()));
        } else if (!fast) {
            // Bordered system [[A_JJ, 1], [1^T, 0]] [x; y] = [0; 1], mu = -y.
            Matrix K(k + 1, k + 1);
            for (std::size_t a = 0; a < k; ++a) {
                for (std::size_t b = 0; b < k; ++b)
                    K(a, b) = A(J[a], J[b]);
                K(a, k) = 1;
                K(k, a) = 1;
            }
            Vector rhs(k + 1, Rational(0));
            rhs[k] = 1;
            auto y = solve(K, rhs);
            if (!y)
                continue;
            bool positive = true;
            for (std::size_t a = 0; a < k && positive; ++a)
                positive = sign_of((*y)[a]) == Sign::positive;
            if (!positive)
                continue;
            cand.x.assign(y->begin(), y->begin() + static_cast<std::ptrdiff_t>(k));
            cand.value = -(*y)[k];
        }
        if (!have_minimum || cand.value < out.minimum) {
            out.minimum = cand.value;
            out.witness = Vector(n, Rational(0));
            for (std::size_t a = 0; a < k; ++a)
                out.witness[J[a]] = cand.x[a];
            have_minimum = true;
        }
        out.candidates.push_back(std::move(cand));
    }
    if (!have_minimum)
        throw std::logic_error("KKT enumeration found no candidate (impossible for a symmetric A)");
    out.copositive = sign_of(out.minimum) != Sign::negative;
    if (out.copositive)
        out.witness.clear();
    else if (bilinear(out.witness, A, out.witness) != out.minimum)
        throw std::logic_error("KKT witness does not attain its value");
    return out;
}

Vector interior_witness(const Matrix& A, const Vector& z) {
    if (sign_of(bilinear(z, A, z)) != Sign::negative)
        throw std::logic_error("interior_witness needs z^T A z < 0");
    const Vector ones(z.size(), Rational(1));
    // f(z + eps 1) -> f(z) < 0 as eps -> 0, so halving terminates.
    for (Rational eps = 1;; eps /= 2) {
        Vector moved = z + eps * ones;
        if (sign_of(bilinear(moved, A, moved)) == Sign::negative)
            return moved;
    }
}

} // namespace impactcert
