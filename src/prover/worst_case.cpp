// SPDX-License-Identifier: GPL-3.0-or-later
// worst_case -- proofs/README.md, "The exact worst case of a law" (Lemma W and its certificate).
#include "prover/worst_case.hpp"

#include "prover/obligations/prover.hpp"

#include <algorithm>
#include <stdexcept>

namespace impactcert {

namespace {

constexpr std::size_t kFirstBits = 64, kLastBits = 4096;

Matrix sub_matrix(const Matrix& a, const std::vector<std::size_t>& idx) {
    Matrix s(idx.size(), idx.size());
    for (std::size_t i = 0; i < idx.size(); ++i)
        for (std::size_t j = 0; j < idx.size(); ++j)
            s(i, j) = a(idx[i], idx[j]);
    return s;
}

Rational pow2(long e) {
    Rational r(1);
    const Rational two(2);
    for (long i = 0; i < (e < 0 ? -e : e); ++i)
        r = e < 0 ? r / two : r * two;
    return r;
}

// Vectors of the (approximate) eigenspace of the pencil (A, B) at the root isolated in iv, each
// with every entry > 0 after a sign change (possibly none). A rational root: the exact null space
// of A - root B (its basis vectors and their sum). Otherwise one inverse iteration step from B s
// at the interval's upper end (not a root), for several starts s (1, each unit vector, 1..k): the
// root's eigenvector dominates by the ratio of its distance to the others over the interval's
// width, unless s has no component along it (1 may be exactly another root's eigenvector), so the
// caller keeps the try of the largest ratio.
std::vector<Vector> positive_eigenvectors(const Matrix& A, const Matrix& B, const RootInterval& iv, bool any_sign = false) {
    const std::size_t k = A.rows();
    std::vector<Vector> tries;
    if (iv.lo == iv.hi) {
        const Matrix K = A - iv.lo * B;
        std::vector<Vector> rows;
        for (std::size_t i = 0; i < k; ++i)
            rows.push_back(K.row(i));
        const auto basis = null_space(rows, k);
        Vector sum(k, Rational(0));
        for (const auto& v : basis) {
            tries.push_back(v);
            sum = sum + v;
        }
        if (!basis.empty())
            tries.push_back(sum);
    } else {
        const Matrix K = A - iv.hi * B;
        std::vector<Vector> starts{Vector(k, Rational(1))};
        for (std::size_t i = 0; i < k && k > 1; ++i)
            starts.push_back(unit_vector(k, i));
        Vector ramp(k);
        for (std::size_t i = 0; i < k; ++i)
            ramp[i] = Rational(static_cast<long>(i + 1));
        starts.push_back(ramp);
        for (const auto& s : starts)
            if (auto y = solve(K, B * s))
                tries.push_back(*y);
    }
    std::vector<Vector> out;
    for (Vector v : tries) {
        if (is_zero(v))
            continue;
        Rational total(0);
        for (const auto& x : v)
            total += x;
        if (sign_of(total) == Sign::negative)
            v = Rational(-1) * v;
        if (any_sign || std::all_of(v.begin(), v.end(), [](const Rational& x) { return sign_of(x) == Sign::positive; }))
            out.push_back(std::move(v));
    }
    return out;
}

Rational width_at(std::size_t bits, const RootInterval& iv) {
    return pow2(-static_cast<long>(bits)) * (Rational(1) + abs_of(iv.hi));
}

bool below_or_equal(const PieceBound& a, const UPoly& qa, const PieceBound& top, const UPoly& qtop) {
    // value(a) <= value(top): a's interval ends below top's, or the two values are one root.
    if (a.upper <= top.lower)
        return true;
    const Rational lo = std::max(a.lower, top.lower), hi = std::min(a.upper, top.upper);
    return lo <= hi && count_roots(gcd(qa, qtop), lo, hi) == 1;
}

// The global value from the pieces' certificates, or nothing when two of them are not yet
// separated (more bits needed).
bool combine(LawBound& out, const std::vector<UPoly>& square_free_polys) {
    std::size_t top = 0;
    for (std::size_t i = 1; i < out.pieces.size(); ++i)
        if (out.pieces[i].lower > out.pieces[top].lower)
            top = i;
    for (std::size_t i = 0; i < out.pieces.size(); ++i)
        if (i != top && !below_or_equal(out.pieces[i], square_free_polys[i], out.pieces[top], square_free_polys[top]))
            return false;
    out.top = top;
    out.value.poly = square_free_polys[top];
    // A root at 0 that is not the value: divide x out (square-free: at most once).
    if (!out.value.poly.c.empty() && sign_of(out.value.poly.c[0]) == Sign::zero && sign_of(out.pieces[top].lower) == Sign::positive)
        out.value.poly.c.erase(out.value.poly.c.begin());
    out.value.lo = out.pieces[top].lower;
    out.value.hi = out.pieces[top].upper;
    out.value.exact = rational_root(out.value.poly, {out.value.lo, out.value.hi}, 256);
    out.decided = true;
    return true;
}

struct Candidate {
    std::size_t face; // index into the face list
    RootInterval iv;
};

// The certificate of one piece for the energy ratio at `bits`, or nothing (not separated yet).
std::optional<PieceBound> energy_piece(const Model& model, std::size_t p, std::size_t bits,
                                       const WorstCaseOptions& options) {
    const Piece& pc = model.pieces()[p];
    const std::size_t c = pc.R.rows();
    const Matrix P = transpose(pc.R) * transpose(pc.Q) * model.H() * pc.Q * pc.R;
    const Matrix N = transpose(pc.R) * model.H() * pc.R;
    if (c >= 63 || (std::size_t{1} << c) - 1 > options.max_faces)
        throw LimitExceeded("the worst case of piece " + pc.name + " needs 2^" + std::to_string(c) +
                                " - 1 faces (--max-faces " + std::to_string(options.max_faces) + ")",
                            "--max-faces");
    std::vector<std::vector<std::size_t>> faces;
    std::vector<UPoly> polys, free_polys;
    std::vector<Candidate> candidates;
    for (std::size_t mask = 1; mask < (std::size_t{1} << c); ++mask) {
        std::vector<std::size_t> idx;
        for (std::size_t i = 0; i < c; ++i)
            if (mask >> i & 1)
                idx.push_back(i);
        faces.push_back(idx);
        polys.push_back(pencil_determinant(sub_matrix(P, idx), sub_matrix(N, idx)));
        free_polys.push_back(square_free(polys.back()));
        for (const auto& iv : isolate(free_polys.back()))
            candidates.push_back({faces.size() - 1, iv});
    }
    // Refined first, so that the order below is the order of the roots (up to the width).
    for (auto& cand : candidates) {
        cand.iv = refine(free_polys[cand.face], cand.iv, width_at(bits, cand.iv));
        if (const auto r = rational_root(free_polys[cand.face], cand.iv, 64))
            cand.iv = {*r, *r}; // an exact eigenvector then, from the null space
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        return a.iv.hi != b.iv.hi ? a.iv.hi > b.iv.hi : a.iv.lo > b.iv.lo;
    });
    for (Candidate cand : candidates) {
        const auto& idx = faces[cand.face];
        // The try of the largest ratio; none reaching the interval: not attained inside this face
        // (its boundary has its own candidates) or not found from these starts.
        std::optional<Vector> z;
        Rational lower;
        for (const auto& y : positive_eigenvectors(sub_matrix(P, idx), sub_matrix(N, idx), cand.iv)) {
            Vector x(c, Rational(0));
            for (std::size_t i = 0; i < idx.size(); ++i)
                x[idx[i]] = y[i];
            const Rational r = bilinear(x, P, x) / bilinear(x, N, x);
            if (!z || r > lower) {
                z = std::move(x);
                lower = r;
            }
        }
        // A try far below the root (by more than the interval's width; an approximate eigenvector
        // is off by the square of it) is another root's eigenvector.
        if (!z || lower < cand.iv.lo - (cand.iv.hi - cand.iv.lo))
            continue;
        const Rational upper = cand.iv.hi;
        if (upper < lower)
            return std::nullopt; // this root is below a value attained: a larger one was missed
        auto cop = decide_copositivity(upper * N - P, options.max_faces, options.integer_kernels);
        if (!cop.copositive)
            return std::nullopt; // the supremum is above: an earlier candidate was missed
        // Every face polynomial has in [lower, upper] at most this root.
        for (std::size_t f = 0; f < faces.size(); ++f) {
            const std::size_t n = count_roots(free_polys[f], lower, upper);
            if (n == 0)
                continue;
            if (n > 1 || count_roots(gcd(free_polys[f], free_polys[cand.face]), lower, upper) != 1)
                return std::nullopt; // another root inside: more bits // another root inside: more bits
        }
        PieceBound b;
        b.piece = p;
        b.face = idx;
        b.poly = polys[cand.face];
        b.lower = lower;
        b.upper = upper;
        b.point = primitive_ray(pc.R * *z); // the same ratio: it is a positive multiple
        b.upper_evidence = std::move(cop);
        return b;
    }
    return std::nullopt;
}

std::optional<PieceBound> lipschitz_piece(const Model& model, std::size_t p, std::size_t bits) {
    const Piece& pc = model.pieces()[p];
    const Matrix& H = model.H();
    const Matrix K = transpose(pc.Q) * H * pc.Q;
    const UPoly poly = pencil_determinant(K, H), q = square_free(poly);
    const auto roots = isolate(q);
    if (roots.empty())
        throw std::logic_error("a symmetric definite pencil without a real eigenvalue");
    RootInterval iv = refine(q, roots.back(), width_at(bits, roots.back()));
    if (const auto r = rational_root(q, iv, 64))
        iv = {*r, *r};
    // Any eigenvector will do (a direction, not a point of a cone): the try of the largest ratio.
    std::optional<Vector> y;
    Rational best;
    for (const auto& v : positive_eigenvectors(K, H, iv, true)) {
        const Rational r = bilinear(v, K, v) / bilinear(v, H, v);
        if (!y || r > best) {
            y = v;
            best = r;
        }
    }
    if (!y)
        return std::nullopt;
    PieceBound b;
    b.piece = p;
    b.poly = poly;
    b.lower = bilinear(*y, K, *y) / bilinear(*y, H, *y);
    b.upper = iv.hi;
    b.point = canonical_line(*y);
    if (b.upper < b.lower || count_roots(q, b.lower, b.upper) != 1 || count_roots_above(q, b.upper) != 0)
        return std::nullopt;
    return b;
}

template <class PieceFn> LawBound bound_law(const Model& model, PieceFn piece_fn) {
    LawBound out;
    for (std::size_t bits = kFirstBits; bits <= kLastBits; bits *= 2) {
        out.pieces.clear();
        std::vector<UPoly> free_polys;
        bool all = true;
        for (std::size_t p = 0; p < model.pieces().size() && all; ++p) {
            auto b = piece_fn(p, bits);
            if (!b) {
                all = false;
                break;
            }
            free_polys.push_back(square_free(b->poly));
            out.pieces.push_back(std::move(*b));
        }
        if (all && !out.pieces.empty() && combine(out, free_polys))
            return out;
    }
    out.pieces.clear();
    out.limit = "the pieces' values were not separated with intervals of " + std::to_string(kLastBits) +
                " bits (a bound of the prover, no option raises it)";
    return out;
}

} // namespace

