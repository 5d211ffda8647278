// impactcert-check -- the independent checker of impactcert-certificate/1 documents.
//
// Contract: reads one certificate, re-derives everything it states from the law it contains,
// and exits 0 (verified), 1 (rejected: one line naming the JSON path and the reason) or
// 2 (malformed: not a certificate it can read). It shares no code with the prover: it links GMP
// (gmpxx) and nlohmann-json only, and has its own rationals, matrices, SHA-256 and law reader.
// Verified means: the law hash matches; G and H follow from the masses and W; every
// obligation's verdict follows, a "proved" one from its evidence (re-computed products, LDL^T
// factors multiplied back, KKT faces re-enumerated), a "refuted" one from its counterexample
// (re-computed from scratch); and the top verdict is "proved" iff every claimed obligation is.
// The schema is in proofs/README.md.
#include "impactcert_check.hpp"

#include <gmpxx.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace {

using Json = nlohmann::ordered_json;
using Q = mpq_class;
using Vec = std::vector<Q>;
using Mat = std::vector<Vec>; // row-major, rows of equal length

struct Malformed {
    std::string path, why;
};
struct Rejected {
    std::string path, why;
};
// A decision the prover bounds by a limit would exceed the checker's copy of that limit: the
// certificate is neither verified nor rejected (it may be right, made with a raised limit).
struct Undecided {
    std::string option, path, why; // option: "--max-faces", "--max-chambers" or "--max-subsets"
};

// The prover's limits (src/limits.hpp), with the same defaults and options, counted the same
// way and checked before the work is done.
struct Limits {
    std::size_t max_faces = 16384;     // --max-faces: simplex faces of one KKT enumeration
    std::size_t max_chambers = 200000; // --max-chambers: steps of the chamber enumeration
    std::size_t max_subsets = 5000000; // --max-subsets: constraint subsets for cone intersections
    // The checker's own: the bits of an entry of a declared identity's product (about 1.26
    // million decimal digits), bounded from the factors before multiplying; a product of many
    // large factors grows without a bound the prover checks.
    std::size_t max_product_bits = 4194304; // --max-product-bits
};

[[noreturn]] void malformed(const std::string& path, const std::string& why) { throw Malformed{path, why}; }
[[noreturn]] void reject(const std::string& path, const std::string& why) { throw Rejected{path, why}; }
[[noreturn]] void undecided(const std::string& option, const std::string& path, const std::string& why) {
    throw Undecided{option, path, why};
}
void require(bool ok, const std::string& path, const std::string& why) {
    if (!ok)
        reject(path, why);
}

// ---------------------------------------------------------------------------------------------
// SHA-256 (FIPS 180-4). The round constants are computed, not typed: K[i] and the initial hash
// are the first 32 fractional bits of the cube and square roots of the first primes, obtained
// exactly with integer roots.

std::string sha256_hex(const std::string& message) {
    static const std::vector<std::uint32_t> primes = [] {
        std::vector<std::uint32_t> p;
        for (std::uint32_t n = 2; p.size() < 64; ++n) {
            bool prime = true;
            for (auto d : p)
                prime = prime && n % d != 0;
            if (prime)
                p.push_back(n);
        }
        return p;
    }();
    auto frac_bits = [](std::uint32_t p, unsigned root) {
        mpz_class x = mpz_class(p) << (32 * root), r;
        mpz_root(r.get_mpz_t(), x.get_mpz_t(), root);
        mpz_class low = r & mpz_class(0xffffffffUL);
        return static_cast<std::uint32_t>(low.get_ui());
    };
    std::uint32_t k[64], h[8];
    for (int i = 0; i < 64; ++i)
        k[i] = frac_bits(primes[static_cast<std::size_t>(i)], 3);
    for (int i = 0; i < 8; ++i)
        h[i] = frac_bits(primes[static_cast<std::size_t>(i)], 2);
    auto rotr = [](std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); };

    std::string m = message;
    const std::uint64_t bits = static_cast<std::uint64_t>(message.size()) * 8;
    m += static_cast<char>(0x80);
    while (m.size() % 64 != 56)
        m += '\0';
    for (int i = 7; i >= 0; --i)
        m += static_cast<char>((bits >> (8 * i)) & 0xff);
    for (std::size_t chunk = 0; chunk < m.size(); chunk += 64) {
        std::uint32_t w[64];
        for (int t = 0; t < 16; ++t) {
            w[t] = 0;
            for (int b = 0; b < 4; ++b)
                w[t] = (w[t] << 8) | static_cast<unsigned char>(m[chunk + static_cast<std::size_t>(4 * t + b)]);
        }
        for (int t = 16; t < 64; ++t) {
            const std::uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
            const std::uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
            w[t] = w[t - 16] + s0 + w[t - 7] + s1;
        }
        std::uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], hh = h[7];
        for (int t = 0; t < 64; ++t) {
            const std::uint32_t t1 = hh + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + k[t] + w[t];
            const std::uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
            hh = g;
            g = f;
            f = e;
            e = d + t1;
            d = c;
            c = b;
            b = a;
            a = t1 + t2;
        }
        h[0] += a; h[1] += b; h[2] += c; h[3] += d; h[4] += e; h[5] += f; h[6] += g; h[7] += hh;
    }
    std::ostringstream out;
    for (auto word : h)
        for (int shift = 28; shift >= 0; shift -= 4)
            out << "0123456789abcdef"[(word >> shift) & 15];
    return out.str();
}

// ---------------------------------------------------------------------------------------------
// Reading

std::string at(const std::string& path, const std::string& key) { return path + "." + key; }
std::string at(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

const Json& field(const Json& j, const std::string& path, const std::string& key) {
    if (!j.is_object())
        malformed(path, "expected an object");
    if (!j.contains(key))
        malformed(path, "missing key \"" + key + "\"");
    return j[key];
}

std::string str(const Json& j, const std::string& path) {
    if (!j.is_string())
        malformed(path, "expected a string");
    return j.get<std::string>();
}

// A count or index: the JSON integer type only (1.0 is a number equal to 1, not an integer).
std::size_t natural(const Json& j, const std::string& path) {
    if (!j.is_number_unsigned())
        malformed(path, "expected a non-negative integer");
    return j.get<std::size_t>();
}

// A rational: a string in canonical form (lowest terms, no sign on zero, no leading zeros, no
// "+", no "/1"), as the prover writes it, so that no rational can be re-spelled unnoticed.
Q rat(const Json& j, const std::string& path) {
    if (!j.is_string())
        malformed(path, "expected a rational string");
    const std::string s = j.get<std::string>();
    std::size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
    const std::size_t digits_start = i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])))
        ++i;
    bool ok = i > digits_start;
    if (ok && i < s.size()) {
        ok = s[i] == '/';
        const std::size_t den_start = ++i;
        while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])))
            ++i;
        ok = ok && i > den_start && i == s.size();
    }
    if (!ok)
        malformed(path, "\"" + s + "\" is not a rational p or p/q");
    Q q;
    q.set_str(s[0] == '+' ? s.substr(1) : s, 10);
    if (s.find('/') != std::string::npos && q.get_den() == 0)
        malformed(path, "zero denominator");
    q.canonicalize();
    if (q.get_str() != s)
        malformed(path, "\"" + s + "\" is not in canonical form (\"" + q.get_str() + "\")");
    return q;
}

Vec vec(const Json& j, const std::string& path) {
    if (!j.is_array())
        malformed(path, "expected an array");
    Vec v;
    for (std::size_t i = 0; i < j.size(); ++i)
        v.push_back(rat(j[i], at(path, i)));
    return v;
}

Mat mat(const Json& j, const std::string& path) {
    if (!j.is_array() || j.empty())
        malformed(path, "expected a non-empty array of rows");
    Mat m;
    for (std::size_t i = 0; i < j.size(); ++i) {
        m.push_back(vec(j[i], at(path, i)));
        if (m.back().size() != m.front().size() || m.back().empty())
            malformed(at(path, i), "ragged or empty row");
    }
    return m;
}

// ---------------------------------------------------------------------------------------------
// Exact linear algebra

Mat zeros(std::size_t r, std::size_t c) { return Mat(r, Vec(c, Q(0))); }
Mat eye(std::size_t n) {
    Mat m = zeros(n, n);
    for (std::size_t i = 0; i < n; ++i)
        m[i][i] = 1;
    return m;
}
Mat mul(const Mat& a, const Mat& b) {
    Mat c = zeros(a.size(), b[0].size());
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t k = 0; k < b.size(); ++k)
            for (std::size_t j = 0; j < b[0].size(); ++j)
                c[i][j] += a[i][k] * b[k][j];
    return c;
}
Vec mul(const Mat& a, const Vec& x) {
    Vec y(a.size(), Q(0));
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t k = 0; k < x.size(); ++k)
            y[i] += a[i][k] * x[k];
    return y;
}
Mat tr(const Mat& a) {
    Mat t = zeros(a[0].size(), a.size());
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < a[0].size(); ++j)
            t[j][i] = a[i][j];
    return t;
}
Mat sub(Mat a, const Mat& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < a[0].size(); ++j)
            a[i][j] -= b[i][j];
    return a;
}
Vec sub(Vec a, const Vec& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
        a[i] -= b[i];
    return a;
}
Q dot(const Vec& a, const Vec& b) {
    Q s = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        s += a[i] * b[i];
    return s;
}
Q form(const Mat& a, const Vec& x) { return dot(x, mul(a, x)); }
Vec col(const Mat& a, std::size_t j) {
    Vec v;
    for (const auto& row : a)
        v.push_back(row[j]);
    return v;
}
Mat from_cols(const std::vector<Vec>& cols) {
    Mat m = zeros(cols[0].size(), cols.size());
    for (std::size_t j = 0; j < cols.size(); ++j)
        for (std::size_t i = 0; i < cols[0].size(); ++i)
            m[i][j] = cols[j][i];
    return m;
}
bool nonneg(const Vec& v) {
    return std::all_of(v.begin(), v.end(), [](const Q& x) { return sgn(x) >= 0; });
}
bool positive(const Vec& v) {
    return std::all_of(v.begin(), v.end(), [](const Q& x) { return sgn(x) > 0; });
}

// Solves a x = b (square); false when singular.
bool solve(Mat a, Vec b, Vec& x) {
    const std::size_t n = a.size();
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t p = c;
        while (p < n && sgn(a[p][c]) == 0)
            ++p;
        if (p == n)
            return false;
        std::swap(a[p], a[c]);
        std::swap(b[p], b[c]);
        for (std::size_t r = 0; r < n; ++r) {
            if (r == c || sgn(a[r][c]) == 0)
                continue;
            const Q f = a[r][c] / a[c][c];
            for (std::size_t k = c; k < n; ++k)
                a[r][k] -= f * a[c][k];
            b[r] -= f * b[c];
        }
    }
    x.assign(n, Q(0));
    for (std::size_t i = 0; i < n; ++i)
        x[i] = b[i] / a[i][i];
    return true;
}

bool invert(const Mat& a, Mat& inv) {
    const std::size_t n = a.size();
    std::vector<Vec> cols;
    for (std::size_t j = 0; j < n; ++j) {
        Vec e(n, Q(0)), x;
        e[j] = 1;
        if (!solve(a, e, x))
            return false;
        cols.push_back(x);
    }
    inv = from_cols(cols);
    return true;
}

Q det(Mat a) {
    const std::size_t n = a.size();
    Q d = 1;
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t p = c;
        while (p < n && sgn(a[p][c]) == 0)
            ++p;
        if (p == n)
            return 0;
        if (p != c) {
            std::swap(a[p], a[c]);
            d = -d;
        }
        d *= a[c][c];
        for (std::size_t r = c + 1; r < n; ++r) {
            const Q f = a[r][c] / a[c][c];
            for (std::size_t k = c; k < n; ++k)
                a[r][k] -= f * a[c][k];
        }
    }
    return d;
}

Vec primitive(const Vec& v) {
    mpz_class l = 1, g = 0;
    for (const auto& x : v)
        l = lcm(l, x.get_den());
    Vec out;
    for (const auto& x : v) {
        out.push_back(Q(x * l));
        g = gcd(g, out.back().get_num());
    }
    if (g == 0)
        return out; // the zero vector: no ray
    for (auto& x : out)
        x /= g;
    return out;
}

// The primitive vector of the line through v != 0 whose first non-zero entry is positive.
Vec canonical_line(const Vec& v) {
    Vec p = primitive(v);
    for (const auto& x : p)
        if (sgn(x) != 0) {
            if (sgn(x) < 0)
                for (auto& y : p)
                    y = -y;
            break;
        }
    return p;
}

// A basis of {x : r . x = 0 for every row r} (Gaussian elimination, then one vector per column
// without a pivot).
std::vector<Vec> kernel(std::vector<Vec> rows, std::size_t dim) {
    std::vector<std::size_t> pivots;
    std::size_t r = 0;
    for (std::size_t col = 0; col < dim && r < rows.size(); ++col) {
        std::size_t p = r;
        while (p < rows.size() && sgn(rows[p][col]) == 0)
            ++p;
        if (p == rows.size())
            continue;
        std::swap(rows[p], rows[r]);
        const Q lead = rows[r][col];
        for (auto& x : rows[r])
            x /= lead;
        for (std::size_t i = 0; i < rows.size(); ++i)
            if (i != r && sgn(rows[i][col]) != 0) {
                const Q f = rows[i][col];
                for (std::size_t k = 0; k < dim; ++k)
                    rows[i][k] -= f * rows[r][k];
            }
        pivots.push_back(col);
        ++r;
    }
    std::vector<Vec> out;
    for (std::size_t f = 0; f < dim; ++f) {
        if (std::find(pivots.begin(), pivots.end(), f) != pivots.end())
            continue;
        Vec x(dim, Q(0));
        x[f] = 1;
        for (std::size_t k = 0; k < pivots.size(); ++k)
            x[pivots[k]] = -rows[k][f];
        out.push_back(x);
    }
    return out;
}

