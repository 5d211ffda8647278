#include "copositivity.hpp"

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

} // namespace

CopositivityResult decide_copositivity(const Matrix& A, std::size_t max_faces) {
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
    for (std::size_t mask = 1; mask < subsets; ++mask) {
        std::vector<std::size_t> J;
        for (std::size_t i = 0; i < n; ++i)
            if (mask & (std::size_t{1} << i))
                J.push_back(i);
        const std::size_t k = J.size();
        ++out.faces;
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
        KktCandidate cand;
        cand.support = J;
        cand.x.assign(y->begin(), y->begin() + static_cast<std::ptrdiff_t>(k));
        cand.value = -(*y)[k];
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