LawBound energy_supremum(const Model& model, const WorstCaseOptions& options) {
    try {
        return bound_law(model, [&](std::size_t p, std::size_t bits) { return energy_piece(model, p, bits, options); });
    } catch (const LimitExceeded& e) {
        LawBound out;
        out.limit = e.what(); // names the option
        return out;
    }
}

LawBound lipschitz_squared(const Model& model, const WorstCaseOptions&) {
    return bound_law(model, [&](std::size_t p, std::size_t bits) { return lipschitz_piece(model, p, bits); });
}

WorstCase worst_case(const Model& model, bool continuous_tiling, const WorstCaseOptions& options) {
    WorstCase w;
    w.energy = energy_supremum(model, options);
    if (continuous_tiling)
        w.lipschitz = lipschitz_squared(model, options);
    return w;
}

std::string value_decimal(const AlgebraicValue& v) {
    if (v.exact)
        return readable_text(*v.exact);
    // Narrow the interval until both ends agree to 17 significant digits.
    RootInterval iv{v.lo, v.hi};
    for (int i = 0; i < 400; ++i) {
        const std::string a = readable_text(iv.lo), b = readable_text(iv.hi);
        if (a == b)
            return a[0] == '~' ? a : "~" + a;
        iv = refine(v.poly, iv, (iv.hi - iv.lo) / Rational(1024));
        if (iv.lo == iv.hi)
            return readable_text(iv.lo);
    }
    return "~" + readable_text(iv.lo).substr(readable_text(iv.lo)[0] == '~' ? 1 : 0);
}