// The number of chambers of the central arrangement {x : n . x = 0} (n in `normals`, distinct
// lines) in R^d, by deletion and restriction of the first hyperplane, unrolled:
// r(A) = 1 + sum_k r(A_{>k} restricted to h_k), A_{>k} the hyperplanes after h_k (so the
// recursion is on the dimension only). Gives up (returns more than `cap`) once over `cap`.
std::size_t count_chambers(const std::vector<Vec>& normals, std::size_t d, std::size_t cap) {
    if (normals.empty())
        return 1;
    if (d == 1)
        return 2;
    std::size_t total = 1;
    for (std::size_t k = 0; k < normals.size() && total <= cap; ++k) {
        const std::vector<Vec> basis = kernel({normals[k]}, d);
        std::vector<Vec> restricted;
        std::set<Vec> seen;
        for (std::size_t l = k + 1; l < normals.size(); ++l) {
            Vec local;
            for (const auto& b : basis)
                local.push_back(dot(b, normals[l]));
            const Vec line = canonical_line(local);
            if (seen.insert(line).second)
                restricted.push_back(line);
        }
        total += count_chambers(restricted, d - 1, cap - total);
    }
    return total;
}

// The prover's count of chamber-enumeration steps (src/fan.cpp, charge): one per call and one
// per point of a restriction; more than --max-chambers of them and the prover gives up.
struct ChamberSteps {
    std::size_t done, max;
    std::string path;
    void charge() {
        if (++done > max)
            undecided("--max-chambers", path,
                      "the facet arrangement needs more than " + std::to_string(max) + " chamber-enumeration steps");
    }
};

// One point per chamber, by the prover's rule (proofs/README.md, "Check, complete"): the
// hyperplanes added in order; after adding h (normal n) the earlier points off h are kept, and
// every point y of the earlier hyperplanes restricted to h (in the primitive kernel basis of n)
// gives y +- eps n, eps = min(1, |m.y| / (2 |m.n|) over earlier m with m.n != 0), primitive;
// then the first point of every sign vector is kept. The checker regenerates the list to demand
// the canonical one (so no point can be changed unnoticed) and counts the chambers by a second
// route (count_chambers) to know that the list is complete.
std::vector<Vec> canonical_chamber_points(const std::vector<Vec>& normals, std::size_t d, std::size_t& budget,
                                          ChamberSteps& steps) {
    if (budget == 0)
        reject("$.obligations[0].data.chamber_points", "more chamber-enumeration work than the certificate lists points");
    --budget;
    steps.charge();
    if (d == 1)
        return normals.empty() ? std::vector<Vec>{Vec{Q(1)}} : std::vector<Vec>{Vec{Q(1)}, Vec{Q(-1)}};
    Vec first(d, Q(0));
    first[0] = 1;
    std::vector<Vec> points = {first};
    for (std::size_t k = 0; k < normals.size(); ++k) {
        const Vec& n = normals[k];
        std::vector<Vec> next;
        for (const auto& p : points)
            if (sgn(dot(n, p)) != 0)
                next.push_back(p);
        std::vector<Vec> basis = kernel({n}, d);
        for (auto& b : basis)
            b = primitive(b);
        std::vector<Vec> restricted;
        for (std::size_t l = 0; l < k; ++l) {
            Vec local;
            for (const auto& b : basis)
                local.push_back(dot(b, normals[l]));
            const Vec line = canonical_line(local);
            if (std::find(restricted.begin(), restricted.end(), line) == restricted.end())
                restricted.push_back(line);
        }
        for (const auto& local : canonical_chamber_points(restricted, d - 1, budget, steps)) {
            Vec y(d, Q(0));
            for (std::size_t i = 0; i + 1 < d; ++i)
                for (std::size_t j = 0; j < d; ++j)
                    y[j] += local[i] * basis[i][j];
            Q eps = 1;
            for (std::size_t l = 0; l < k; ++l) {
                const Q mn = dot(normals[l], n);
                if (sgn(mn) != 0)
                    eps = std::min(eps, Q(abs(dot(normals[l], y)) / (2 * abs(mn))));
            }
            for (int side : {1, -1}) {
                Vec z = y;
                for (std::size_t j = 0; j < d; ++j)
                    z[j] += side * eps * n[j];
                next.push_back(primitive(z));
            }
            steps.charge();
        }
        std::set<std::vector<int>> seen;
        points.clear();
        for (const auto& p : next) {
            std::vector<int> signs;
            for (std::size_t l = 0; l <= k; ++l)
                signs.push_back(sgn(dot(normals[l], p)));
            if (seen.insert(signs).second)
                points.push_back(p);
        }
    }
    return points;
}

// ---- Tilings by walls (proofs/README.md, "Check, walls"): sum w_i [x in int C_i] equals the
// target at every generic x iff identical cones cancel to the target's count at one generic
// point and, across every facet hyperplane, the facets in it (weighted by the side of their
// cone) cancel as cones of the hyperplane, recursively.

struct WCone {
    std::vector<Vec> rays;
    long w = 0;
};

bool inside_open(const std::vector<Vec>& rays, const Vec& x) {
    Vec s;
    return solve(from_cols(rays), x, s) && positive(s);
}

Vec first_generic(const std::vector<Vec>& normals, std::size_t d) {
    for (long t = 1;; ++t) {
        Vec x;
        Q power = 1;
        for (std::size_t i = 0; i < d; ++i, power *= t)
            x.push_back(power);
        if (std::all_of(normals.begin(), normals.end(), [&](const Vec& n) { return sgn(dot(n, x)) != 0; }))
            return x;
    }
}

bool walls_balance(const std::vector<WCone>& in, std::size_t d, long target) {
    std::map<std::vector<Vec>, long> net;
    for (auto cone : in) {
        std::sort(cone.rays.begin(), cone.rays.end());
        net[cone.rays] += cone.w;
    }
    std::vector<WCone> family;
    for (const auto& [rays, w] : net)
        if (w != 0)
            family.push_back({rays, w});
    if (family.empty())
        return target == 0;
    if (d == 1) {
        long pos = 0, neg = 0;
        for (const auto& cone : family)
            (sgn(cone.rays[0][0]) > 0 ? pos : neg) += cone.w;
        return pos == target && neg == target;
    }
    std::map<Vec, std::map<std::vector<Vec>, long>> walls;
    for (const auto& cone : family)
        for (std::size_t drop = 0; drop < d; ++drop) {
            std::vector<Vec> facet;
            for (std::size_t k = 0; k < d; ++k)
                if (k != drop)
                    facet.push_back(cone.rays[k]);
            const Vec n = canonical_line(kernel(facet, d).at(0));
            walls[n][facet] += (sgn(dot(n, cone.rays[drop])) > 0 ? 1 : -1) * cone.w;
        }
    std::vector<Vec> normals;
    for (const auto& entry : walls)
        normals.push_back(entry.first);
    const Vec x0 = first_generic(normals, d);
    long count = 0;
    for (const auto& cone : family)
        if (inside_open(cone.rays, x0))
            count += cone.w;
    if (count != target)
        return false;
    for (const auto& [n, facets] : walls) {
        std::vector<Vec> basis = kernel({n}, d);
        for (auto& b : basis)
            b = primitive(b);
        // Coordinates in h: the basis has full column rank; solve the normal equations.
        Mat gram(basis.size(), Vec(basis.size()));
        for (std::size_t i = 0; i < basis.size(); ++i)
            for (std::size_t j = 0; j < basis.size(); ++j)
                gram[i][j] = dot(basis[i], basis[j]);
        std::vector<WCone> induced;
        for (const auto& [facet, w] : facets) {
            if (w == 0)
                continue;
            WCone wc;
            wc.w = w;
            for (const auto& r : facet) {
                Vec rhs, y;
                for (const auto& b : basis)
                    rhs.push_back(dot(b, r));
                if (!solve(gram, rhs, y))
                    reject("$.law.pieces", "a facet basis is singular");
                wc.rays.push_back(primitive(y));
            }
            induced.push_back(wc);
        }
        if (!induced.empty() && !walls_balance(induced, d - 1, 0))
            return false;
    }
    return true;
}

// ---------------------------------------------------------------------------------------------
// The law, re-derived

struct Piece {
    std::string name;
    Mat Q_, R, R_inv;
    std::vector<Vec> rays; // primitive
};

struct Identity {
    std::size_t lhs;
    std::vector<std::size_t> product;
    Json lhs_json, product_json; // as declared, for comparison with the evidence
};
struct SingleImpact {
    std::size_t piece, contact; // contact in 1..c
    Q restitution;
    Json piece_json;
};
struct OutcomeDecl {
    std::string name;
    Vec u_minus, u_plus;
};

struct Law {
    Json json;
    Vec masses;
    Mat W, M_inv, G, H;
    std::size_t n = 0, c = 0;
    std::vector<Piece> pieces;
    std::map<std::string, std::size_t> piece_index;
    std::vector<Vec> distinct_rays;     // in order of first appearance
    std::map<Vec, std::size_t> ray_index; // into distinct_rays
    std::vector<Identity> identities;
    std::vector<SingleImpact> single_impacts;
    std::vector<OutcomeDecl> outcomes;
    std::set<std::string> claimed_ids;
    bool claims_given = false;

    std::size_t piece(const Json& name, const std::string& path) const {
        const std::string s = str(name, path);
        const auto it = piece_index.find(s);
        if (it == piece_index.end())
            reject(path, "unknown piece \"" + s + "\"");
        return it->second;
    }
    bool in_cone(std::size_t p, const Vec& g) const { return nonneg(mul(pieces[p].R_inv, g)); }
    bool in_interior(std::size_t p, const Vec& g) const { return positive(mul(pieces[p].R_inv, g)); }
    std::vector<std::size_t> interiors(const Vec& g) const {
        std::vector<std::size_t> out;
        for (std::size_t p = 0; p < pieces.size(); ++p)
            if (in_interior(p, g))
                out.push_back(p);
        return out;
    }
    bool is_ray_of(std::size_t p, const Vec& v) const {
        const Vec pv = primitive(v);
        return std::find(pieces[p].rays.begin(), pieces[p].rays.end(), pv) != pieces[p].rays.end();
    }
    Q energy(const Vec& g) const { return form(H, g); }
    Mat impact(std::size_t k, const Q& e) const {
        Mat q = eye(c);
        for (std::size_t i = 0; i < c; ++i)
            q[i][k] -= (1 + e) * G[i][k] / G[k][k];
        return q;
    }
    Vec u_plus(const Vec& u, const Vec& gm, const Vec& gp) const {
        const Vec lambda = mul(H, sub(gp, gm));
        const Vec du = mul(M_inv, mul(W, lambda));
        Vec out = u;
        for (std::size_t i = 0; i < n; ++i)
            out[i] += du[i];
        return out;
    }
};

const std::vector<std::string> kIds = {"fan", "P1", "P2", "P3", "kinematic", "kinetic", "energetic",
                                       "identities", "single-impacts", "nonexpansive", "nonexpansive-lemma",
                                       "outcomes"};

// An object with exactly the keys `required` plus some of `optional`. Every object the checker
// reads goes through here first (then `field`), so that no key is read unchecked and nothing
// outside the schema rides along. A certificate is written by the prover and carries no free
// text: its law is in canonical form, which drops `note` and `description`.
void expect_keys(const Json& j, const std::string& path, std::initializer_list<const char*> required,
                 std::initializer_list<const char*> optional = {}) {
    if (!j.is_object())
        malformed(path, "expected an object");
    for (const char* k : required)
        if (!j.contains(k))
            malformed(path, std::string("missing key \"") + k + "\"");
    for (const auto& item : j.items()) {
        const std::string& k = item.key();
        const bool known = std::any_of(required.begin(), required.end(), [&](const char* r) { return k == r; }) ||
                           std::any_of(optional.begin(), optional.end(), [&](const char* o) { return k == o; });
        if (!known)
            malformed(at(path, k), "unknown key");
    }
}

// The declarations that make identities, single-impacts and outcomes apply (non-empty lists;
// read_law has checked that each is an array when present).
bool declares(const Json& law, const char* key) { return law.contains(key) && !law.at(key).empty(); }
bool applies(const Json& law, const std::string& id) {
    if (id == "identities")
        return declares(law, "identities");
    if (id == "single-impacts")
        return declares(law, "single_impacts");
    if (id == "outcomes")
        return declares(law, "outcomes");
    return true;
}

