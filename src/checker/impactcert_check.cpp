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
#include <gmpxx.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
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

[[noreturn]] void malformed(const std::string& path, const std::string& why) { throw Malformed{path, why}; }
[[noreturn]] void reject(const std::string& path, const std::string& why) { throw Rejected{path, why}; }
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

Q rat(const Json& j, const std::string& path) {
    if (j.is_number_integer())
        return Q(j.dump());
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

// ---------------------------------------------------------------------------------------------
// The law, re-derived

struct Piece {
    std::string name;
    Mat Q_, R, R_inv;
    std::vector<Vec> rays; // primitive
};

struct Law {
    Json json;
    Vec masses;
    Mat W, M_inv, G, H;
    std::size_t n = 0, c = 0;
    std::vector<Piece> pieces;
    std::vector<Vec> distinct_rays;
    std::set<std::string> claimed_ids;
    bool claims_given = false;

    std::size_t piece(const Json& name, const std::string& path) const {
        const std::string s = str(name, path);
        for (std::size_t p = 0; p < pieces.size(); ++p)
            if (pieces[p].name == s)
                return p;
        reject(path, "unknown piece \"" + s + "\"");
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

Law read_law(const Json& j, const std::string& path) {
    Law law;
    law.json = j;
    law.masses = vec(field(j, path, "masses"), at(path, "masses"));
    law.n = law.masses.size();
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
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        const std::string pp = at(at(path, "pieces"), p);
        Piece piece;
        piece.name = str(field(pieces[p], pp, "name"), at(pp, "name"));
        for (const auto& other : law.pieces)
            require(other.name != piece.name, at(pp, "name"), "duplicate piece name");
        piece.Q_ = mat(field(pieces[p], pp, "Q"), at(pp, "Q"));
        require(piece.Q_.size() == law.c && piece.Q_[0].size() == law.c, at(pp, "Q"), "not c x c");
        std::vector<Vec> rays;
        if (pieces[p].contains("rays")) {
            for (std::size_t k = 0; k < pieces[p]["rays"].size(); ++k)
                rays.push_back(vec(pieces[p]["rays"][k], at(at(pp, "rays"), k)));
        } else {
            Mat q_inv;
            require(invert(piece.Q_, q_inv), at(pp, "Q"), "singular Q and no rays");
            for (std::size_t k = 0; k < law.c; ++k)
                rays.push_back(col(q_inv, k));
        }
        require(rays.size() == law.c, at(pp, "rays"), "needs c rays");
        for (std::size_t k = 0; k < rays.size(); ++k) {
            require(rays[k].size() == law.c && !std::all_of(rays[k].begin(), rays[k].end(), [](const Q& x) { return sgn(x) == 0; }),
                    at(at(pp, "rays"), k), "zero or mis-sized ray");
            piece.rays.push_back(primitive(rays[k]));
        }
        piece.R = from_cols(piece.rays);
        require(invert(piece.R, piece.R_inv), at(pp, "rays"), "dependent rays");
        for (const auto& r : piece.rays)
            if (std::find(law.distinct_rays.begin(), law.distinct_rays.end(), r) == law.distinct_rays.end())
                law.distinct_rays.push_back(r);
        law.pieces.push_back(std::move(piece));
    }
    if (j.contains("claims")) {
        law.claims_given = true;
        for (const auto& id : j["claims"])
            law.claimed_ids.insert(str(id, at(path, "claims")));
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

bool check_psd_evidence(const Mat& B, const Json& j, const std::string& path) {
    const Mat L = mat(field(j, path, "L"), at(path, "L"));
    const Vec D = vec(field(j, path, "D"), at(path, "D"));
    require(L.size() == B.size() && D.size() == B.size(), path, "L or D has the wrong size");
    require(lower_unit(L), at(path, "L"), "not unit lower triangular");
    require(nonneg(D), at(path, "D"), "negative entry in D");
    require(ldlt(L, D) == B, path, "L D L^T does not reproduce the matrix");
    return true;
}

bool check_copositive_evidence(const Mat& A, const Json& j, const std::string& path) {
    const std::string method = str(field(j, path, "method"), at(path, "method"));
    const std::size_t n = A.size();
    if (method == "nonnegative-entries") {
        for (const auto& row : A)
            require(nonneg(row), path, "matrix has a negative entry");
        return true;
    }
    if (method == "psd-ldlt")
        return check_psd_evidence(A, j, path);
    if (method == "psd-plus-nonnegative") {
        const Mat N = mat(field(j, path, "N"), at(path, "N"));
        require(N.size() == n, at(path, "N"), "wrong size");
        for (const auto& row : N)
            require(nonneg(row), at(path, "N"), "negative entry in N");
        return check_psd_evidence(sub(A, N), j, path);
    }
    if (method == "kkt-enumeration") {
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
        const Json& cands = field(j, path, "candidates");
        require(cands.size() == mine.size(), at(path, "candidates"),
                "lists " + std::to_string(cands.size()) + " KKT candidates, there are " + std::to_string(mine.size()));
        for (std::size_t k = 0; k < mine.size(); ++k) {
            const std::string cp = at(at(path, "candidates"), k);
            std::vector<std::size_t> support;
            for (const auto& i : field(cands[k], cp, "support"))
                support.push_back(i.get<std::size_t>());
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
        require(have && rat(field(j, path, "minimum"), at(path, "minimum")) == minimum, at(path, "minimum"),
                "not the least candidate");
        return sgn(minimum) >= 0;
    }
    malformed(at(path, "method"), "unknown method \"" + method + "\"");
}

// ---------------------------------------------------------------------------------------------
// Obligations

const std::vector<std::string> kIds = {"fan", "P1", "P2", "P3", "kinematic", "kinetic", "energetic",
                                       "identities", "single-impacts", "nonexpansive", "nonexpansive-lemma",
                                       "outcomes"};

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
    Checker(const Law& law, const Json& obligations) : law_(law), obl_(obligations) {}

    // Decides obligation k's truth from evidence and witnesses; rejects wrong evidence.
    bool holds(std::size_t k) {
        if (auto it = decided_.find(kIds[k]); it != decided_.end())
            return it->second;
        const Json& o = obl_[k];
        const std::string path = at("$.obligations", k);
        const std::string verdict = str(field(o, path, "verdict"), at(path, "verdict"));
        const Json& data = field(o, path, "data");
        const std::string dp = at(path, "data");
        bool truth = true;
        if (verdict == "refuted") {
            check_witness(kIds[k], field(o, path, "counterexample"), at(path, "counterexample"));
            truth = false;
        } else if (verdict == "proved") {
            truth = prove(kIds[k], data, dp);
            require(truth, at(path, "verdict"), "\"proved\" does not follow from the evidence");
        } else {
            malformed(at(path, "verdict"), "unknown verdict");
        }
        decided_[kIds[k]] = truth;
        return truth;
    }

  private:
    const Law& law_;
    const Json& obl_;
    std::map<std::string, bool> decided_;

    bool holds(const std::string& id) {
        return holds(static_cast<std::size_t>(std::find(kIds.begin(), kIds.end(), id) - kIds.begin()));
    }

    // ---- proofs from evidence
    bool prove(const std::string& id, const Json& data, const std::string& dp) {
        const std::size_t P = law_.pieces.size(), c = law_.c;
        if (id == "fan")
            return c == 2 && data.contains("rays_by_angle") ? prove_fan_planar(data, dp) : prove_fan_facets(data, dp);
        if (id == "P1") {
            // Every shared ray of every pair, recomputed here; the listing must agree.
            std::size_t listed = 0;
            for (std::size_t i = 0; i < P; ++i)
                for (std::size_t j = i + 1; j < P; ++j)
                    for (const auto& v : law_.pieces[i].rays) {
                        if (!law_.is_ray_of(j, v))
                            continue;
                        if (mul(law_.pieces[i].Q_, v) != mul(law_.pieces[j].Q_, v))
                            return false;
                        ++listed;
                    }
            require(field(data, dp, "shared").size() == listed, at(dp, "shared"), "does not list every shared ray");
            return true;
        }
        if (id == "P2") {
            for (std::size_t p = 0; p < P; ++p) {
                const Mat qthq = mul(mul(tr(law_.pieces[p].Q_), law_.H), law_.pieces[p].Q_);
                const std::string ep = at(at(dp, "QtHQ"), p);
                require(mat(field(field(data, dp, "QtHQ")[p], ep, "matrix"), at(ep, "matrix")) == qthq, at(ep, "matrix"),
                        "is not Q^T H Q");
                if (qthq != law_.H)
                    return false;
            }
            return true;
        }
        if (id == "P3" || id == "kinematic" || id == "kinetic") {
            for (std::size_t p = 0; p < P; ++p) {
                std::set<std::size_t> axes;
                for (const auto& r : law_.pieces[p].rays) {
                    const Vec img = mul(law_.pieces[p].Q_, r);
                    if (id == "kinetic") {
                        if (!nonneg(mul(law_.H, sub(img, r))))
                            return false;
                    } else if (id == "kinematic") {
                        if (!nonneg(img))
                            return false;
                    } else {
                        std::size_t nz = 0, axis = 0;
                        for (std::size_t i = 0; i < c; ++i)
                            if (sgn(img[i]) != 0) {
                                ++nz;
                                axis = i;
                            }
                        if (nz != 1 || sgn(img[axis]) < 0 || !axes.insert(axis).second)
                            return false;
                    }
                }
            }
            return id != "kinematic" || holds("fan");
        }
        if (id == "energetic") {
            const Json& list = field(data, dp, "pieces");
            require(list.size() == P, at(dp, "pieces"), "needs one entry per piece");
            for (std::size_t p = 0; p < P; ++p) {
                const auto& pc = law_.pieces[p];
                const std::string ep = at(at(dp, "pieces"), p);
                require(law_.piece(field(list[p], ep, "piece"), at(ep, "piece")) == p, at(ep, "piece"), "out of order");
                const Mat B = mul(mul(tr(pc.R), sub(law_.H, mul(mul(tr(pc.Q_), law_.H), pc.Q_))), pc.R);
                require(mat(field(list[p], ep, "B"), at(ep, "B")) == B, at(ep, "B"), "is not R^T (H - Q^T H Q) R");
                if (!check_copositive_evidence(B, field(list[p], ep, "certificate"), at(ep, "certificate")))
                    return false;
            }
            return true;
        }
        if (id == "identities") {
            for (std::size_t i = 0; i < law_.json["identities"].size(); ++i) {
                const Json& d = law_.json["identities"][i];
                Mat prod = eye(c);
                for (const auto& f : d["product"])
                    prod = mul(prod, law_.pieces[law_.piece(f, "$.law.identities")].Q_);
                if (law_.pieces[law_.piece(d["lhs"], "$.law.identities")].Q_ != prod)
                    return false;
            }
            return true;
        }
        if (id == "single-impacts") {
            for (const auto& d : law_.json["single_impacts"]) {
                const std::size_t k = d["contact"].get<std::size_t>();
                require(k >= 1 && k <= c, "$.law.single_impacts", "contact out of range");
                if (law_.pieces[law_.piece(d["piece"], "$.law.single_impacts")].Q_ != law_.impact(k - 1, rat(d["restitution"], "$.law.single_impacts")))
                    return false;
            }
            return true;
        }
        if (id == "nonexpansive") {
            const Json& pairs = field(data, dp, "pairs");
            require(pairs.size() == P * P, at(dp, "pairs"), "needs every ordered pair of pieces");
            for (std::size_t i = 0; i < P; ++i)
                for (std::size_t j = 0; j < P; ++j) {
                    const std::string ep = at(at(dp, "pairs"), i * P + j);
                    const Json& e = pairs[i * P + j];
                    require(law_.piece(field(e, ep, "piece_a"), at(ep, "piece_a")) == i &&
                                law_.piece(field(e, ep, "piece_b"), at(ep, "piece_b")) == j,
                            ep, "pairs out of order");
                    const Mat A = pair_form(i, j);
                    require(mat(field(e, ep, "A"), at(ep, "A")) == A, at(ep, "A"), "is not the pair's quadratic form");
                    if (!check_copositive_evidence(A, field(e, ep, "certificate"), at(ep, "certificate")))
                        return false;
                }
            return holds("fan");
        }
        if (id == "nonexpansive-lemma") {
            if (!holds("fan") || !holds("P1"))
                return false;
            const Json& list = field(data, dp, "pieces");
            require(list.size() == P, at(dp, "pieces"), "needs one LDL^T per piece");
            for (std::size_t p = 0; p < P; ++p) {
                const std::string ep = at(at(dp, "pieces"), p);
                require(law_.piece(field(list[p], ep, "piece"), at(ep, "piece")) == p, at(ep, "piece"), "out of order");
                const auto& pc = law_.pieces[p];
                check_psd_evidence(sub(law_.H, mul(mul(tr(pc.Q_), law_.H), pc.Q_)), list[p], ep);
            }
            return true;
        }
        if (id == "outcomes") {
            for (const auto& d : law_.json["outcomes"]) {
                const Vec u = vec(d["u_minus"], "$.law.outcomes"), declared = vec(d["u_plus"], "$.law.outcomes");
                const Vec g = mul(tr(law_.W), u);
                bool any = false;
                for (std::size_t p = 0; p < P; ++p)
                    if (law_.in_cone(p, g)) {
                        any = true;
                        if (law_.u_plus(u, g, mul(law_.pieces[p].Q_, g)) != declared)
                            return false;
                    }
                if (!any)
                    return false;
            }
            return true;
        }
        malformed(dp, "unknown obligation");
    }

    Mat pair_form(std::size_t i, std::size_t j) const {
        const std::size_t c = law_.c;
        const Mat QRi = mul(law_.pieces[i].Q_, law_.pieces[i].R), QRj = mul(law_.pieces[j].Q_, law_.pieces[j].R);
        Mat B1 = zeros(c, 2 * c), B2 = zeros(c, 2 * c);
        for (std::size_t r = 0; r < c; ++r)
            for (std::size_t k = 0; k < c; ++k) {
                B1[r][k] = law_.pieces[i].R[r][k];
                B1[r][c + k] = -law_.pieces[j].R[r][k];
                B2[r][k] = QRi[r][k];
                B2[r][c + k] = -QRj[r][k];
            }
        return sub(mul(mul(tr(B1), law_.H), B1), mul(mul(tr(B2), law_.H), B2));
    }

    bool prove_fan_planar(const Json& data, const std::string& dp) {
        std::vector<Vec> sorted;
        for (std::size_t k = 0; k < field(data, dp, "rays_by_angle").size(); ++k)
            sorted.push_back(vec(data["rays_by_angle"][k], at(at(dp, "rays_by_angle"), k)));
        std::vector<Vec> a = sorted, b = law_.distinct_rays;
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        require(a == b, at(dp, "rays_by_angle"), "is not the set of distinct rays");
        const std::size_t m = sorted.size();
        for (std::size_t k = 1; k < m; ++k)
            require(ccw_before(sorted[0], sorted[k - 1], sorted[k]), at(at(dp, "rays_by_angle"), k), "not in angular order");
        const Json& points = field(data, dp, "sector_points");
        require(points.size() == m, at(dp, "sector_points"), "needs one point per sector");
        for (std::size_t k = 0; k < m; ++k) {
            const Vec d = vec(points[k], at(at(dp, "sector_points"), k));
            const Vec &lo = sorted[k], &hi = sorted[(k + 1) % m];
            // d strictly inside the open counter-clockwise sector from lo to hi.
            const bool inside = !(sign_det2(lo, d) == 0 && sgn(dot(lo, d)) > 0) && ccw_before(lo, d, hi) &&
                                !(primitive(d) == primitive(hi));
            require(inside, at(at(dp, "sector_points"), k), "not strictly inside its sector");
            if (law_.interiors(d).size() != 1)
                return false;
        }
        return true;
    }

    bool prove_fan_facets(const Json& data, const std::string& dp) {
        // Facets and their owners, recomputed here: each must have exactly two owners on
        // opposite sides.
        std::map<std::vector<Vec>, std::vector<int>> facets;
        for (const auto& pc : law_.pieces)
            for (std::size_t drop = 0; drop < law_.c; ++drop) {
                std::vector<Vec> f;
                for (std::size_t k = 0; k < law_.c; ++k)
                    if (k != drop)
                        f.push_back(pc.rays[k]);
                std::sort(f.begin(), f.end());
                std::vector<Vec> cols = f;
                cols.push_back(pc.rays[drop]);
                facets[f].push_back(sgn(det(from_cols(cols))));
            }
        for (const auto& [f, sides] : facets)
            if (sides.size() != 2 || sides[0] == sides[1])
                return false;
        require(field(data, dp, "facets").size() == facets.size(), at(dp, "facets"), "does not list every facet");
        const Vec p = vec(field(data, dp, "generic_point"), at(dp, "generic_point"));
        require(p.size() == law_.c, at(dp, "generic_point"), "wrong size");
        for (const auto& entry : facets) {
            std::vector<Vec> cols = entry.first;
            cols.push_back(p);
            require(sgn(det(from_cols(cols))) != 0, at(dp, "generic_point"), "lies on a facet hyperplane");
        }
        return law_.interiors(p).size() == 1;
    }

    // ---- counterexamples, re-validated from scratch
    void check_witness(const std::string& id, const Json& w, const std::string& wp) {
        const std::string via = w.contains("via") ? str(w["via"], at(wp, "via")) : "";
        if (id == "fan" || via == "fan") {
            if (w.contains("gamma")) {
                const Vec g = vec(w["gamma"], at(wp, "gamma"));
                require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
                require(law_.interiors(g).size() != 1, at(wp, "gamma"), "is covered by exactly one cone");
            } else {
                const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
                std::vector<Vec> f;
                for (std::size_t k = 0; k < field(w, wp, "facet").size(); ++k) {
                    f.push_back(primitive(vec(w["facet"][k], at(at(wp, "facet"), k))));
                    require(law_.is_ray_of(p, f.back()), at(at(wp, "facet"), k), "is not a ray of the piece");
                }
                require(f.size() + 1 == law_.c, at(wp, "facet"), "is not a facet");
                // Count owners and sides here.
                std::vector<int> sides;
                std::sort(f.begin(), f.end());
                for (const auto& pc : law_.pieces) {
                    std::vector<Vec> rest;
                    bool has = true;
                    for (const auto& r : f)
                        has = has && std::find(pc.rays.begin(), pc.rays.end(), r) != pc.rays.end();
                    if (!has)
                        continue;
                    for (const auto& r : pc.rays)
                        if (std::find(f.begin(), f.end(), r) == f.end())
                            rest.push_back(r);
                    std::vector<Vec> cols = f;
                    cols.push_back(rest.at(0));
                    sides.push_back(sgn(det(from_cols(cols))));
                }
                require(sides.size() != 2 || sides[0] == sides[1], at(wp, "facet"), "is a well-matched facet");
            }
            if (via == "fan")
                require(!holds("fan"), at(wp, "via"), "the fan is not refuted");
            return;
        }
        if (id == "P1" || via == "P1") {
            const std::size_t a = law_.piece(field(w, wp, "piece_a"), at(wp, "piece_a"));
            const std::size_t b = law_.piece(field(w, wp, "piece_b"), at(wp, "piece_b"));
            const Vec v = vec(field(w, wp, "ray"), at(wp, "ray"));
            require(law_.is_ray_of(a, v) && law_.is_ray_of(b, v), at(wp, "ray"), "is not shared by the two pieces");
            require(mul(law_.pieces[a].Q_, v) != mul(law_.pieces[b].Q_, v), at(wp, "ray"), "both pieces agree on it");
            return;
        }
        if (id == "nonexpansive" || id == "nonexpansive-lemma") {
            const std::size_t a = law_.piece(field(w, wp, "piece_a"), at(wp, "piece_a"));
            const std::size_t b = law_.piece(field(w, wp, "piece_b"), at(wp, "piece_b"));
            const Vec ga = vec(field(w, wp, "gamma_a"), at(wp, "gamma_a"));
            const Vec gb = vec(field(w, wp, "gamma_b"), at(wp, "gamma_b"));
            require(ga.size() == law_.c && gb.size() == law_.c, wp, "wrong size");
            require(law_.in_interior(a, ga), at(wp, "gamma_a"), "not in the interior of piece_a's cone");
            require(law_.in_interior(b, gb), at(wp, "gamma_b"), "not in the interior of piece_b's cone");
            const Q lhs = law_.energy(sub(mul(law_.pieces[a].Q_, ga), mul(law_.pieces[b].Q_, gb)));
            const Q rhs = law_.energy(sub(ga, gb));
            require(rat(field(w, wp, "lhs"), at(wp, "lhs")) == lhs, at(wp, "lhs"), "is not |S(a) - S(b)|_H^2");
            require(rat(field(w, wp, "rhs"), at(wp, "rhs")) == rhs, at(wp, "rhs"), "is not |a - b|_H^2");
            require(lhs > rhs, wp, "lhs <= rhs: not a violation");
            return;
        }
        if (id == "P2" || id == "energetic") {
            const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
            const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
            const Q lhs = law_.energy(mul(law_.pieces[p].Q_, g)), rhs = law_.energy(g);
            if (id == "P2")
                require(lhs != rhs, wp, "energy is conserved at gamma");
            else
                require(law_.in_cone(p, g) && lhs > rhs, wp, "not an energy increase inside the cone");
            return;
        }
        if (id == "P3" || id == "kinematic" || id == "kinetic") {
            const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
            const Vec r = vec(field(w, wp, "ray"), at(wp, "ray"));
            require(law_.is_ray_of(p, r), at(wp, "ray"), "is not a ray of the piece");
            const Vec img = mul(law_.pieces[p].Q_, r);
            if (id == "kinetic") {
                require(!nonneg(mul(law_.H, sub(img, r))), at(wp, "ray"), "impulse is non-negative");
            } else if (id == "kinematic") {
                require(!nonneg(img), at(wp, "ray"), "image is non-negative");
            } else {
                std::size_t nz = 0;
                for (const auto& x : img)
                    nz += sgn(x) != 0 ? 1 : 0;
                bool clash = false;
                for (const auto& other : law_.pieces[p].rays)
                    clash = clash || (other != primitive(r) && primitive(mul(law_.pieces[p].Q_, other)) == primitive(img));
                require(nz != 1 || !nonneg(img) || clash, at(wp, "ray"), "maps onto a positive axis of its own");
            }
            return;
        }
        if (id == "identities") {
            const std::size_t i = field(w, wp, "identity").get<std::size_t>();
            require(i < law_.json["identities"].size(), at(wp, "identity"), "no such identity");
            const Json& d = law_.json["identities"][i];
            const Vec e = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            Vec rhs = e;
            for (auto it = d["product"].rbegin(); it != d["product"].rend(); ++it)
                rhs = mul(law_.pieces[law_.piece(*it, "$.law.identities")].Q_, rhs);
            require(mul(law_.pieces[law_.piece(d["lhs"], "$.law.identities")].Q_, e) != rhs, at(wp, "gamma"),
                    "both sides agree on it");
            return;
        }
        if (id == "single-impacts") {
            const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
            bool declared = false;
            for (const auto& d : law_.json["single_impacts"])
                declared = declared || (d["piece"] == w["piece"] && d["contact"] == w["contact"] &&
                                        rat(d["restitution"], "$.law") == rat(w["restitution"], at(wp, "restitution")));
            require(declared, wp, "is not a declared single impact");
            const std::size_t k = field(w, wp, "contact").get<std::size_t>();
            const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
            require(mul(law_.pieces[p].Q_, g) != mul(law_.impact(k - 1, rat(w["restitution"], wp)), g), at(wp, "gamma"),
                    "the piece and the impact agree on it");
            return;
        }
        if (id == "outcomes") {
            const std::string name = str(field(w, wp, "outcome"), at(wp, "outcome"));
            const Json* decl = nullptr;
            for (const auto& d : law_.json["outcomes"])
                if (d["name"] == name)
                    decl = &d;
            require(decl != nullptr, at(wp, "outcome"), "no such outcome");
            const Vec u = vec((*decl)["u_minus"], "$.law.outcomes"), declared = vec((*decl)["u_plus"], "$.law.outcomes");
            const Vec g = mul(tr(law_.W), u);
            if (!w.contains("piece")) {
                for (std::size_t p = 0; p < law_.pieces.size(); ++p)
                    require(!law_.in_cone(p, g), wp, "gamma- lies in a cone");
                return;
            }
            const std::size_t p = law_.piece(w["piece"], at(wp, "piece"));
            require(law_.in_cone(p, g), at(wp, "piece"), "gamma- is not in this piece's cone");
            require(law_.u_plus(u, g, mul(law_.pieces[p].Q_, g)) != declared, at(wp, "piece"), "gives the declared u+");
            return;
        }
        malformed(wp, "unknown obligation");
    }
};

int check(const Json& cert) {
    if (!cert.is_object() || !cert.contains("format") || cert["format"] != "impactcert-certificate/1")
        malformed("$.format", "not an impactcert-certificate/1 document");
    const Json& law_json = field(cert, "$", "law");
    const std::string hash = str(field(cert, "$", "law_sha256"), "$.law_sha256");
    require(sha256_hex(law_json.dump()) == hash, "$.law_sha256", "does not match the SHA-256 of the law's canonical text");
    const Law law = read_law(law_json, "$.law");

    const Json& system = field(cert, "$", "system");
    require(mat(field(system, "$.system", "G"), "$.system.G") == law.G, "$.system.G", "is not W^T M^-1 W");
    require(mat(field(system, "$.system", "H"), "$.system.H") == law.H, "$.system.H", "is not G^-1");

    const Json& obligations = field(cert, "$", "obligations");
    if (!obligations.is_array() || obligations.size() != kIds.size())
        malformed("$.obligations", "expected the 12 obligations");
    Checker checker(law, obligations);
    bool all_claimed_proved = true;
    for (std::size_t k = 0; k < kIds.size(); ++k) {
        const std::string path = at("$.obligations", k);
        const Json& o = obligations[k];
        require(str(field(o, path, "id"), at(path, "id")) == kIds[k], at(path, "id"), "expected \"" + kIds[k] + "\"");
        const bool applies = (kIds[k] == "identities")       ? law_json.contains("identities")
                             : (kIds[k] == "single-impacts") ? law_json.contains("single_impacts")
                             : (kIds[k] == "outcomes")       ? law_json.contains("outcomes")
                                                             : true;
        const bool claimed = law.claims_given ? law.claimed_ids.count(kIds[k]) > 0 : applies;
        const Json& claimed_json = field(o, path, "claimed");
        if (!claimed_json.is_boolean())
            malformed(at(path, "claimed"), "expected true or false");
        require(claimed_json.get<bool>() == claimed, at(path, "claimed"), "does not match the law's claims");
        const std::string verdict = str(field(o, path, "verdict"), at(path, "verdict"));
        if (!applies) {
            require(verdict == "skipped", at(path, "verdict"), "nothing is declared: must be \"skipped\"");
            continue;
        }
        require(verdict != "skipped", at(path, "verdict"), "the law declares something to check");
        require((verdict == "refuted") == o.contains("counterexample"), path,
                "a counterexample goes with a refutation, and only with one");
        const bool truth = checker.holds(k);
        if (claimed && !truth)
            all_claimed_proved = false;
    }
    const std::string top = str(field(cert, "$", "verdict"), "$.verdict");
    require(top == (all_claimed_proved ? "proved" : "refuted"), "$.verdict",
            "does not follow from the claimed obligations");
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2 || std::string(argv[1]) == "--help") {
        std::cerr << "usage: impactcert-check CERTIFICATE.json\n"
                     "exit 0 verified, 1 rejected, 2 malformed\n";
        return argc == 2 ? 0 : 2;
    }
    const std::string file = argv[1];
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        std::cerr << "impactcert-check: " << file << ": cannot read file\n";
        return 2;
    }
    Json cert;
    try {
        cert = Json::parse(in);
    } catch (const Json::exception& e) {
        std::cerr << "impactcert-check: " << file << ": malformed JSON: " << e.what() << "\n";
        return 2;
    }
    try {
        check(cert);
        std::cout << "impactcert-check: " << file << ": verified (" << cert["law"]["name"].get<std::string>() << ": "
                  << cert["verdict"].get<std::string>() << ")\n";
        return 0;
    } catch (const Rejected& r) {
        std::cerr << "impactcert-check: " << file << ": rejected: " << r.path << ": " << r.why << "\n";
        return 1;
    } catch (const Malformed& m) {
        std::cerr << "impactcert-check: " << file << ": malformed: " << m.path << ": " << m.why << "\n";
        return 2;
    } catch (const Json::exception& e) {
        std::cerr << "impactcert-check: " << file << ": malformed: " << e.what() << "\n";
        return 2;
    }
}