std::string value_text(const AlgebraicValue& v) {
    if (v.exact) // exact; a decimal instead when the rational is long (the exact one is in --json)
        return to_string(*v.exact).size() <= 40 ? to_string(*v.exact) : readable_text(*v.exact);
    std::string poly;
    for (std::size_t i = v.poly.c.size(); i-- > 0;) {
        const Rational& a = v.poly.c[i];
        if (sign_of(a) == Sign::zero)
            continue;
        const bool neg = sign_of(a) == Sign::negative;
        const Rational m = abs_of(a);
        std::string term = i == 0 || m != Rational(1) ? to_string(m) : "";
        if (i > 0)
            term += (term.empty() ? "" : " ") + std::string("x") + (i > 1 ? "^" + std::to_string(i) : "");
        poly += poly.empty() ? (neg ? "-" : "") + term : (neg ? " - " : " + ") + term;
    }
    if (poly.size() > 120)
        poly = "a polynomial of degree " + std::to_string(v.poly.degree()) + " (--json)";
    return value_decimal(v) + " (a root of " + poly + ")";
}

Json to_json(const AlgebraicValue& v) {
    Json j;
    if (v.exact)
        j["exact"] = to_json(*v.exact);
    j["polynomial"] = to_json(v.poly);
    j["interval"] = Json::array({to_json(v.lo), to_json(v.hi)});
    j["decimal"] = value_decimal(v);
    return j;
}