Law read_law(const Json& j, const std::string& path) {
    Law law;
    law.json = j;
    // The prover's input rules (SPEC section 4): a law it rejects is never verified.
    expect_keys(j, path, {"format", "name", "masses", "contacts", "pieces"},
                {"identities", "single_impacts", "outcomes", "claims"});
    require(field(j, path, "format") == "impactcert-law/1", at(path, "format"), "is not \"impactcert-law/1\"");
    require(!str(field(j, path, "name"), at(path, "name")).empty(), at(path, "name"), "empty law name");
    law.masses = vec(field(j, path, "masses"), at(path, "masses"));
    law.n = law.masses.size();
    require(law.n >= 1, at(path, "masses"), "no balls");
    for (std::size_t i = 0; i < law.n; ++i)
        require(sgn(law.masses[i]) > 0, at(at(path, "masses"), i), "mass must be positive");
    const Json& contacts = field(j, path, "contacts");
    if (contacts.is_string() && contacts == "chain") {
        require(law.n >= 2, at(path, "masses"), "a chain needs two balls");
        law.W = zeros(law.n, law.n - 1);
        for (std::size_t k = 0; k + 1 < law.n; ++k) {
            law.W[k][k] = -1;
            law.W[k + 1][k] = 1;
        }
    } else {
        expect_keys(contacts, at(path, "contacts"), {"W"});
        law.W = mat(field(contacts, at(path, "contacts"), "W"), at(at(path, "contacts"), "W"));
        require(law.W.size() == law.n, at(at(path, "contacts"), "W"), "needs one row per ball");
    }
    law.c = law.W[0].size();
    law.M_inv = zeros(law.n, law.n);
    for (std::size_t i = 0; i < law.n; ++i)
        law.M_inv[i][i] = 1 / law.masses[i];
    law.G = mul(mul(tr(law.W), law.M_inv), law.W);
    require(invert(law.G, law.H), at(path, "contacts"), "G is singular");
    const Json& pieces = field(j, path, "pieces");
    if (!pieces.is_array())
        malformed(at(path, "pieces"), "expected an array");
    require(!pieces.empty(), at(path, "pieces"), "no pieces");
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        const std::string pp = at(at(path, "pieces"), p);
        expect_keys(pieces[p], pp, {"name", "Q"}, {"rays"});
        Piece piece;
        piece.name = str(field(pieces[p], pp, "name"), at(pp, "name"));
        require(!piece.name.empty(), at(pp, "name"), "empty piece name");
        require(law.piece_index.emplace(piece.name, p).second, at(pp, "name"), "duplicate piece name");
        piece.Q_ = mat(field(pieces[p], pp, "Q"), at(pp, "Q"));
        require(piece.Q_.size() == law.c && piece.Q_[0].size() == law.c, at(pp, "Q"), "not c x c");
        std::vector<Vec> rays;
        if (pieces[p].contains("rays")) {
            const Json& listed = field(pieces[p], pp, "rays");
            if (!listed.is_array())
                malformed(at(pp, "rays"), "expected an array of rays");
            require(listed.size() == law.c, at(pp, "rays"), "needs c rays");
            for (std::size_t k = 0; k < listed.size(); ++k)
                rays.push_back(vec(listed[k], at(at(pp, "rays"), k)));
        } else {
            Mat q_inv;
            require(invert(piece.Q_, q_inv), at(pp, "Q"), "singular Q and no rays");
            for (std::size_t k = 0; k < law.c; ++k)
                rays.push_back(col(q_inv, k));
        }
        for (std::size_t k = 0; k < rays.size(); ++k) {
            require(rays[k].size() == law.c && !std::all_of(rays[k].begin(), rays[k].end(), [](const Q& x) { return sgn(x) == 0; }),
                    at(at(pp, "rays"), k), "zero or mis-sized ray");
            piece.rays.push_back(primitive(rays[k]));
        }
        piece.R = from_cols(piece.rays);
        require(invert(piece.R, piece.R_inv), at(pp, "rays"), "dependent rays");
        for (const auto& r : piece.rays)
            if (law.ray_index.emplace(r, law.distinct_rays.size()).second)
                law.distinct_rays.push_back(r);
        law.pieces.push_back(std::move(piece));
    }
    // Declarations: their shape is checked here once and kept parsed, so that no later step
    // reads a missing key or a vector of the wrong length (a hash can be recomputed for any law).
    auto entries = [&](const char* key) {
        const Json& l = j.contains(key) ? field(j, path, key) : Json::array();
        if (!l.is_array())
            malformed(at(path, key), "expected an array");
        return l;
    };
    const Json identities = entries("identities");
    for (std::size_t i = 0; i < identities.size(); ++i) {
        const std::string ip = at(at(path, "identities"), i);
        expect_keys(identities[i], ip, {"lhs", "product"});
        Identity d;
        d.lhs_json = field(identities[i], ip, "lhs");
        d.lhs = law.piece(d.lhs_json, at(ip, "lhs"));
        d.product_json = field(identities[i], ip, "product");
        if (!d.product_json.is_array() || d.product_json.empty())
            malformed(at(ip, "product"), "expected a non-empty array of piece names");
        for (std::size_t k = 0; k < d.product_json.size(); ++k)
            d.product.push_back(law.piece(d.product_json[k], at(at(ip, "product"), k)));
        law.identities.push_back(std::move(d));
    }
    const Json impacts = entries("single_impacts");
    for (std::size_t i = 0; i < impacts.size(); ++i) {
        const std::string ip = at(at(path, "single_impacts"), i);
        expect_keys(impacts[i], ip, {"piece", "contact", "restitution"});
        SingleImpact d;
        d.piece_json = field(impacts[i], ip, "piece");
        d.piece = law.piece(d.piece_json, at(ip, "piece"));
        d.contact = natural(field(impacts[i], ip, "contact"), at(ip, "contact"));
        if (d.contact < 1 || d.contact > law.c)
            malformed(at(ip, "contact"), "expected a contact number in 1..c");
        d.restitution = rat(field(impacts[i], ip, "restitution"), at(ip, "restitution"));
        require(sgn(d.restitution) >= 0 && d.restitution <= 1, at(ip, "restitution"), "restitution outside [0, 1]");
        law.single_impacts.push_back(std::move(d));
    }
    const Json outcomes = entries("outcomes");
    std::set<std::string> outcome_names;
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
        const std::string op = at(at(path, "outcomes"), i);
        expect_keys(outcomes[i], op, {"name", "u_minus", "u_plus"});
        OutcomeDecl d;
        d.name = str(field(outcomes[i], op, "name"), at(op, "name"));
        require(outcome_names.insert(d.name).second, at(op, "name"), "duplicate outcome name");
        d.u_minus = vec(field(outcomes[i], op, "u_minus"), at(op, "u_minus"));
        d.u_plus = vec(field(outcomes[i], op, "u_plus"), at(op, "u_plus"));
        for (const Vec* v : {&d.u_minus, &d.u_plus})
            if (v->size() != law.n)
                malformed(at(op, v == &d.u_minus ? "u_minus" : "u_plus"), "expected one velocity per ball");
        law.outcomes.push_back(std::move(d));
    }
    if (j.contains("claims")) {
        law.claims_given = true;
        const Json& claims = field(j, path, "claims");
        if (!claims.is_array())
            malformed(at(path, "claims"), "expected an array");
        require(!claims.empty(), at(path, "claims"), "no obligation claimed");
        for (std::size_t i = 0; i < claims.size(); ++i) {
            const std::string id = str(claims[i], at(at(path, "claims"), i));
            require(std::find(kIds.begin(), kIds.end(), id) != kIds.end(), at(at(path, "claims"), i), "unknown obligation");
            require(law.claimed_ids.insert(id).second, at(at(path, "claims"), i), "claimed twice");
            require(applies(j, id), at(at(path, "claims"), i), "claimed but the law declares nothing for it");
        }
    }
    return law;
}

// ---------------------------------------------------------------------------------------------
// Copositivity evidence: returns whether the evidence proves A copositive; rejects evidence
// that is wrong. For the KKT method the checker re-enumerates every face itself.

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

