// SPDX-License-Identifier: GPL-3.0-or-later
// The certificate's "worst_case" (proofs/README.md, "The exact worst case of a law"), re-checked
// with the checker's own polynomials: every face polynomial recomputed by Faddeev-LeVerrier (the
// prover interpolates), roots counted by Sturm sequences written here again.
#include "checker.hpp"

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace impactcert_check::detail {

namespace {

using Poly = std::vector<Q>; // constant term first, no zero leading coefficient

Poly trimmed(Poly p) {
    while (!p.empty() && sgn(p.back()) == 0)
        p.pop_back();
    return p;
}

Q value_at(const Poly& p, const Q& x) {
    Q v = 0;
    for (auto it = p.rbegin(); it != p.rend(); ++it)
        v = v * x + *it;
    return v;
}

Poly remainder(Poly a, const Poly& b) {
    while (a.size() >= b.size() && !a.empty()) {
        const Q t = a.back() / b.back();
        const std::size_t shift = a.size() - b.size();
        for (std::size_t j = 0; j < b.size(); ++j)
            a[shift + j] -= t * b[j];
        a.pop_back(); // now zero
        a = trimmed(a);
    }
    return a;
}

Poly quotient(Poly a, const Poly& b) {
    Poly q(a.size() >= b.size() ? a.size() - b.size() + 1 : 0, Q(0));
    while (a.size() >= b.size() && !a.empty()) {
        const Q t = a.back() / b.back();
        const std::size_t shift = a.size() - b.size();
        q[shift] = t;
        for (std::size_t j = 0; j < b.size(); ++j)
            a[shift + j] -= t * b[j];
        a.pop_back();
        a = trimmed(a);
    }
    return trimmed(q);
}

Poly derived(const Poly& p) {
    Poly d;
    for (std::size_t i = 1; i < p.size(); ++i)
        d.push_back(Q(static_cast<long>(i)) * p[i]);
    return trimmed(d);
}

Poly common_divisor(Poly a, Poly b) {
    while (!b.empty()) {
        Poly r = remainder(a, b);
        a = std::move(b);
        b = std::move(r);
    }
    if (!a.empty()) {
        const Q lead = a.back();
        for (auto& x : a)
            x /= lead;
    }
    return a;
}

Poly squarefree(const Poly& p) {
    if (p.size() <= 2)
        return p;
    return quotient(p, common_divisor(p, derived(p)));
}

std::vector<Poly> sturm(const Poly& p) {
    std::vector<Poly> s{squarefree(p)};
    s.push_back(derived(s[0]));
    while (!s.back().empty()) {
        Poly r = remainder(s[s.size() - 2], s.back());
        for (auto& x : r)
            x = -x;
        s.push_back(std::move(r));
    }
    s.pop_back();
    return s;
}

std::size_t sign_changes(const std::vector<int>& signs) {
    std::size_t n = 0;
    int last = 0;
    for (int v : signs)
        if (v != 0) {
            n += last != 0 && v != last;
            last = v;
        }
    return n;
}

std::size_t changes_at(const std::vector<Poly>& s, const Q& x) {
    std::vector<int> v;
    for (const auto& p : s)
        v.push_back(sgn(value_at(p, x)));
    return sign_changes(v);
}

// Distinct real roots in [lo, hi] (lo <= hi), p not zero.
std::size_t roots_in(const Poly& p, const Q& lo, const Q& hi) {
    const auto s = sturm(p);
    const std::size_t at_lo = sgn(value_at(s[0], lo)) == 0 ? 1 : 0;
    if (lo == hi)
        return at_lo;
    return changes_at(s, lo) - changes_at(s, hi) + at_lo;
}

std::size_t roots_above(const Poly& p, const Q& lo) {
    const auto s = sturm(p);
    std::vector<int> at_infinity;
    for (const auto& q : s)
        at_infinity.push_back(q.empty() ? 0 : sgn(q.back()));
    return changes_at(s, lo) - sign_changes(at_infinity);
}

// det(P - x N) = det(N) det(A - x I), A = N^-1 P, with det(x I - A) by Faddeev-LeVerrier.
Poly pencil_polynomial(const Mat& P, const Mat& N, const std::string& path) {
    const std::size_t k = P.size();
    Mat N_inv;
    require(invert(N, N_inv), path, "the metric restricted to a face is singular");
    const Mat A = mul(N_inv, P);
    std::vector<Q> c(k + 1, Q(0)); // det(x I - A) = sum c_i x^i
    c[k] = 1;
    Mat Mk = zeros(k, k);
    for (std::size_t i = 1; i <= k; ++i) {
        Mat AM = mul(A, Mk);
        for (std::size_t r = 0; r < k; ++r)
            AM[r][r] += c[k - i + 1];
        Mk = AM;
        const Mat AMk = mul(A, Mk);
        Q trace = 0;
        for (std::size_t r = 0; r < k; ++r)
            trace += AMk[r][r];
        c[k - i] = -trace / Q(static_cast<long>(i));
    }
    const Q scale = det(N) * (k % 2 == 0 ? Q(1) : Q(-1));
    Poly out;
    for (const auto& x : c)
        out.push_back(scale * x);
    return trimmed(out);
}

Mat restricted(const Mat& a, const std::vector<std::size_t>& idx) {
    Mat s = zeros(idx.size(), idx.size());
    for (std::size_t i = 0; i < idx.size(); ++i)
        for (std::size_t j = 0; j < idx.size(); ++j)
            s[i][j] = a[idx[i]][idx[j]];
    return s;
}

Poly poly_of(const Json& j, const std::string& path) {
    if (!j.is_array() || j.empty())
        malformed(path, "expected a polynomial: an array of rationals, constant term first");
    Poly p;
    for (std::size_t i = 0; i < j.size(); ++i)
        p.push_back(rat(j[i], at(path, i)));
    require(sgn(p.back()) != 0, path, "the leading coefficient is zero");
    return p;
}

// 10^e as a rational (e of either sign).
Q pow10(long e) {
    mpz_class p;
    mpz_ui_pow_ui(p.get_mpz_t(), 10, static_cast<unsigned long>(e < 0 ? -e : e));
    return e < 0 ? Q(1) / Q(p) : Q(p);
}

// The value's "decimal" (docs/formats.md): its decimal correctly rounded to 17 significant
// digits (ties away from zero), "~" first exactly when that is not the value itself. Read here
// as a number d; then the value (the only root of `sqf` in [lo, hi], or `exact`) must lie within
// half a unit of d's 17th significant digit (on the side towards zero of a power of ten, the
// unit of the decade below), and equal d exactly when there is no "~".
void check_decimal(const std::string& text, const Poly& sqf, const Q& lo, const Q& hi, const Q* exact,
                   const std::string& path) {
    std::size_t i = 0;
    const bool rounded = text.size() > i && text[i] == '~';
    i += rounded;
    const bool negative = text.size() > i && text[i] == '-';
    i += negative;
    std::string digits, frac;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9')
        digits += text[i++];
    if (i < text.size() && text[i] == '.') {
        ++i;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9')
            frac += text[i++];
        require(!frac.empty(), path, "is not a decimal number");
    }
    long exponent = 0;
    if (i < text.size() && text[i] == 'e') {
        ++i;
        require(i < text.size() && (text[i] == '+' || text[i] == '-'), path, "is not a decimal number");
        const bool neg_e = text[i++] == '-';
        std::string e;
        while (i < text.size() && text[i] >= '0' && text[i] <= '9' && e.size() < 6)
            e += text[i++];
        require(!e.empty(), path, "is not a decimal number");
        exponent = std::stol(e) * (neg_e ? -1 : 1);
    }
    require(!digits.empty() && i == text.size(), path, "is not a decimal number (expected [~][-]D[.D][e+-D])");
    std::string all = digits + frac;
    const std::size_t first = all.find_first_not_of('0');
    const std::size_t significant = first == std::string::npos ? 0 : all.size() - first;
    require(significant <= 17, path, "has more than 17 significant digits");
    // Base 10 explicitly: mpz_class reads a leading 0 as octal ("0.11" would be 9/100).
    const Q d = Q(mpz_class(all.empty() ? "0" : all, 10)) * pow10(exponent - static_cast<long>(frac.size())) * (negative ? -1 : 1);
    // The value is d exactly, or (with "~") within half a unit of d's last place.
    const bool equal = exact ? *exact == d : (lo <= d && d <= hi && sgn(value_at(sqf, d)) == 0);
    if (!rounded) {
        require(equal, path, "is not the value (a rounded decimal starts with ~)");
        return;
    }
    require(!equal, path, "is the value exactly: it must not start with ~");
    require(sgn(d) != 0, path, "~0 is not a 17-digit decimal of a non-zero value");
    Q ad = abs(d);
    long e10 = static_cast<long>(all.size() - first) - 1 + exponent - static_cast<long>(frac.size()); // 10^e10 <= |d|
    while (pow10(e10) > ad)
        --e10;
    while (pow10(e10 + 1) <= ad)
        ++e10;
    const Q unit = pow10(e10 - 16);
    const Q below = ad == pow10(e10) ? unit / 10 : unit; // towards zero of a power of ten: the decade below
    const Q down = negative ? unit : below, up = negative ? below : unit;
    const Q a = d - down / 2, b = d + up / 2;
    if (exact) {
        require(a <= *exact && *exact <= b, path, "is not the value rounded to 17 significant digits");
        // A tie rounds away from zero.
        const Q half = (*exact > d ? up : down) / 2;
        require(abs(*exact - d) != half || abs(d) > abs(*exact), path, "a tie is rounded away from zero");
        return;
    }
    const Q l = std::max(lo, a), h = std::min(hi, b);
    require(l <= h && roots_in(sqf, l, h) == 1, path, "is not the value rounded to 17 significant digits");
    // A tie rounds away from zero: the value must not be the end of [a, b] away from zero.
    const Q far = sgn(d) > 0 ? b : a;
    require(!(lo <= far && far <= hi && sgn(value_at(sqf, far)) == 0), path, "a tie is rounded away from zero");
}

struct Checked {
    Poly square_free;
    Q lower, upper;
    Vec point;
};

// A value equal to or below the top one: its interval ends below the top's, or the two share
// their one root (a common root of both polynomials inside both intervals).
bool at_most(const Checked& a, const Checked& top) {
    if (a.upper <= top.lower)
        return true;
    const Q lo = std::max(a.lower, top.lower), hi = std::min(a.upper, top.upper);
    return lo <= hi && roots_in(common_divisor(a.square_free, top.square_free), lo, hi) == 1;
}

void check_bound(const Law& law, const Json& b, const std::string& path, bool energy, const Limits& limits) {
    expect_keys(b, path, {"status"}, {"limit", "value", "piece", "point", "direction", "pieces"});
    const std::string status = str(field(b, path, "status"), at(path, "status"));
    if (status == "undecided") {
        // Only what the prover can reach (src/prover/worst_case.cpp): the energy ratio stops at its first
        // piece when the law's 2^c - 1 faces exceed --max-faces N; either bound stops when the
        // pieces' values are not separated at the prover's last precision (no option raises it).
        expect_keys(b, path, {"status", "limit"});
        const std::string limit = str(field(b, path, "limit"), at(path, "limit"));
        const std::string separation = "the pieces' values were not separated with intervals of 4096 bits "
                                       "(a bound of the prover, no option raises it)";
        if (limit == separation)
            return;
        require(energy, at(path, "limit"), "is not a limit the prover can reach for the Lipschitz constant");
        const std::string head = "the worst case of piece " + law.pieces.front().name + " needs 2^" +
                                 std::to_string(law.c) + " - 1 faces (--max-faces ";
        require(limit.size() > head.size() + 1 && limit.compare(0, head.size(), head) == 0 && limit.back() == ')',
                at(path, "limit"), "is not a limit the prover can reach for this law (expected \"" + head + "N)\")");
        const std::string n = limit.substr(head.size(), limit.size() - head.size() - 1);
        require(!n.empty() && n.size() <= 19 && n.find_first_not_of("0123456789") == std::string::npos &&
                    (n.size() == 1 || n[0] != '0'),
                at(path, "limit"), "names no --max-faces value");
        const unsigned long long max_faces = std::stoull(n);
        require(law.c >= 63 || (1ULL << law.c) - 1 > max_faces, at(path, "limit"),
                "the law's pieces have 2^" + std::to_string(law.c) + " - 1 faces, within --max-faces " + n +
                    ": the prover decides the worst case");
        return;
    }
    require(status == "decided", at(path, "status"), "expected \"decided\" or \"undecided\"");
    const char* where = energy ? "point" : "direction";
    expect_keys(b, path, {"status", "value", "piece", where, "pieces"});
    const Json& pieces = field(b, path, "pieces");
    require(pieces.is_array() && pieces.size() == law.pieces.size(), at(path, "pieces"),
            "expected one entry per piece of the law, in order");
    const Mat& H = law.H;
    const std::size_t c = law.c;
    std::vector<Checked> checked;
    for (std::size_t i = 0; i < law.pieces.size(); ++i) {
        const std::string pp = at(at(path, "pieces"), i);
        const Json& e = pieces[i];
        const Piece& pc = law.pieces[i];
        if (energy)
            expect_keys(e, pp, {"piece", "face", "polynomial", "lower", "upper", "point", "certificate"});
        else
            expect_keys(e, pp, {"piece", "polynomial", "lower", "upper", "direction"});
        require(str(field(e, pp, "piece"), at(pp, "piece")) == pc.name, at(pp, "piece"), "expected \"" + pc.name + "\"");
        Checked k;
        k.lower = rat(field(e, pp, "lower"), at(pp, "lower"));
        k.upper = rat(field(e, pp, "upper"), at(pp, "upper"));
        require(k.lower <= k.upper, at(pp, "upper"), "is below the lower end");
        k.point = vec(field(e, pp, where), at(pp, where));
        require(k.point.size() == c, at(pp, where), "expected " + std::to_string(c) + " entries");
        require(!std::all_of(k.point.begin(), k.point.end(), [](const Q& x) { return sgn(x) == 0; }), at(pp, where), "is zero");
        const Vec image = mul(pc.Q_, k.point);
        // The lower end is the ratio attained at the point (a direction, for the Lipschitz bound).
        require(form(H, image) / form(H, k.point) == k.lower, at(pp, "lower"), "is not the ratio at the " + std::string(where));
        const Poly given = poly_of(field(e, pp, "polynomial"), at(pp, "polynomial"));
        if (energy) {
            require(nonneg(mul(pc.R_inv, k.point)), at(pp, "point"), "is not in the piece's cone");
            // Upper end: upper N - P copositive, N = R^T H R, P = R^T Q^T H Q R.
            const Mat N = mul(tr(pc.R), mul(H, pc.R));
            const Mat P = mul(tr(pc.R), mul(tr(pc.Q_), mul(H, mul(pc.Q_, pc.R))));
            Mat B = N;
            for (std::size_t r = 0; r < c; ++r)
                for (std::size_t s = 0; s < c; ++s)
                    B[r][s] = k.upper * N[r][s] - P[r][s];
            require(check_copositive_evidence(B, field(e, pp, "certificate"), at(pp, "certificate"), limits.max_faces),
                    at(pp, "certificate"), "does not show upper N - P copositive");
            // The face and its polynomial; then every face: no other root in [lower, upper].
            const Json& face = field(e, pp, "face");
            if (!face.is_array() || face.empty() || face.size() > c)
                malformed(at(pp, "face"), "expected rays 1..c, increasing");
            std::vector<std::size_t> idx;
            for (std::size_t t = 0; t < face.size(); ++t) {
                const std::size_t r = natural(face[t], at(at(pp, "face"), t));
                require(r >= 1 && r <= c && (idx.empty() || r - 1 > idx.back()), at(at(pp, "face"), t), "expected rays 1..c, increasing");
                idx.push_back(r - 1);
            }
            require(given == pencil_polynomial(restricted(P, idx), restricted(N, idx), pp), at(pp, "polynomial"),
                    "is not det(P_JJ - x N_JJ) of the face");
            k.square_free = squarefree(given);
            require(roots_in(k.square_free, k.lower, k.upper) == 1, at(pp, "polynomial"), "has not exactly one root in [lower, upper]");
            if (c >= 63 || (std::size_t{1} << c) - 1 > limits.max_faces)
                undecided("--max-faces", pp, "the faces of the piece exceed --max-faces");
            for (std::size_t mask = 1; mask < (std::size_t{1} << c); ++mask) {
                std::vector<std::size_t> other;
                for (std::size_t r = 0; r < c; ++r)
                    if (mask >> r & 1)
                        other.push_back(r);
                const Poly q = squarefree(pencil_polynomial(restricted(P, other), restricted(N, other), pp));
                const std::size_t n = roots_in(q, k.lower, k.upper);
                require(n == 0 || (n == 1 && roots_in(common_divisor(q, k.square_free), k.lower, k.upper) == 1), pp,
                        "another face's polynomial has a different root in [lower, upper] (face mask " + std::to_string(mask) + ")");
            }
        } else {
            const Mat K = mul(tr(pc.Q_), mul(H, pc.Q_));
            require(given == pencil_polynomial(K, H, pp), at(pp, "polynomial"), "is not det(Q^T H Q - x H)");
            k.square_free = squarefree(given);
            require(roots_in(k.square_free, k.lower, k.upper) == 1, at(pp, "polynomial"), "has not exactly one root in [lower, upper]");
            require(roots_above(k.square_free, k.upper) == 0, at(pp, "upper"), "a larger root lies above it");
        }
        checked.push_back(std::move(k));
    }
    // The top piece and the value.
    const std::string top_name = str(field(b, path, "piece"), at(path, "piece"));
    const auto it = law.piece_index.find(top_name);
    require(it != law.piece_index.end(), at(path, "piece"), "names no piece of the law");
    const Checked& top = checked[it->second];
    require(vec(field(b, path, where), at(path, where)) == top.point, at(path, where), "is not the top piece's");
    for (std::size_t i = 0; i < checked.size(); ++i)
        require(at_most(checked[i], top), at(at(path, "pieces"), i), "its value is not shown at most the top piece's");
    const std::string vp = at(path, "value");
    const Json& value = field(b, path, "value");
    expect_keys(value, vp, {"polynomial", "interval", "decimal"}, {"exact"});
    const std::string decimal = str(field(value, vp, "decimal"), at(vp, "decimal"));
    const Vec iv = vec(field(value, vp, "interval"), at(vp, "interval"));
    require(iv.size() == 2 && iv[0] == top.lower && iv[1] == top.upper, at(vp, "interval"), "is not the top piece's [lower, upper]");
    const Poly vpoly = poly_of(field(value, vp, "polynomial"), at(vp, "polynomial"));
    require(roots_in(vpoly, iv[0], iv[1]) == 1 && roots_in(common_divisor(squarefree(vpoly), top.square_free), iv[0], iv[1]) == 1,
            at(vp, "polynomial"), "does not have the top piece's root as its only root in the interval");
    std::optional<Q> exact;
    if (value.contains("exact")) {
        const Q x = rat(value.at("exact"), at(vp, "exact"));
        require(iv[0] <= x && x <= iv[1] && sgn(value_at(vpoly, x)) == 0, at(vp, "exact"), "is not the root");
        exact = x;
    }
    check_decimal(decimal, top.square_free, iv[0], iv[1], exact ? &*exact : nullptr, at(vp, "decimal"));
}

} // namespace

void check_worst_case(const Law& law, const Json& w, bool continuous_tiling, const Limits& limits) {
    const std::string path = "$.worst_case";
    expect_keys(w, path, {"energy_ratio"}, {"lipschitz_squared"});
    check_bound(law, field(w, path, "energy_ratio"), at(path, "energy_ratio"), true, limits);
    require(w.contains("lipschitz_squared") == continuous_tiling, path,
            continuous_tiling ? "the law is a continuous tiling: lipschitz_squared is missing"
                              : "lipschitz_squared needs fan and P1 proved");
    if (continuous_tiling)
        check_bound(law, w.at("lipschitz_squared"), at(path, "lipschitz_squared"), false, limits);
}

} // namespace impactcert_check::detail