namespace {

Json bound_json(const LawBound& b, const Model& model, bool energy) {
    Json j;
    if (!b.decided) {
        j["status"] = "undecided";
        j["limit"] = b.limit;
        return j;
    }
    j["status"] = "decided";
    j["value"] = to_json(b.value);
    j["piece"] = model.pieces()[b.pieces[b.top].piece].name;
    j[energy ? "point" : "direction"] = to_json(b.pieces[b.top].point);
    Json pieces = Json::array();
    for (const auto& p : b.pieces) {
        Json e;
        e["piece"] = model.pieces()[p.piece].name;
        if (energy) {
            Json face = Json::array();
            for (auto i : p.face)
                face.push_back(i + 1);
            e["face"] = face;
        }
        e["polynomial"] = to_json(p.poly);
        e["lower"] = to_json(p.lower);
        e["upper"] = to_json(p.upper);
        e[energy ? "point" : "direction"] = to_json(p.point);
        if (energy)
            e["certificate"] = detail::certificate_json(p.upper_evidence);
        pieces.push_back(std::move(e));
    }
    j["pieces"] = std::move(pieces);
    return j;
}

} // namespace

Json to_json(const WorstCase& w, const Model& model) {
    Json j;
    j["energy_ratio"] = bound_json(w.energy, model, true);
    if (w.lipschitz)
        j["lipschitz_squared"] = bound_json(*w.lipschitz, model, false);
    return j;
}

} // namespace impactcert