// The prover's bound (src/copositivity.cpp): 2^n - 1 faces, refused before the enumeration,
// and before 1 << n could overflow.
void check_face_limit(std::size_t n, std::size_t max_faces, const std::string& path) {
    if (n >= 63 || (std::size_t{1} << n) - 1 > max_faces)
        undecided("--max-faces", path,
                  "the KKT enumeration of a " + std::to_string(n) + "x" + std::to_string(n) + " form has 2^" +
                      std::to_string(n) + " - 1 faces, more than " + std::to_string(max_faces));
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
        for (std::size_t mask = 1; mask < (std::size_t{1} << n); ++mask) {
            std::vector<std::size_t> J;
            for (std::size_t i = 0; i < n; ++i)
                if (mask >> i & 1)
                    J.push_back(i);
            Mat K = zeros(J.size() + 1, J.size() + 1);
            for (std::size_t a = 0; a < J.size(); ++a) {
                for (std::size_t b = 0; b < J.size(); ++b)
                    K[a][b] = A[J[a]][J[b]];
                K[a][J.size()] = 1;
                K[J.size()][a] = 1;
            }
            Vec rhs(J.size() + 1, Q(0)), y;
            rhs[J.size()] = 1;
            if (!solve(K, rhs, y))
                continue;
            Vec x(y.begin(), y.end() - 1);
            if (!positive(x))
                continue;
            const Q value = -y.back();
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

// ---------------------------------------------------------------------------------------------
// Obligations

int sign_det2(const Vec& a, const Vec& b) { return sgn(a[0] * b[1] - a[1] * b[0]); }

// Angle of v measured counter-clockwise from a, as (half, v): comparable with ccw_less.
bool ccw_before(const Vec& a, const Vec& x, const Vec& y) {
    auto half = [&](const Vec& v) { return (sign_det2(a, v) > 0 || (sign_det2(a, v) == 0 && sgn(dot(a, v)) > 0)) ? 0 : 1; };
    if (half(x) != half(y))
        return half(x) < half(y);
    return sign_det2(x, y) > 0;
}

class Checker {
  public:
    Checker(const Law& law, const Json& obligations, const Limits& limits) : law_(law), obl_(obligations), limits_(limits) {}

    enum class Truth { proved, refuted, undecided };

    // Decides obligation k's truth; rejects evidence or witnesses that are wrong, and a verdict
    // that does not follow. Dependencies run one way only (fan and P1 depend on nothing else),
    // so this never recurses without bound.
    Truth holds(std::size_t k) {
        if (auto it = decided_.find(kIds[k]); it != decided_.end())
            return it->second;
        // check() has validated the obligation's keys, and visits obligations in order: the
        // only ones reached from here out of order (fan, P1) come first.
        const Json& o = obl_[k];
        const std::string path = at("$.obligations", k);
        const std::string verdict = str(field(o, path, "verdict"), at(path, "verdict"));
        const Json& data = field(o, path, "data");
        if (!data.is_object())
            malformed(at(path, "data"), "expected an object");
        Truth truth;
        if (verdict == "undecided") {
            // A limit was reached: nothing is claimed, so nothing is checked but the shape, and
            // that the prover could have stopped there.
            require(data.empty(), at(path, "data"), "an undecided obligation carries no evidence");
            could_be_undecided(kIds[k], str(field(o, path, "limit"), at(path, "limit")), at(path, "limit"));
            truth = Truth::undecided;
        } else {
            require(!o.contains("limit"), at(path, "limit"), "only an undecided obligation names a limit");
            // Every listed piece of evidence must be right, whatever the verdict.
            const bool local = evidence(kIds[k], data, at(path, "data"));
            if (verdict == "refuted") {
                check_witness(kIds[k], field(o, path, "counterexample"), at(path, "counterexample"), local);
                truth = Truth::refuted;
            } else if (verdict == "proved") {
                bool follows = local;
                if (kIds[k] == "kinematic" || kIds[k] == "nonexpansive" || kIds[k] == "nonexpansive-lemma")
                    follows = follows && s_is_a_function(path);
                if (kIds[k] == "nonexpansive-lemma")
                    follows = follows && holds("P1") == Truth::proved;
                require(follows, at(path, "verdict"), "\"proved\" does not follow from the evidence");
                truth = Truth::proved;
            } else {
                malformed(at(path, "verdict"), "unknown verdict");
            }
        }
        decided_[kIds[k]] = truth;
        return truth;
    }

  private:
    const Law& law_;
    const Json& obl_;
    const Limits& limits_;
    std::map<std::string, Truth> decided_;
    std::vector<Vec> fan_points_;              // the fan's validated test points (when decided)
    std::vector<std::size_t> fan_cover_;       // how many open cones contain each of them
    std::optional<bool> face_to_face_;        // the fast path of the fan holds
    std::optional<bool> walls_tile_;          // the cones tile R^c (decided by walls)
    std::optional<std::optional<Json>> domain_; // the canonical domain witness, if any
    std::vector<std::size_t> q_class_, next_other_; // see number_matrices
    std::size_t distinct_pairs_ = 0;
    std::map<std::size_t, Mat> products_;       // identity index -> its product

    Truth holds(const std::string& id) {
        return holds(static_cast<std::size_t>(std::find(kIds.begin(), kIds.end(), id) - kIds.begin()));
    }
    const Piece& pc(std::size_t p) const { return law_.pieces[p]; }
    const std::string& name(std::size_t p) const { return law_.pieces[p].name; }
    std::size_t P() const { return law_.pieces.size(); }

    static const Json& list(const Json& data, const std::string& dp, const char* key) {
        const Json& l = field(data, dp, key);
        if (!l.is_array())
            malformed(at(dp, key), "expected an array");
        return l;
    }
    static void expect_vec(const Json& j, const std::string& path, const char* key, const Vec& v, const char* what) {
        require(vec(field(j, path, key), at(path, key)) == v, at(path, key), std::string("is not ") + what);
    }
    static void expect_mat(const Json& j, const std::string& path, const char* key, const Mat& m, const char* what) {
        require(mat(field(j, path, key), at(path, key)) == m, at(path, key), std::string("is not ") + what);
    }
    void expect_piece(const Json& j, const std::string& path, const char* key, std::size_t p) const {
        require(str(field(j, path, key), at(path, key)) == name(p), at(path, key), "expected piece \"" + name(p) + "\"");
    }
    Mat QtHQ(std::size_t p) const { return mul(mul(tr(pc(p).Q_), law_.H), pc(p).Q_); }

    // Evidence lists are canonical: in order, up to and including the first failing entry, or
    // complete when nothing fails. A failing entry anywhere but last is rejected here; a list
    // that stops early without a failure is rejected by the callers' completeness checks.
    static void ends_at_first_failure(bool entry_ok, std::size_t index, std::size_t listed, const std::string& path) {
        require(entry_ok || index + 1 == listed, at(path, index), "evidence must end at the first failing entry");
    }
    static void complete_unless_failed(bool any_failed, std::size_t listed, std::size_t total, const std::string& path) {
        require(any_failed || listed == total, path, "is incomplete");
    }

    // Whether the prover can have left obligation `id` undecided with this `limit` text. In the
    // prover (src/obligations.cpp) only three decisions throw LimitExceeded: the fan's chamber
    // enumeration (--max-chambers), P1's intersections (--max-subsets) and a KKT enumeration
    // (--max-faces). So: fan by --max-chambers; P1 by --max-subsets (a fan beyond its limit only
    // sends P1 to the intersections); kinematic by the fan's limit once every ray's image is
    // non-negative; energetic by --max-faces; nonexpansive by --max-faces, or by the fan's limit;
    // nonexpansive-lemma by the fan's limit or, once S is a function, P1's. P2, P3, kinetic,
    // identities, single-impacts and outcomes have no limit, so a refutation cannot hide there.
    void could_be_undecided(const std::string& id, const std::string& limit, const std::string& path) {
        std::vector<std::string> options;
        if (id == "fan" || id == "kinematic")
            options = {"--max-chambers"};
        else if (id == "P1")
            options = {"--max-subsets"};
        else if (id == "energetic")
            options = {"--max-faces"};
        else if (id == "nonexpansive")
            options = {"--max-faces", "--max-chambers"};
        else if (id == "nonexpansive-lemma")
            options = {"--max-chambers", "--max-subsets"};
        require(!options.empty(), path, "the prover decides " + id + " without a limit: it cannot be undecided");
        std::string option, expected;
        for (const auto& o : options) {
            const std::string tail = " (raise it with " + o + ")";
            if (limit.size() > tail.size() && limit.compare(limit.size() - tail.size(), tail.size(), tail) == 0)
                option = o;
            expected += (expected.empty() ? "" : " or ") + o;
        }
        require(!option.empty(), path, "names no limit that can stop " + id + " (expected \"... (raise it with " + expected + ")\")");
        if (id == "fan")
            require(law_.c != 2 && !facet_criterion() && !walls_tile(), path,
                    "the fan is decided without enumerating chambers");
        else if (option == "--max-chambers")
            require(holds("fan") == Truth::undecided, path, "the fan is not undecided");
        if (id == "kinematic")
            for (std::size_t p = 0; p < P(); ++p)
                for (const auto& r : pc(p).rays)
                    require(nonneg(mul(pc(p).Q_, r)), path,
                            "a ray's image is negative: the prover refutes kinematic before it needs the fan");
        if (id == "P1")
            require(!face_to_face(), path, "the cones meet face to face: P1 is decided on shared rays, without a limit");
        if (id == "nonexpansive" && option == "--max-faces" && holds("fan") != Truth::undecided)
            require(!domain_witness(), path, "S is not a function: the prover refutes nonexpansive by the domain witness");
        if (id == "nonexpansive-lemma" && option == "--max-subsets")
            require(holds("fan") != Truth::undecided && !domain_witness() && holds("P1") == Truth::undecided, path,
                    "P1 is decided, or S is not a function: the lemma does not stop at P1's limit");
    }

    // ---- evidence: checks each listed entry; returns true when the list is complete and the
    // obligation holds on it.
    bool evidence(const std::string& id, const Json& data, const std::string& dp) {
        const std::size_t c = law_.c;
        if (id == "fan") {
            if (law_.c == 2) {
                expect_keys(data, dp, {"rays_by_angle", "sector_points"});
                return fan_planar(data, dp);
            }
            if (facet_criterion()) {
                expect_keys(data, dp, {"facets", "generic_point"});
                return fan_facets(data, dp);
            }
            if (walls_tile()) {
                expect_keys(data, dp, {"hyperplanes", "generic_point"});
                const std::vector<Vec> planes = facet_hyperplanes();
                require(listed_rays(field(data, dp, "hyperplanes"), at(dp, "hyperplanes")) == planes, at(dp, "hyperplanes"),
                        "are not the facet hyperplanes (canonical normals, sorted)");
                const Vec x0 = vec(field(data, dp, "generic_point"), at(dp, "generic_point"));
                require(x0 == first_generic(planes, law_.c), at(dp, "generic_point"),
                        "is not the first point of the moment curve off every facet hyperplane");
                require(law_.interiors(x0).size() == 1, at(dp, "generic_point"), "is not covered once");
                fan_points_ = {x0};
                fan_cover_ = {1};
                return true;
            }
            expect_keys(data, dp, {"hyperplanes", "chamber_points"});
            return fan_chambers(data, dp);
        }
        if (id == "P1" && !face_to_face()) {
            expect_keys(data, dp, {"intersections"});
            return p1_intersections(data, dp);
        }
        if (id == "P1") {
            expect_keys(data, dp, {}, {"shared"});
            const Json& l = data.contains("shared") ? list(data, dp, "shared") : Json::array();
            // One more than listed: enough to tell a complete list from an incomplete one.
            const auto shared = shared_rays(l.size() + 1);
            require(l.size() <= shared.size(), at(dp, "shared"), "lists more rays than are shared");
            bool ok = true;
            for (std::size_t k = 0; k < l.size(); ++k) {
                const auto& [i, j, v] = shared[k];
                const std::string ep = at(at(dp, "shared"), k);
                expect_keys(l[k], ep, {"piece_a", "piece_b", "ray", "image_a", "image_b"});
                expect_piece(l[k], ep, "piece_a", i);
                expect_piece(l[k], ep, "piece_b", j);
                expect_vec(l[k], ep, "ray", v, "the shared ray");
                expect_vec(l[k], ep, "image_a", mul(pc(i).Q_, v), "Q_a ray");
                expect_vec(l[k], ep, "image_b", mul(pc(j).Q_, v), "Q_b ray");
                const bool this_ok = mul(pc(i).Q_, v) == mul(pc(j).Q_, v);
                ends_at_first_failure(this_ok, k, l.size(), at(dp, "shared"));
                ok = ok && this_ok;
            }
            complete_unless_failed(!ok, l.size(), shared.size(), at(dp, "shared"));
            return ok;
        }
        if (id == "P2") {
            expect_keys(data, dp, {"QtHQ"});
            const Json& l = list(data, dp, "QtHQ");
            require(l.size() <= P(), at(dp, "QtHQ"), "too many entries");
            bool ok = true;
            for (std::size_t p = 0; p < l.size(); ++p) {
                const std::string ep = at(at(dp, "QtHQ"), p);
                expect_keys(l[p], ep, {"piece", "matrix"});
                expect_piece(l[p], ep, "piece", p);
                const Mat m = QtHQ(p);
                expect_mat(l[p], ep, "matrix", m, "Q^T H Q");
                const bool this_ok = m == law_.H;
                ends_at_first_failure(this_ok, p, l.size(), at(dp, "QtHQ"));
                ok = ok && this_ok;
            }
            complete_unless_failed(!ok, l.size(), P(), at(dp, "QtHQ"));
            return ok;
        }
        if (id == "P3" || id == "kinematic" || id == "kinetic") {
            const char* key = id == "kinetic" ? "impulses" : "images";
            const char* value = id == "kinetic" ? "impulse" : "image";
            expect_keys(data, dp, {key});
            const Json& l = list(data, dp, key);
            require(l.size() <= P() * c, at(dp, key), "too many entries");
            bool ok = true;
            for (std::size_t k = 0; k < l.size(); ++k) {
                const std::size_t p = k / c;
                const Vec& r = pc(p).rays[k % c];
                const std::string ep = at(at(dp, key), k);
                expect_keys(l[k], ep, {"piece", "ray", value});
                expect_piece(l[k], ep, "piece", p);
                expect_vec(l[k], ep, "ray", r, "the piece's ray");
                const Vec img = mul(pc(p).Q_, r);
                bool this_ok = true;
                if (id == "kinetic") {
                    const Vec impulse = mul(law_.H, sub(img, r));
                    expect_vec(l[k], ep, "impulse", impulse, "H (Q - I) ray");
                    this_ok = nonneg(impulse);
                } else {
                    expect_vec(l[k], ep, "image", img, "Q ray");
                    if (id == "kinematic") {
                        this_ok = nonneg(img);
                    } else {
                        std::size_t nz = 0, axis = 0;
                        for (std::size_t i = 0; i < c; ++i)
                            if (sgn(img[i]) != 0) {
                                ++nz;
                                axis = i;
                            }
                        bool distinct = true;
                        for (std::size_t other = p * c; other < k; ++other)
                            distinct = distinct && primitive(mul(pc(p).Q_, pc(p).rays[other % c])) != primitive(img);
                        this_ok = nz == 1 && sgn(img[axis]) > 0 && distinct;
                    }
                }
                ends_at_first_failure(this_ok, k, l.size(), at(dp, key));
                ok = ok && this_ok;
            }
            complete_unless_failed(!ok, l.size(), P() * c, at(dp, key));
            return ok;
        }
        if (id == "energetic") {
            expect_keys(data, dp, {"pieces"});
            const Json& l = list(data, dp, "pieces");
            require(l.size() <= P(), at(dp, "pieces"), "too many entries");
            bool ok = true;
            for (std::size_t p = 0; p < l.size(); ++p) {
                const std::string ep = at(at(dp, "pieces"), p);
                expect_keys(l[p], ep, {"piece", "B", "certificate"});
                expect_piece(l[p], ep, "piece", p);
                const Mat B = mul(mul(tr(pc(p).R), sub(law_.H, QtHQ(p))), pc(p).R);
                expect_mat(l[p], ep, "B", B, "R^T (H - Q^T H Q) R");
                const bool this_ok =
                    check_copositive_evidence(B, field(l[p], ep, "certificate"), at(ep, "certificate"), limits_.max_faces);
                ends_at_first_failure(this_ok, p, l.size(), at(dp, "pieces"));
                ok = ok && this_ok;
            }
            complete_unless_failed(!ok, l.size(), P(), at(dp, "pieces"));
            return ok;
        }
        if (id == "identities") {
            const auto& decls = law_.identities;
            expect_keys(data, dp, {"products"});
            const Json& l = list(data, dp, "products");
            require(l.size() <= decls.size(), at(dp, "products"), "too many entries");
            bool ok = true;
            for (std::size_t i = 0; i < l.size(); ++i) {
                const std::string ep = at(at(dp, "products"), i);
                expect_keys(l[i], ep, {"lhs", "product", "lhs_matrix", "product_matrix"});
                require(field(l[i], ep, "lhs") == decls[i].lhs_json && field(l[i], ep, "product") == decls[i].product_json, ep,
                        "is not the declared identity");
                const Mat& prod = identity_product(i);
                const Mat& lhs = pc(decls[i].lhs).Q_;
                expect_mat(l[i], ep, "lhs_matrix", lhs, "Q_lhs");
                expect_mat(l[i], ep, "product_matrix", prod, "the product");
                ends_at_first_failure(lhs == prod, i, l.size(), at(dp, "products"));
                ok = ok && lhs == prod;
            }
            complete_unless_failed(!ok, l.size(), decls.size(), at(dp, "products"));
            return ok;
        }
        if (id == "single-impacts") {
            const auto& decls = law_.single_impacts;
            expect_keys(data, dp, {"impacts"});
            const Json& l = list(data, dp, "impacts");
            require(l.size() <= decls.size(), at(dp, "impacts"), "too many entries");
            bool ok = true;
            for (std::size_t i = 0; i < l.size(); ++i) {
                const std::string ep = at(at(dp, "impacts"), i);
                expect_keys(l[i], ep, {"piece", "contact", "restitution", "impact"});
                require(field(l[i], ep, "piece") == decls[i].piece_json &&
                            natural(field(l[i], ep, "contact"), at(ep, "contact")) == decls[i].contact &&
                            rat(field(l[i], ep, "restitution"), at(ep, "restitution")) == decls[i].restitution,
                        ep, "is not the declared single impact");
                const Mat impact = law_.impact(decls[i].contact - 1, decls[i].restitution);
                expect_mat(l[i], ep, "impact", impact, "Q^(k)(e)");
                const bool this_ok = pc(decls[i].piece).Q_ == impact;
                ends_at_first_failure(this_ok, i, l.size(), at(dp, "impacts"));
                ok = ok && this_ok;
            }
            complete_unless_failed(!ok, l.size(), decls.size(), at(dp, "impacts"));
            return ok;
        }
        if (id == "nonexpansive") {
            // S undefined or two-valued: refuted before any pair is examined.
            if (holds("fan") != Truth::undecided && domain_witness()) {
                require(data.empty(), dp, "lists pairs although S is not a function");
                return false;
            }
            expect_keys(data, dp, {"pairs"});
            const Json& l = list(data, dp, "pairs");
            require(l.size() <= P() * P(), at(dp, "pairs"), "too many entries");
            bool ok = true;
            for (std::size_t k = 0; k < l.size(); ++k) {
                const std::size_t i = k / P(), j = k % P();
                const std::string ep = at(at(dp, "pairs"), k);
                expect_keys(l[k], ep, {"piece_a", "piece_b", "A", "certificate"});
                expect_piece(l[k], ep, "piece_a", i);
                expect_piece(l[k], ep, "piece_b", j);
                const Mat A = pair_form(i, j);
                expect_mat(l[k], ep, "A", A, "the pair's quadratic form");
                const bool this_ok =
                    check_copositive_evidence(A, field(l[k], ep, "certificate"), at(ep, "certificate"), limits_.max_faces);
                ends_at_first_failure(this_ok, k, l.size(), at(dp, "pairs"));
                ok = ok && this_ok;
            }
            complete_unless_failed(!ok, l.size(), P() * P(), at(dp, "pairs"));
            return ok;
        }
        if (id == "nonexpansive-lemma") {
            expect_keys(data, dp, {}, {"pieces"});
            const Json& l = data.contains("pieces") ? list(data, dp, "pieces") : Json::array();
            require(l.size() <= P(), at(dp, "pieces"), "too many entries");
            for (std::size_t p = 0; p < l.size(); ++p) {
                const std::string ep = at(at(dp, "pieces"), p);
                expect_keys(l[p], ep, {"piece", "matrix", "L", "D"});
                expect_piece(l[p], ep, "piece", p);
                const Mat B = sub(law_.H, QtHQ(p));
                expect_mat(l[p], ep, "matrix", B, "H - Q^T H Q");
                check_psd_evidence(B, l[p], ep);
            }
            if (!s_is_a_function(at(dp, "pieces")) || holds("P1") != Truth::proved) {
                require(l.empty(), at(dp, "pieces"), "listed although S is not a function or P1 is not proved");
                return false;
            }
            if (l.size() < P()) {
                require(psd_witness(sub(law_.H, QtHQ(l.size()))).has_value(), at(dp, "pieces"), "is incomplete");
                return false;
            }
            return true;
        }
        if (id == "outcomes") {
            const auto& decls = law_.outcomes;
            expect_keys(data, dp, {}, {"outcomes"});
            const Json& l = data.contains("outcomes") ? list(data, dp, "outcomes") : Json::array();
            require(l.size() <= decls.size(), at(dp, "outcomes"), "too many entries");
            bool ok = true;
            for (std::size_t i = 0; i < l.size(); ++i) {
                const std::string ep = at(at(dp, "outcomes"), i);
                expect_keys(l[i], ep, {"outcome", "gamma_minus", "pieces"});
                require(str(field(l[i], ep, "outcome"), at(ep, "outcome")) == decls[i].name, at(ep, "outcome"),
                        "is not the declared outcome");
                const Vec& u = decls[i].u_minus;
                const Vec g = mul(tr(law_.W), u);
                expect_vec(l[i], ep, "gamma_minus", g, "W^T u-");
                const bool this_ok = check_outcome_pieces(field(l[i], ep, "pieces"), at(ep, "pieces"), u, g, decls[i].u_plus);
                ends_at_first_failure(this_ok, i, l.size(), at(dp, "outcomes"));
                ok = ok && this_ok;
            }
            if (l.size() < decls.size() && ok) {
                // Only an outcome whose gamma- lies in no cone ends the list without an entry.
                const Vec g = mul(tr(law_.W), decls[l.size()].u_minus);
                for (std::size_t q = 0; q < P(); ++q)
                    require(!law_.in_cone(q, g), at(dp, "outcomes"), "is incomplete");
                return false;
            }
            return ok;
        }
        malformed(dp, "unknown obligation");
    }

    // The list of (piece, u+) for every piece containing gamma-; true when all give `declared`.
    bool check_outcome_pieces(const Json& l, const std::string& lp, const Vec& u, const Vec& g, const Vec& declared) {
        std::vector<std::size_t> containing;
        for (std::size_t p = 0; p < P(); ++p)
            if (law_.in_cone(p, g))
                containing.push_back(p);
        require(l.is_array() && l.size() == containing.size(), lp, "is not the list of pieces containing gamma-");
        bool ok = !containing.empty();
        for (std::size_t k = 0; k < containing.size(); ++k) {
            const std::string ep = at(lp, k);
            expect_keys(l[k], ep, {"piece", "u_plus"});
            expect_piece(l[k], ep, "piece", containing[k]);
            const Vec up = law_.u_plus(u, g, mul(pc(containing[k]).Q_, g));
            expect_vec(l[k], ep, "u_plus", up, "the post-impact velocities");
            ok = ok && up == declared;
        }
        return ok;
    }

    // The canonical negative direction of a symmetric matrix (the congruence elimination of
    // proofs/README.md, "Exact copositivity", step 2), or nothing when it is PSD.
    static std::optional<Vec> psd_witness(const Mat& A) {
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
    static Vec kkt_minimiser(const Json& cert, const std::string& path, std::size_t n) {
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

    // The last entry of another obligation's evidence list (evidence() has checked its keys).
    const Json& last_entry(const std::string& id, const char* key) const {
        const std::size_t k = static_cast<std::size_t>(std::find(kIds.begin(), kIds.end(), id) - kIds.begin());
        const std::string dp = at(at("$.obligations", k), "data");
        const Json& data = field(obl_[k], at("$.obligations", k), "data");
        if (!data.is_object() || !data.contains(key) || !data.at(key).is_array() || data.at(key).empty())
            reject(dp, "the refutation's evidence is missing");
        return data.at(key).back();
    }

    // The prover's interior_witness (src/copositivity.cpp): z + eps 1 for the first eps in
    // 1, 1/2, 1/4, ... with f(z + eps 1) < 0, where f(x) = x^T A x and f(z) < 0. Halving one
    // step at a time takes log2(1/eps) steps, which a law can make huge (Q = -(1 + 10^-10000)
    // needs 33,000 halvings of 10,000-digit numbers). But g(eps) = f(z + eps 1) is a quadratic
    // with g(0) < 0: when g(1) >= 0, g is negative on (0, r) and non-negative on [r, 1] for its
    // least positive root r (a third sign change would need a third root). So "g(2^-k) < 0" is
    // false and then true for good as k grows, and its first k is found by doubling and
    // bisection: O(log k) evaluations, k bounded by the bit length of g's coefficients.
    static Vec moved_inside(const Mat& A, const Vec& z, const std::string& path) {
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

    // Entries of a product of identity factors grow with the number of factors: a bound on
    // their size (bits of numerator and denominator), from the factors, checked before
    // multiplying. Q = N / d with d the common denominator: a product of k factors has entries
    // (N_1 ... N_k)_ij / (d_1 ... d_k) with |(N_1 ... N_k)_ij| <= c^(k-1) prod max |N_f|.
    std::size_t factor_bits(std::size_t p) const {
        mpz_class d = 1, top = 0;
        for (const auto& row : pc(p).Q_)
            for (const auto& x : row)
                d = lcm(d, x.get_den());
        for (const auto& row : pc(p).Q_)
            for (const auto& x : row)
                top = std::max(top, mpz_class(abs(x.get_num()) * (d / x.get_den())));
        return mpz_sizeinbase(top.get_mpz_t(), 2) + mpz_sizeinbase(d.get_mpz_t(), 2) +
               mpz_sizeinbase(mpz_class(law_.c).get_mpz_t(), 2);
    }

    // Identity i's product, by balanced splitting: exact products are associative, and halves
    // of equal length keep the operands balanced, so the cost is quasi-linear in the size of the
    // result instead of quadratic in the number of factors (left to right, each factor
    // multiplies an ever larger matrix). A product whose entries may exceed --max-product-bits
    // (the checker's own limit: the prover multiplies without one) is not computed.
    const Mat& identity_product(std::size_t i) {
        if (auto it = products_.find(i); it != products_.end())
            return it->second;
        const auto& factors = law_.identities[i].product;
        std::size_t bound = 0;
        for (auto f : factors)
            bound = std::min<std::size_t>(SIZE_MAX / 2, bound + factor_bits(f));
        if (bound > limits_.max_product_bits)
            undecided("--max-product-bits", at(at("$.law.identities", i), "product"),
                      "the product of " + std::to_string(factors.size()) + " factors may have entries of " +
                          std::to_string(bound) + " bits, more than " + std::to_string(limits_.max_product_bits));
        std::function<Mat(std::size_t, std::size_t)> product = [&](std::size_t lo, std::size_t hi) {
            if (hi - lo == 1)
                return pc(factors[lo]).Q_;
            const std::size_t mid = lo + (hi - lo) / 2;
            return mul(product(lo, mid), product(mid, hi));
        };
        return products_[i] = product(0, factors.size());
    }

    Mat pair_form(std::size_t i, std::size_t j) const {
        const std::size_t c = law_.c;
        const Mat QRi = mul(pc(i).Q_, pc(i).R), QRj = mul(pc(j).Q_, pc(j).R);
        Mat B1 = zeros(c, 2 * c), B2 = zeros(c, 2 * c);
        for (std::size_t r = 0; r < c; ++r)
            for (std::size_t k = 0; k < c; ++k) {
                B1[r][k] = pc(i).R[r][k];
                B1[r][c + k] = -pc(j).R[r][k];
                B2[r][k] = QRi[r][k];
                B2[r][c + k] = -QRj[r][k];
            }
        return sub(mul(mul(tr(B1), law_.H), B1), mul(mul(tr(B2), law_.H), B2));
    }

    // The test direction of the sector from lo to hi: lo + hi when the sector spans less than
    // pi, else the quarter turn of lo.
    static Vec sector_point(const Vec& lo, const Vec& hi, std::size_t m) {
        if (m > 1 && sign_det2(lo, hi) > 0)
            return Vec{lo[0] + hi[0], lo[1] + hi[1]};
        return Vec{-lo[1], lo[0]};
    }

    // The distinct rays (c = 2) in angular order from the positive gamma1 axis, as the prover
    // sorts them.
    std::vector<Vec> rays_by_angle() const {
        std::vector<Vec> sorted = law_.distinct_rays;
        auto half = [](const Vec& v) { return (sgn(v[1]) > 0 || (sgn(v[1]) == 0 && sgn(v[0]) > 0)) ? 0 : 1; };
        std::sort(sorted.begin(), sorted.end(), [&](const Vec& a, const Vec& b) {
            return half(a) != half(b) ? half(a) < half(b) : sign_det2(a, b) > 0;
        });
        return sorted;
    }

    // For c = 2: how many open cones contain each open sector (sector k runs counter-clockwise
    // from sorted[k] to sorted[k + 1]). A cone's rays are two of the sorted rays, so the cone
    // contains exactly the sectors of the arc (less than pi) between them: one pass over the
    // pieces with a circular difference array, instead of testing every piece at every sector
    // point (P^2 work for P sectors).
    std::vector<std::size_t> planar_cover(const std::vector<Vec>& sorted) const {
        const std::size_t m = sorted.size();
        std::map<Vec, std::size_t> position;
        for (std::size_t k = 0; k < m; ++k)
            position[sorted[k]] = k;
        std::vector<long> delta(m + 1, 0);
        for (std::size_t p = 0; p < P(); ++p) {
            const Vec &r0 = pc(p).rays[0], &r1 = pc(p).rays[1];
            // Counter-clockwise from `from` to `to` spans less than pi (the rays are independent).
            const bool ccw = sign_det2(r0, r1) > 0;
            const std::size_t from = position.at(ccw ? r0 : r1), to = position.at(ccw ? r1 : r0);
            ++delta[from];
            --delta[to];
            if (from > to) { // wraps past sorted[0]
                ++delta[0];
                --delta[m];
            }
        }
        std::vector<std::size_t> cover;
        long running = 0;
        for (std::size_t k = 0; k < m; ++k)
            cover.push_back(static_cast<std::size_t>(running += delta[k]));
        return cover;
    }

    bool fan_planar(const Json& data, const std::string& dp) {
        require(law_.c == 2, at(dp, "rays_by_angle"), "the angular method needs c = 2");
        std::vector<Vec> listed;
        const Json& rl = list(data, dp, "rays_by_angle");
        for (std::size_t k = 0; k < rl.size(); ++k)
            listed.push_back(vec(rl[k], at(at(dp, "rays_by_angle"), k)));
        const std::vector<Vec> sorted = rays_by_angle();
        std::vector<Vec> a = listed, b = sorted;
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        require(a == b, at(dp, "rays_by_angle"), "is not the set of distinct rays");
        require(listed == sorted, at(dp, "rays_by_angle"), "not in angular order from the positive gamma1 axis");
        const std::size_t m = sorted.size();
        const Json& points = list(data, dp, "sector_points");
        require(points.size() == m, at(dp, "sector_points"), "is not one point per sector");
        fan_points_.clear();
        for (std::size_t k = 0; k < points.size(); ++k) {
            const Vec d = vec(points[k], at(at(dp, "sector_points"), k));
            require(d.size() == 2, at(at(dp, "sector_points"), k), "wrong size");
            const Vec &lo = sorted[k], &hi = sorted[(k + 1) % m];
            require(d == sector_point(lo, hi, m), at(at(dp, "sector_points"), k), "is not the sector's test direction");
            const bool on_lo = sign_det2(lo, d) == 0 && sgn(dot(lo, d)) > 0;
            require(!on_lo && ccw_before(lo, d, hi), at(at(dp, "sector_points"), k), "not strictly inside its sector");
            fan_points_.push_back(d);
        }
        // Each point is strictly inside its sector, so the cones containing it are those
        // containing the sector.
        fan_cover_ = planar_cover(sorted);
        return std::all_of(fan_cover_.begin(), fan_cover_.end(), [](std::size_t n) { return n == 1; });
    }

    // Facets keyed by their ray ids (first appearance in the law), owners in piece order.
    std::size_t ray_id(const Vec& r) const { return law_.ray_index.at(r); }
    std::map<std::vector<std::size_t>, std::vector<std::pair<std::size_t, int>>> all_facets() const {
        std::map<std::vector<std::size_t>, std::vector<std::pair<std::size_t, int>>> facets;
        for (std::size_t p = 0; p < P(); ++p)
            for (std::size_t drop = 0; drop < law_.c; ++drop) {
                std::vector<std::size_t> ids;
                for (std::size_t k = 0; k < law_.c; ++k)
                    if (k != drop)
                        ids.push_back(ray_id(pc(p).rays[k]));
                std::sort(ids.begin(), ids.end());
                std::vector<Vec> cols;
                for (auto id : ids)
                    cols.push_back(law_.distinct_rays[id]);
                cols.push_back(pc(p).rays[drop]);
                facets[ids].push_back({p, sgn(det(from_cols(cols)))});
            }
        return facets;
    }
    std::vector<Vec> facet_rays(const std::vector<std::size_t>& ids) const {
        std::vector<Vec> out;
        for (auto id : ids)
            out.push_back(law_.distinct_rays[id]);
        return out;
    }
    std::vector<Vec> listed_rays(const Json& l, const std::string& path) const {
        std::vector<Vec> out;
        if (!l.is_array())
            malformed(path, "expected an array of rays");
        for (std::size_t r = 0; r < l.size(); ++r)
            out.push_back(vec(l[r], at(path, r)));
        return out;
    }
    std::vector<std::string> listed_names(const Json& l, const std::string& path) const {
        std::vector<std::string> out;
        if (!l.is_array())
            malformed(path, "expected an array of piece names");
        for (const auto& o : l)
            out.push_back(str(o, path));
        return out;
    }
    Vec generic_point() const {
        const auto facets = all_facets();
        for (long t = 1;; ++t) {
            Vec p(law_.c);
            Q power = 1;
            for (std::size_t i = 0; i < law_.c; ++i, power *= t)
                p[i] = power;
            bool generic = true;
            for (const auto& entry : facets) {
                std::vector<Vec> cols = facet_rays(entry.first);
                cols.push_back(p);
                generic = generic && sgn(det(from_cols(cols))) != 0;
            }
            if (generic)
                return p;
        }
    }

    bool fan_facets(const Json& data, const std::string& dp) {
        const auto facets = all_facets();
        const Json& l = list(data, dp, "facets");
        require(l.size() == facets.size(), at(dp, "facets"), "does not list every facet");
        bool ok = true;
        std::size_t k = 0;
        for (const auto& [ids, owners] : facets) {
            const std::string ep = at(at(dp, "facets"), k);
            expect_keys(l[k], ep, {"rays", "pieces"});
            require(listed_rays(field(l[k], ep, "rays"), at(ep, "rays")) == facet_rays(ids), at(ep, "rays"),
                    "is not the next facet");
            std::vector<std::string> names;
            for (const auto& [p, side] : owners)
                names.push_back(name(p));
            require(listed_names(field(l[k], ep, "pieces"), at(ep, "pieces")) == names, at(ep, "pieces"),
                    "are not the cones having this facet");
            ok = ok && owners.size() == 2 && owners[0].second != owners[1].second;
            ++k;
        }
        if (!ok) {
            require(!data.contains("generic_point"), at(dp, "generic_point"), "listed although a facet is unmatched");
            return false;
        }
        const Vec p = vec(field(data, dp, "generic_point"), at(dp, "generic_point"));
        require(p == generic_point(), at(dp, "generic_point"), "is not the first generic point of the moment curve");
        fan_points_ = {p};
        fan_cover_ = {law_.interiors(p).size()};
        return fan_cover_[0] == 1;
    }

    // The fast path: every facet shared by exactly two cones on opposite sides, and the first
    // generic point of the moment curve covered once.
    bool facet_criterion() const {
        for (const auto& [ids, owners] : all_facets())
            if (owners.size() != 2 || owners[0].second == owners[1].second)
                return false;
        return law_.interiors(generic_point()).size() == 1;
    }

    // The cones tile R^c, decided by walls (the checker's own recursion).
    bool walls_tile() {
        if (!walls_tile_) {
            std::vector<WCone> family;
            for (std::size_t p = 0; p < P(); ++p)
                family.push_back({pc(p).rays, 1});
            walls_tile_ = walls_balance(family, law_.c, 1);
        }
        return *walls_tile_;
    }

    // Pairs i < j, Q_i != Q_j, with facets in one hyperplane on opposite sides.
    std::vector<std::pair<std::size_t, std::size_t>> across_walls() const {
        std::map<Vec, std::pair<std::set<std::size_t>, std::set<std::size_t>>> sides;
        for (std::size_t p = 0; p < P(); ++p)
            for (std::size_t drop = 0; drop < law_.c; ++drop) {
                std::vector<Vec> facet;
                for (std::size_t k = 0; k < law_.c; ++k)
                    if (k != drop)
                        facet.push_back(pc(p).rays[k]);
                const Vec n = canonical_line(kernel(facet, law_.c).at(0));
                (sgn(dot(n, pc(p).rays[drop])) > 0 ? sides[n].first : sides[n].second).insert(p);
            }
        std::set<std::pair<std::size_t, std::size_t>> out;
        for (const auto& [n, two] : sides)
            for (auto a : two.first)
                for (auto b : two.second)
                    if (a != b && pc(a).Q_ != pc(b).Q_)
                        out.insert({std::min(a, b), std::max(a, b)});
        return {out.begin(), out.end()};
    }

    // The cones form a fan meeting face to face (then P1 is decided on shared rays).
    bool face_to_face() {
        if (!face_to_face_) {
            if (law_.c == 2) {
                const auto cover = planar_cover(rays_by_angle());
                face_to_face_ = std::all_of(cover.begin(), cover.end(), [](std::size_t n) { return n == 1; });
            } else {
                face_to_face_ = facet_criterion();
            }
        }
        return *face_to_face_;
    }

    // The distinct facet hyperplanes, as sorted canonical normals.
    std::vector<Vec> facet_hyperplanes() const {
        std::set<Vec> out;
        for (std::size_t p = 0; p < P(); ++p)
            for (std::size_t drop = 0; drop < law_.c; ++drop) {
                std::vector<Vec> rows;
                for (std::size_t k = 0; k < law_.c; ++k)
                    if (k != drop)
                        rows.push_back(pc(p).rays[k]);
                out.insert(canonical_line(kernel(rows, law_.c).at(0)));
            }
        return {out.begin(), out.end()};
    }

    // Complete decision: the listed points lie on no facet hyperplane, in pairwise different
    // chambers, as many as the arrangement has (counted by deletion and restriction).
    bool fan_chambers(const Json& data, const std::string& dp) {
        const std::vector<Vec> planes = facet_hyperplanes();
        const Json& hl = list(data, dp, "hyperplanes");
        require(listed_rays(hl, at(dp, "hyperplanes")) == planes, at(dp, "hyperplanes"),
                "are not the facet hyperplanes (canonical normals, sorted)");
        const Json& pl = list(data, dp, "chamber_points");
        std::set<std::vector<int>> chambers;
        bool ok = true;
        fan_points_.clear();
        fan_cover_.clear();
        for (std::size_t k = 0; k < pl.size(); ++k) {
            const std::string ep = at(at(dp, "chamber_points"), k);
            const Vec x = vec(pl[k], ep);
            require(x.size() == law_.c, ep, "wrong size");
            std::vector<int> signs;
            for (const auto& n : planes) {
                signs.push_back(sgn(dot(n, x)));
                require(signs.back() != 0, ep, "lies on a facet hyperplane");
            }
            require(chambers.insert(signs).second, ep, "lies in the chamber of an earlier point");
            fan_cover_.push_back(law_.interiors(x).size());
            ok = ok && fan_cover_.back() == 1;
            fan_points_.push_back(x);
        }
        const std::size_t count = count_chambers(planes, law_.c, pl.size());
        require(count == pl.size(), at(dp, "chamber_points"),
                "misses a chamber: the arrangement has more chambers than points are listed");
        // Bounded by the listed points: each step of the enumeration emits at least one point;
        // and by the prover's --max-chambers, counted as the prover counts its steps.
        std::size_t budget = 4 * (pl.size() + 1) * (planes.size() + 1);
        ChamberSteps steps{0, limits_.max_chambers, at(dp, "chamber_points")};
        require(canonical_chamber_points(planes, law_.c, budget, steps) == fan_points_, at(dp, "chamber_points"),
                "are not the canonical chamber points (the prover's deletion and restriction)");
        return ok;
    }

    // Whether S is a function on R^c (no gap; overlapping interiors carry equal matrices), from
    // the fan's validated test points; rejects when the fan is undecided.
    bool s_is_a_function(const std::string& path) {
        const Truth fan = holds("fan");
        require(fan != Truth::undecided, path, "the fan is undecided: S is not known to be a function");
        return fan == Truth::proved || !domain_witness();
    }

    // The canonical witness that S is not a function (the prover's rule, proofs/README.md):
    // the first test point in no cone, or the first covered by two cones with different
    // matrices, moved off the kernel of their difference when needed.
    std::optional<Json> domain_witness() {
        if (domain_)
            return *domain_;
        domain_ = std::optional<Json>();
        if (holds("fan") != Truth::refuted)
            return *domain_;
        const std::size_t c = law_.c;
        for (std::size_t k = 0; k < fan_points_.size(); ++k) {
            if (fan_cover_[k] == 1)
                continue;
            const Vec& x = fan_points_[k];
            const auto cov = law_.interiors(x);
            if (cov.empty()) {
                domain_ = Json{{"via", "fan"}, {"gamma", jvec(x)}, {"interior_of", Json::array()},
                               {"reason", "S is undefined at gamma: it lies in no cone"}};
                return *domain_;
            }
            for (std::size_t u = 0; u < cov.size(); ++u)
                for (std::size_t v = u + 1; v < cov.size(); ++v) {
                    const std::size_t a = cov[u], b = cov[v];
                    const Mat diff = sub(pc(a).Q_, pc(b).Q_);
                    if (diff == zeros(c, c))
                        continue;
                    auto vanishes = [&](const Vec& y) {
                        const Vec d = mul(diff, y);
                        return std::all_of(d.begin(), d.end(), [](const Q& q) { return sgn(q) == 0; });
                    };
                    Vec y = x;
                    for (std::size_t e = 0; e < c && vanishes(y); ++e) {
                        Q delta = 1;
                        for (std::size_t p : {a, b}) {
                            const Vec sx = mul(pc(p).R_inv, x);
                            for (std::size_t i = 0; i < c; ++i)
                                if (sgn(pc(p).R_inv[i][e]) < 0)
                                    delta = std::min(delta, Q(sx[i] / (2 * abs(pc(p).R_inv[i][e]))));
                        }
                        y = x;
                        y[e] += delta;
                        y = primitive(y);
                    }
                    require(!vanishes(y), "$.obligations[0].data", "two different matrices agree on a basis");
                    Json names = Json::array();
                    for (auto p : law_.interiors(y))
                        names.push_back(name(p));
                    domain_ = Json{{"via", "fan"}, {"gamma", jvec(y)}, {"interior_of", names},
                                   {"reason", "S is two-valued near gamma: it is interior to two cones whose matrices differ there"}};
                    return *domain_;
                }
        }
        return *domain_;
    }

    static Json jvec(const Vec& v) {
        Json a = Json::array();
        for (const auto& x : v)
            a.push_back(x.get_str());
        return a;
    }

    // The extreme rays of C_i ∩ C_j = {R_i s : s >= 0, R_j^-1 R_i s >= 0}: for every choice of
    // c-1 of the 2c constraints whose solutions form a line, the directions on it that satisfy
    // all constraints. Primitive, sorted.
    std::vector<Vec> intersection_rays(std::size_t i, std::size_t j) const {
        const std::size_t c = law_.c;
        const Mat T = mul(pc(j).R_inv, pc(i).R);
        std::vector<Vec> cons;
        for (std::size_t k = 0; k < c; ++k) {
            Vec e(c, Q(0));
            e[k] = 1;
            cons.push_back(e);
        }
        for (const auto& row : T)
            cons.push_back(row);
        std::vector<Vec> out;
        std::vector<bool> chosen(cons.size(), false);
        std::fill(chosen.end() - static_cast<std::ptrdiff_t>(c - 1), chosen.end(), true);
        do {
            std::vector<Vec> rows;
            for (std::size_t k = 0; k < cons.size(); ++k)
                if (chosen[k])
                    rows.push_back(cons[k]);
            const auto line = kernel(rows, c);
            if (line.size() != 1)
                continue;
            for (int sign : {1, -1}) {
                Vec s = line[0];
                for (auto& x : s)
                    x *= sign;
                if (std::all_of(cons.begin(), cons.end(), [&](const Vec& g) { return sgn(dot(g, s)) >= 0; })) {
                    const Vec ray = primitive(mul(pc(i).R, s));
                    if (std::find(out.begin(), out.end(), ray) == out.end())
                        out.push_back(ray);
                }
            }
        } while (std::next_permutation(chosen.begin(), chosen.end()));
        std::sort(out.begin(), out.end());
        return out;
    }

    // C(2c, c-1): the constraint subsets intersection_rays tries for one pair, saturating at
    // the largest size_t (the prover's intersection_subsets, src/fan.cpp, without overflow).
    std::size_t subsets_per_pair() const {
        const std::size_t n = 2 * law_.c, k = law_.c - 1;
        mpz_class out;
        mpz_bin_uiui(out.get_mpz_t(), n, k);
        return out.fits_ulong_p() ? static_cast<std::size_t>(out.get_ui()) : SIZE_MAX;
    }

    // Pieces numbered by their matrix (equal Q, equal class), and for each piece the next one
    // after it in another class: enough to walk the pairs i < j with Q_i != Q_j in order
    // without listing them all (P^2 / 2 of them) or comparing matrices pair by pair.
    void number_matrices() {
        if (!q_class_.empty())
            return;
        std::map<Mat, std::size_t> classes;
        std::map<std::size_t, std::size_t> sizes;
        for (std::size_t p = 0; p < P(); ++p) {
            q_class_.push_back(classes.emplace(pc(p).Q_, classes.size()).first->second);
            ++sizes[q_class_.back()];
        }
        next_other_.assign(P(), P());
        for (std::size_t p = P() - 1; p-- > 0;)
            next_other_[p] = q_class_[p + 1] != q_class_[p] ? p + 1 : next_other_[p + 1];
        distinct_pairs_ = P() * (P() - 1) / 2;
        for (const auto& [cls, size] : sizes)
            distinct_pairs_ -= size * (size - 1) / 2;
    }
    // The pair after (i, j) (start with (0, 0)) among i < j with Q_i != Q_j; false at the end.
    bool next_distinct_pair(std::size_t& i, std::size_t& j) const {
        for (++j;; j = i + 1) {
            if (j <= i)
                j = i + 1;
            while (j < P() && q_class_[j] == q_class_[i])
                j = next_other_[j]; // the next piece in another class than j's, which is i's
            if (j < P())
                return true;
            if (++i >= P())
                return false;
        }
    }

    // P1 when the cones do not meet face to face: every pair with different matrices, the
    // extreme rays of the intersection of their cones, both matrices agreeing on each.
    bool p1_intersections(const Json& data, const std::string& dp) {
        // With a tiling (walls) only pairs across a common facet hyperplane, else every pair.
        const bool walls = law_.c != 2 && walls_tile();
        std::vector<std::pair<std::size_t, std::size_t>> wall_pairs;
        std::size_t count = 0;
        if (walls) {
            wall_pairs = across_walls();
            count = wall_pairs.size();
        } else {
            number_matrices();
            count = distinct_pairs_;
        }
        // The prover's --max-subsets (src/obligations.cpp), before any intersection is computed.
        const std::size_t per_pair = subsets_per_pair();
        if (count > 0 && per_pair > limits_.max_subsets / count)
            undecided("--max-subsets", at(dp, "intersections"),
                      "the intersections of " + std::to_string(count) + " pairs of cones need " + std::to_string(per_pair) +
                          " constraint subsets each, more than " + std::to_string(limits_.max_subsets) + " in all");
        const Json& l = list(data, dp, "intersections");
        require(l.size() <= count, at(dp, "intersections"), "too many entries");
        bool ok = true;
        std::size_t i = 0, j = 0;
        for (std::size_t k = 0; k < l.size(); ++k) {
            if (walls)
                std::tie(i, j) = wall_pairs[k];
            else
                next_distinct_pair(i, j);
            const std::string ep = at(at(dp, "intersections"), k);
            expect_keys(l[k], ep, {"piece_a", "piece_b", "rays"});
            expect_piece(l[k], ep, "piece_a", i);
            expect_piece(l[k], ep, "piece_b", j);
            const std::vector<Vec> rays = intersection_rays(i, j);
            require(listed_rays(field(l[k], ep, "rays"), at(ep, "rays")) == rays, at(ep, "rays"),
                    "are not the extreme rays of the intersection (primitive, sorted)");
            bool this_ok = true;
            for (const auto& r : rays)
                this_ok = this_ok && mul(pc(i).Q_, r) == mul(pc(j).Q_, r);
            ends_at_first_failure(this_ok, k, l.size(), at(dp, "intersections"));
            ok = ok && this_ok;
        }
        complete_unless_failed(!ok, l.size(), count, at(dp, "intersections"));
        return ok;
    }

    // The rays shared by two pieces, in the prover's order (pairs i < j, then the rays of i in
    // order), at most `limit` of them: generated from the pieces through each ray, so that the
    // work follows the evidence listed rather than the P^2 / 2 pairs.
    std::vector<std::tuple<std::size_t, std::size_t, Vec>> shared_rays(std::size_t limit) const {
        std::vector<std::vector<std::size_t>> through(law_.distinct_rays.size()); // pieces in order
        for (std::size_t p = 0; p < P(); ++p)
            for (const auto& r : pc(p).rays)
                through[ray_id(r)].push_back(p);
        std::vector<std::tuple<std::size_t, std::size_t, Vec>> out;
        for (std::size_t i = 0; i < P() && out.size() < limit; ++i) {
            std::vector<std::pair<std::size_t, std::size_t>> mine; // (j, index of the ray in i)
            for (std::size_t a = 0; a < law_.c; ++a) {
                // The first `limit` pieces after i through this ray (sorted) are all that can be
                // among the first `limit` pairs of piece i.
                const auto& ps = through[ray_id(pc(i).rays[a])];
                auto it = std::upper_bound(ps.begin(), ps.end(), i);
                for (std::size_t taken = 0; it != ps.end() && taken < limit; ++it, ++taken)
                    mine.emplace_back(*it, a);
            }
            std::sort(mine.begin(), mine.end());
            for (const auto& [j, a] : mine)
                if (out.size() < limit)
                    out.emplace_back(i, j, pc(i).rays[a]);
        }
        return out;
    }

    // ---- counterexamples, re-validated from scratch
    // A borrowed witness ("via") only where SPEC section 3 allows it: "fan" (S undefined or
    // two-valued on an open set) on kinematic, nonexpansive and nonexpansive-lemma; "P1" (a
    // discontinuity) on nonexpansive-lemma. Every witness is checked by itself, never by
    // consulting the verdict it borrows from.
    void check_witness(const std::string& id, const Json& w, const std::string& wp, bool local) {
        if (!w.is_object())
            malformed(wp, "expected an object");
        const std::string via = w.contains("via") ? str(field(w, wp, "via"), at(wp, "via")) : "";
        if (!via.empty()) {
            const bool allowed = (via == "fan" && (id == "kinematic" || id == "nonexpansive" || id == "nonexpansive-lemma")) ||
                                 (via == "P1" && id == "nonexpansive-lemma");
            require(allowed, at(wp, "via"), "a witness of \"" + via + "\" does not refute " + id);
        }
        if (via == "fan") {
            expect_keys(w, wp, {"via", "gamma", "interior_of", "reason"});
            str(field(w, wp, "reason"), at(wp, "reason"));
            require(holds("fan") != Truth::undecided, at(wp, "via"), "the fan is undecided");
            const auto canonical = domain_witness();
            require(canonical.has_value(), at(wp, "via"), "S is a function on R^c: nothing to borrow");
            const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
            // By itself: gamma in no closed cone, or interior to two cones whose images differ.
            const auto inside = law_.interiors(g);
            bool shows = false;
            if (inside.empty()) {
                shows = true;
                for (std::size_t p = 0; p < P(); ++p)
                    shows = shows && !law_.in_cone(p, g);
            }
            for (auto a : inside)
                for (auto b : inside)
                    shows = shows || mul(pc(a).Q_, g) != mul(pc(b).Q_, g);
            require(shows, at(wp, "gamma"), "S is defined and single-valued near gamma");
            require(w == *canonical, wp, "is not the canonical witness (the first test point where S is not a function)");
            if (id == "kinematic")
                require(local, wp, "a ray's image is negative: that is the canonical witness");
            return;
        }
        if (id == "fan") {
            expect_keys(w, wp, {"gamma", "interior_of", "reason"});
            str(field(w, wp, "reason"), at(wp, "reason"));
            const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
            const auto inside = law_.interiors(g);
            bool gap = inside.empty();
            for (std::size_t p = 0; p < P() && gap; ++p)
                gap = !law_.in_cone(p, g);
            require(gap || inside.size() >= 2, at(wp, "gamma"), "is neither in a gap nor in two interiors");
            std::size_t first = 0;
            while (first < fan_cover_.size() && fan_cover_[first] == 1)
                ++first;
            require(first < fan_points_.size() && g == fan_points_[first], at(wp, "gamma"),
                    "is not the first test point of the fan check covered k != 1 times");
            const auto listed = listed_names(field(w, wp, "interior_of"), at(wp, "interior_of"));
            std::vector<std::string> names;
            for (auto p : inside)
                names.push_back(name(p));
            require(listed == names, at(wp, "interior_of"), "are not the cones whose interior contains gamma");
            return;
        }
        if (id == "P1" || via == "P1") {
            expect_keys(w, wp, {"piece_a", "piece_b", "gamma", "image_a", "image_b"}, {"via"});
            const std::size_t a = law_.piece(field(w, wp, "piece_a"), at(wp, "piece_a"));
            const std::size_t b = law_.piece(field(w, wp, "piece_b"), at(wp, "piece_b"));
            const Vec v = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(v.size() == law_.c && law_.in_cone(a, v) && law_.in_cone(b, v), at(wp, "gamma"),
                    "is not in both closed cones");
            expect_vec(w, wp, "image_a", mul(pc(a).Q_, v), "Q_a gamma");
            expect_vec(w, wp, "image_b", mul(pc(b).Q_, v), "Q_b gamma");
            require(mul(pc(a).Q_, v) != mul(pc(b).Q_, v), at(wp, "gamma"), "both pieces agree on it");
            if (via == "P1") {
                require(s_is_a_function(at(wp, "via")), at(wp, "via"), "S is not a function: the canonical witness is the fan's");
                require(holds("P1") == Truth::refuted, at(wp, "via"), "P1 is not refuted");
                Json own = w;
                own.erase("via");
                require(own == field(obl_[1], "$.obligations[1]", "counterexample"), wp, "is not P1's counterexample");
                return;
            }
            // Canonical: the failing entry that ends P1's evidence (whose keys evidence() has
            // checked; which list it is follows from the law, not from the keys present).
            if (!face_to_face()) {
                const Json& e = last_entry("P1", "intersections");
                require(e.at("piece_a") == w.at("piece_a") && e.at("piece_b") == w.at("piece_b"), wp,
                        "is not the first pair that fails");
                Vec first;
                for (const auto& r : intersection_rays(a, b))
                    if (first.empty() && mul(pc(a).Q_, r) != mul(pc(b).Q_, r))
                        first = r;
                require(v == first, at(wp, "gamma"), "is not the first extreme ray where the pieces differ");
            } else {
                const Json& e = last_entry("P1", "shared");
                require(e.at("piece_a") == w.at("piece_a") && e.at("piece_b") == w.at("piece_b") &&
                            e.at("ray") == w.at("gamma"),
                        wp, "is not the first shared ray where the pieces differ");
            }
            return;
        }
        if (id == "nonexpansive" || id == "nonexpansive-lemma") {
            expect_keys(w, wp, {"piece_a", "piece_b", "gamma_a", "gamma_b", "lhs", "rhs"});
            const std::size_t a = law_.piece(field(w, wp, "piece_a"), at(wp, "piece_a"));
            const std::size_t b = law_.piece(field(w, wp, "piece_b"), at(wp, "piece_b"));
            const Vec ga = vec(field(w, wp, "gamma_a"), at(wp, "gamma_a"));
            const Vec gb = vec(field(w, wp, "gamma_b"), at(wp, "gamma_b"));
            require(ga.size() == law_.c && gb.size() == law_.c, wp, "wrong size");
            require(law_.in_interior(a, ga), at(wp, "gamma_a"), "not in the interior of piece_a's cone");
            require(law_.in_interior(b, gb), at(wp, "gamma_b"), "not in the interior of piece_b's cone");
            const Q lhs = law_.energy(sub(mul(pc(a).Q_, ga), mul(pc(b).Q_, gb)));
            const Q rhs = law_.energy(sub(ga, gb));
            require(rat(field(w, wp, "lhs"), at(wp, "lhs")) == lhs, at(wp, "lhs"), "is not |S(a) - S(b)|_H^2");
            require(rat(field(w, wp, "rhs"), at(wp, "rhs")) == rhs, at(wp, "rhs"), "is not |a - b|_H^2");
            require(lhs > rhs, wp, "lhs <= rhs: not a violation");
            Vec ca, cb;
            if (id == "nonexpansive") {
                if (holds("fan") != Truth::undecided)
                    require(!domain_witness(), wp, "S is not a function: the canonical witness is the fan's");
                const Json& entry = last_entry("nonexpansive", "pairs");
                require(entry.at("piece_a") == w.at("piece_a") && entry.at("piece_b") == w.at("piece_b"), wp,
                        "is not the first pair that fails");
                const Mat A = pair_form(a, b);
                const Vec z = moved_inside(A, kkt_minimiser(entry.at("certificate"), wp, 2 * law_.c), wp);
                ca = mul(pc(a).R, Vec(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(law_.c)));
                cb = mul(pc(b).R, Vec(z.begin() + static_cast<std::ptrdiff_t>(law_.c), z.end()));
            } else {
                require(s_is_a_function(wp) && holds("P1") == Truth::proved, wp,
                        "S is not a continuous function: the canonical witness is borrowed");
                require(a == b, wp, "the lemma's witness lies in one cone");
                const auto x = psd_witness(sub(law_.H, QtHQ(a)));
                require(x.has_value(), at(wp, "piece_a"), "H - Q^T H Q is PSD for this piece");
                const Vec centre = mul(pc(a).R, Vec(law_.c, Q(1)));
                Q spread = 1;
                for (const auto& coeff : mul(pc(a).R_inv, *x))
                    spread = std::max(spread, Q(abs(coeff) + 1));
                const Q eps = 1 / (2 * spread);
                ca = centre;
                for (std::size_t i = 0; i < law_.c; ++i)
                    ca[i] += eps * (*x)[i];
                cb = centre;
            }
            require(ga == ca && gb == cb, wp, "is not the canonical witness");
            return;
        }
        if (id == "P2" || id == "energetic") {
            expect_keys(w, wp, {"piece", "gamma", "lhs", "rhs"});
            const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
            const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
            Vec canonical;
            if (id == "P2") {
                const Json& data = field(obl_[2], "$.obligations[2]", "data");
                require(p + 1 == field(data, "$.obligations[2].data", "QtHQ").size(), at(wp, "piece"),
                        "is not the first piece that fails");
                const Mat D = sub(QtHQ(p), law_.H);
                for (std::size_t k = 0; k < law_.c && canonical.empty(); ++k)
                    if (sgn(D[k][k]) != 0) {
                        canonical.assign(law_.c, Q(0));
                        canonical[k] = 1;
                    }
                for (std::size_t k = 0; k < law_.c && canonical.empty(); ++k)
                    for (std::size_t l = k + 1; l < law_.c && canonical.empty(); ++l)
                        if (sgn(D[k][l]) != 0) {
                            canonical.assign(law_.c, Q(0));
                            canonical[k] = canonical[l] = 1;
                        }
            } else {
                const Json& entry = last_entry("energetic", "pieces");
                require(entry.at("piece") == w.at("piece"), at(wp, "piece"), "is not the first piece that fails");
                canonical = mul(pc(p).R, kkt_minimiser(entry.at("certificate"), wp, law_.c));
            }
            require(g == canonical, at(wp, "gamma"), "is not the canonical witness");
            const Q lhs = law_.energy(mul(pc(p).Q_, g)), rhs = law_.energy(g);
            require(rat(field(w, wp, "lhs"), at(wp, "lhs")) == lhs, at(wp, "lhs"), "is not |Q gamma|_H^2");
            require(rat(field(w, wp, "rhs"), at(wp, "rhs")) == rhs, at(wp, "rhs"), "is not |gamma|_H^2");
            if (id == "P2")
                require(lhs != rhs, wp, "energy is conserved at gamma");
            else
                require(law_.in_cone(p, g) && lhs > rhs, wp, "not an energy increase inside the cone");
            return;
        }
        if (id == "P3" || id == "kinematic" || id == "kinetic") {
            if (id == "P3") {
                expect_keys(w, wp, {"piece", "ray", "image", "reason"});
                str(field(w, wp, "reason"), at(wp, "reason"));
            } else {
                expect_keys(w, wp, {"piece", "ray", id == "kinetic" ? "impulse" : "image"});
            }
            const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
            const Vec r = vec(field(w, wp, "ray"), at(wp, "ray"));
            require(r.size() == law_.c && law_.is_ray_of(p, r), at(wp, "ray"), "is not a ray of the piece");
            const Vec img = mul(pc(p).Q_, r);
            if (id == "kinetic") {
                const Vec impulse = mul(law_.H, sub(img, r));
                expect_vec(w, wp, "impulse", impulse, "H (Q - I) ray");
                require(!nonneg(impulse), at(wp, "ray"), "impulse is non-negative");
                return;
            }
            expect_vec(w, wp, "image", img, "Q ray");
            if (id == "kinematic") {
                require(!nonneg(img), at(wp, "ray"), "image is non-negative");
            } else {
                std::size_t nz = 0;
                for (const auto& x : img)
                    nz += sgn(x) != 0 ? 1 : 0;
                bool clash = false;
                for (const auto& other : pc(p).rays)
                    clash = clash || (other != primitive(r) && primitive(mul(pc(p).Q_, other)) == primitive(img));
                require(nz != 1 || !nonneg(img) || clash, at(wp, "ray"), "maps onto a positive axis of its own");
            }
            return;
        }
        if (id == "identities") {
            expect_keys(w, wp, {"identity", "lhs", "product", "gamma", "lhs_image", "product_image"});
            const std::size_t i = natural(field(w, wp, "identity"), at(wp, "identity"));
            require(i < law_.identities.size(), at(wp, "identity"), "no such identity");
            const Identity& d = law_.identities[i];
            require(field(w, wp, "lhs") == d.lhs_json && field(w, wp, "product") == d.product_json, wp, "is not that identity");
            const Vec e = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(e.size() == law_.c, at(wp, "gamma"), "wrong size");
            const Vec rhs = mul(identity_product(i), e);
            const Vec lhs = mul(pc(d.lhs).Q_, e);
            expect_vec(w, wp, "lhs_image", lhs, "Q_lhs gamma");
            expect_vec(w, wp, "product_image", rhs, "the product applied to gamma");
            require(lhs != rhs, at(wp, "gamma"), "both sides agree on it");
            return;
        }
        if (id == "single-impacts") {
            expect_keys(w, wp, {"piece", "contact", "restitution", "gamma", "piece_image", "impact_image"});
            const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
            const std::size_t k = natural(field(w, wp, "contact"), at(wp, "contact"));
            const Q e = rat(field(w, wp, "restitution"), at(wp, "restitution"));
            bool declared = false;
            for (const auto& d : law_.single_impacts)
                declared = declared || (d.piece == p && d.contact == k && d.restitution == e);
            require(declared, wp, "is not a declared single impact");
            const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
            const Vec piece_image = mul(pc(p).Q_, g), impact_image = mul(law_.impact(k - 1, e), g);
            expect_vec(w, wp, "piece_image", piece_image, "Q gamma");
            expect_vec(w, wp, "impact_image", impact_image, "Q^(k)(e) gamma");
            require(piece_image != impact_image, at(wp, "gamma"), "the piece and the impact agree on it");
            return;
        }
        if (id == "outcomes") {
            if (w.contains("piece"))
                expect_keys(w, wp, {"outcome", "u_minus", "u_plus_declared", "piece", "u_plus", "pieces_at_gamma"});
            else
                expect_keys(w, wp, {"outcome", "u_minus", "gamma_minus", "reason"});
            const std::string oname = str(field(w, wp, "outcome"), at(wp, "outcome"));
            const OutcomeDecl* decl = nullptr;
            for (const auto& d : law_.outcomes)
                if (d.name == oname)
                    decl = &d;
            require(decl != nullptr, at(wp, "outcome"), "no such outcome");
            const Vec& u = decl->u_minus;
            const Vec g = mul(tr(law_.W), u);
            expect_vec(w, wp, "u_minus", u, "the outcome's u-");
            if (!w.contains("piece")) {
                str(field(w, wp, "reason"), at(wp, "reason"));
                expect_vec(w, wp, "gamma_minus", g, "W^T u-");
                for (std::size_t p = 0; p < P(); ++p)
                    require(!law_.in_cone(p, g), wp, "gamma- lies in a cone");
                return;
            }
            expect_vec(w, wp, "u_plus_declared", decl->u_plus, "the declared u+");
            const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
            require(law_.in_cone(p, g), at(wp, "piece"), "gamma- is not in this piece's cone");
            const Vec up = law_.u_plus(u, g, mul(pc(p).Q_, g));
            expect_vec(w, wp, "u_plus", up, "the piece's post-impact velocities");
            require(up != decl->u_plus, at(wp, "piece"), "gives the declared u+");
            require(!check_outcome_pieces(field(w, wp, "pieces_at_gamma"), at(wp, "pieces_at_gamma"), u, g, decl->u_plus),
                    at(wp, "pieces_at_gamma"), "all give the declared u+");
            return;
        }
        malformed(wp, "unknown obligation");
    }
};

int check(const Json& cert, const Limits& limits) {
    if (!cert.is_object() || !cert.contains("format") || cert.at("format") != "impactcert-certificate/1")
        malformed("$.format", "not an impactcert-certificate/1 document");
    expect_keys(cert, "$", {"format", "tool", "law_sha256", "law", "verdict", "system", "obligations"});
    str(field(cert, "$", "tool"), "$.tool");
    const Json& law_json = field(cert, "$", "law");
    const std::string hash = str(field(cert, "$", "law_sha256"), "$.law_sha256");
    require(sha256_hex(law_json.dump()) == hash, "$.law_sha256", "does not match the SHA-256 of the law's canonical text");
    const Law law = read_law(law_json, "$.law");

    const Json& system = field(cert, "$", "system");
    expect_keys(system, "$.system", {"G", "H"});
    require(mat(field(system, "$.system", "G"), "$.system.G") == law.G, "$.system.G", "is not W^T M^-1 W");
    require(mat(field(system, "$.system", "H"), "$.system.H") == law.H, "$.system.H", "is not G^-1");

    const Json& obligations = field(cert, "$", "obligations");
    if (!obligations.is_array() || obligations.size() != kIds.size())
        malformed("$.obligations", "expected the 12 obligations");
    Checker checker(law, obligations, limits);
    bool any_claimed_refuted = false, any_claimed_undecided = false;
    for (std::size_t k = 0; k < kIds.size(); ++k) {
        const std::string path = at("$.obligations", k);
        const Json& o = obligations[k];
        expect_keys(o, path, {"id", "statement", "method", "claimed", "verdict", "checks", "data"},
                    {"counterexample", "limit"});
        require(str(field(o, path, "id"), at(path, "id")) == kIds[k], at(path, "id"), "expected \"" + kIds[k] + "\"");
        str(field(o, path, "statement"), at(path, "statement")); // informational, but text
        str(field(o, path, "method"), at(path, "method"));
        natural(field(o, path, "checks"), at(path, "checks"));
        const bool applies = ::applies(law_json, kIds[k]);
        const bool claimed = law.claims_given ? law.claimed_ids.count(kIds[k]) > 0 : applies;
        const Json& claimed_json = field(o, path, "claimed");
        if (!claimed_json.is_boolean())
            malformed(at(path, "claimed"), "expected true or false");
        require(claimed_json.get<bool>() == claimed, at(path, "claimed"), "does not match the law's claims");
        const std::string verdict = str(field(o, path, "verdict"), at(path, "verdict"));
        if (!applies) {
            require(verdict == "skipped", at(path, "verdict"), "nothing is declared: must be \"skipped\"");
            // Nothing was decided, so nothing may ride along.
            const Json& data = field(o, path, "data");
            require(data.is_object() && data.empty(), at(path, "data"), "a skipped obligation carries no evidence");
            require(!o.contains("counterexample"), at(path, "counterexample"), "a skipped obligation has no counterexample");
            require(!o.contains("limit"), at(path, "limit"), "only an undecided obligation names a limit");
            continue;
        }
        require(verdict != "skipped", at(path, "verdict"), "the law declares something to check");
        require((verdict == "refuted") == o.contains("counterexample"), path,
                "a counterexample goes with a refutation, and only with one");
        const auto truth = checker.holds(k);
        if (claimed && truth == Checker::Truth::refuted)
            any_claimed_refuted = true;
        if (claimed && truth == Checker::Truth::undecided)
            any_claimed_undecided = true;
    }
    const std::string top = str(field(cert, "$", "verdict"), "$.verdict");
    const char* follows = any_claimed_refuted ? "refuted" : any_claimed_undecided ? "undecided" : "proved";
    require(top == follows, "$.verdict", "does not follow from the claimed obligations");
    return 0;
}

// One line: control characters (C0, DEL, C1 and the Unicode line and paragraph separators)
// and the backslash that introduces an escape are escaped, so that a name or key from the
// input cannot break a message into several lines.
std::string one_line(const std::string& text) {
    static const char* hex = "0123456789abcdef";
    auto escape = [&](std::string& out, unsigned code) {
        out += "\\u";
        for (int shift = 12; shift >= 0; shift -= 4)
            out += hex[(code >> shift) & 15];
    };
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const unsigned char ch = static_cast<unsigned char>(text[i]);
        const unsigned char next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
        const unsigned char third = i + 2 < text.size() ? static_cast<unsigned char>(text[i + 2]) : 0;
        if (ch == '\\')
            out += "\\\\";
        else if (ch == '\n')
            out += "\\n";
        else if (ch == '\r')
            out += "\\r";
        else if (ch == '\t')
            out += "\\t";
        else if (ch < 0x20 || ch == 0x7f)
            escape(out, ch);
        else if (ch == 0xc2 && next >= 0x80 && next <= 0x9f) { // U+0080..U+009F
            escape(out, next);
            ++i;
        } else if (ch == 0xe2 && next == 0x80 && (third == 0xa8 || third == 0xa9)) { // U+2028, U+2029
            escape(out, 0x2000u + third - 0x80u);
            i += 2;
        } else
            out += static_cast<char>(ch);
    }
    return out;
}

} // namespace

namespace impactcert_check {

// The deepest nesting of arrays and objects in a JSON text, counted without recursion (a
// certificate nested 100,000 deep must not overflow the stack of a recursive parser or dump).
std::size_t nesting_depth(const std::string& text) {
    std::size_t depth = 0, deepest = 0;
    bool in_string = false, escaped = false;
    for (char ch : text) {
        if (in_string) {
            if (escaped)
                escaped = false;
            else if (ch == '\\')
                escaped = true;
            else if (ch == '"')
                in_string = false;
        } else if (ch == '"') {
            in_string = true;
        } else if (ch == '[' || ch == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((ch == ']' || ch == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

// Status kUndecided (3, impactcert_check.hpp): a limit (the prover's, or --max-product-bits)
// would be exceeded. The certificate may be right; raising the limit decides it.

Outcome check_text(const std::string& text, const Limits& limits) {
    constexpr std::size_t kMaxDepth = 64; // a certificate is at most 6 deep
    try {
        if (nesting_depth(text) > kMaxDepth)
            return {kMalformed, "malformed: nested more than " + std::to_string(kMaxDepth) + " levels deep"};
        Json cert;
        try {
            cert = Json::parse(text);
        } catch (const Json::exception& e) {
            return {kMalformed, one_line(std::string("malformed JSON: ") + e.what())};
        }
        try {
            check(cert, limits);
            return {kVerified, one_line("verified (" + cert.at("law").at("name").get<std::string>() + ": " +
                                        cert.at("verdict").get<std::string>() + ")")};
        } catch (const Rejected& r) {
            return {kRejected, one_line("rejected: " + r.path + ": " + r.why)};
        } catch (const Malformed& m) {
            return {kMalformed, one_line("malformed: " + m.path + ": " + m.why)};
        } catch (const Undecided& u) {
            return {kUndecided, one_line("undecided: " + u.option.substr(2) + " exceeded: " + u.path + ": " + u.why +
                                         " (raise it with " + u.option + ")")};
        } catch (const Json::exception& e) {
            return {kMalformed, one_line(std::string("malformed: ") + e.what())};
        }
    } catch (const std::bad_alloc&) {
        return {kMalformed, "error: out of memory while checking (status 2: not checked)"};
    } catch (const std::exception& e) {
        return {kMalformed, one_line(std::string("error: internal: ") + e.what() + " (status 2: not checked)")};
    }
}

Outcome check_text(const std::string& text) { return check_text(text, Limits{}); }

} // namespace impactcert_check

#ifndef IMPACTCERT_CHECK_NO_MAIN
namespace {

const char* const kUsage =
    "usage: impactcert-check [--max-faces N] [--max-chambers N] [--max-subsets N] [--max-product-bits N]\n"
    "                        CERTIFICATE.json\n"
    "exit 0 verified, 1 rejected, 2 malformed (or not checked: usage, unreadable, out of memory),\n"
    "3 undecided (a limit would be exceeded; the message names the option that raises it)\n"
    "limits (defaults as the prover's): --max-faces 16384 (KKT faces of one copositivity check),\n"
    "--max-chambers 200000 (steps of the chamber enumeration), --max-subsets 5000000 (constraint\n"
    "subsets for intersections of cones); the checker's own: --max-product-bits 4194304 (bits of\n"
    "an entry of a declared identity's product)\n";

int usage_error(const std::string& why) {
    std::cerr << "impactcert-check: " << one_line(why) << " (see --help)\n";
    return impactcert_check::kMalformed;
}

} // namespace

int main(int argc, char** argv) {
    Limits limits;
    std::string file;
    bool have_file = false, options_done = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (!options_done && (arg == "--help" || arg == "-h")) {
            // Usage is not a verification: never status 0.
            std::cout << kUsage;
            return impactcert_check::kMalformed;
        }
        if (!options_done && arg == "--") {
            options_done = true;
            continue;
        }
        if (!options_done && arg.size() > 1 && arg[0] == '-') {
            std::string name = arg, value;
            if (const auto eq = arg.find('='); eq != std::string::npos) {
                name = arg.substr(0, eq);
                value = arg.substr(eq + 1);
            } else if (i + 1 < argc) {
                value = argv[++i];
            } else {
                return usage_error("option " + arg + " needs a value");
            }
            std::size_t* target = name == "--max-faces"          ? &limits.max_faces
                                  : name == "--max-chambers"     ? &limits.max_chambers
                                  : name == "--max-subsets"      ? &limits.max_subsets
                                  : name == "--max-product-bits" ? &limits.max_product_bits
                                                                 : nullptr;
            if (target == nullptr)
                return usage_error("unknown option " + name);
            const bool digits = !value.empty() && value.size() <= 19 &&
                                std::all_of(value.begin(), value.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
            if (!digits)
                return usage_error(name + " needs a non-negative integer, got \"" + value + "\"");
            *target = static_cast<std::size_t>(std::stoull(value));
            continue;
        }
        if (have_file)
            return usage_error("more than one certificate given");
        file = arg;
        have_file = true;
    }
    if (!have_file)
        return usage_error("no certificate given");
    try {
        std::ifstream in(file, std::ios::binary);
        if (!in) {
            std::cerr << "impactcert-check: " << one_line(file) << ": cannot read file\n";
            return impactcert_check::kMalformed;
        }
        std::ostringstream text;
        text << in.rdbuf();
        const auto outcome = impactcert_check::check_text(text.str(), limits);
        (outcome.status == impactcert_check::kVerified ? std::cout : std::cerr)
            << "impactcert-check: " << one_line(file) << ": " << outcome.message << "\n";
        return outcome.status;
    } catch (const std::exception& e) {
        std::cerr << "impactcert-check: " << one_line(file) << ": error: "
                  << one_line(e.what()) << "\n";
        return impactcert_check::kMalformed;
    }
}
#endif
