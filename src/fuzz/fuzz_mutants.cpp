// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/fuzz_mutants.hpp"

#include "base/errors.hpp"
#include "exact/exact_double.hpp"
#include "fuzz/float_eval.hpp"
#include "base/splitmix.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

namespace impactcert::fuzz {

namespace {

struct OpName {
    Mutation::Op op;
    const char* name;
};
constexpr OpName kOps[] = {
    {Mutation::Op::none, "none"},
    {Mutation::Op::dead_zone, "dead-zone"},
    {Mutation::Op::slow_contact, "slow-contact"},
    {Mutation::Op::facet_flip, "facet-flip"},
    {Mutation::Op::facet_drop, "facet-drop"},
    {Mutation::Op::sign, "sign"},
    {Mutation::Op::formula, "formula"},
    {Mutation::Op::separating, "separating"},
    {Mutation::Op::float32, "float32"},
    {Mutation::Op::naive_norm, "naive-norm"},
    {Mutation::Op::flush_subnormal, "flush-subnormal"},
    {Mutation::Op::constant_digits, "constant-digits"},
};

const char* op_name(Mutation::Op op) {
    for (const auto& o : kOps)
        if (o.op == op)
            return o.name;
    return "?";
}

// A double from a decimal of 6 significant digits (the constant-digits mutation).
double six_digits(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return std::strtod(buf, nullptr);
}

// IEEE double -> float conversion, overflow included (a plain cast beyond FLT_MAX is undefined).
float to_float(double x) {
    if (std::isnan(x))
        return NAN;
    if (std::fabs(x) >= 0x1.ffffffp127) // half an ulp above FLT_MAX rounds to infinity
        return x > 0 ? INFINITY : -INFINITY;
    return static_cast<float>(x);
}

class PlainLaw final : public Implementation {
  public:
    PlainLaw(const Model& model, const Mutation& m) : model_(model), m_(m), c_(model.contacts()) {
        for (const auto& piece : model.pieces()) {
            Piece p;
            for (std::size_t k = 0; k < c_; ++k)
                for (std::size_t j = 0; j < c_; ++j) {
                    const double r = nearest_double(piece.R_inv(k, j));
                    p.rinv.push_back(r);
                    p.rinv32.push_back(to_float(r));
                }
            for (std::size_t i = 0; i < c_; ++i)
                for (std::size_t j = 0; j < c_; ++j) {
                    double q = nearest_double(piece.Q(i, j));
                    if (m.op == Mutation::Op::constant_digits)
                        q = six_digits(q);
                    p.q.push_back(q);
                    p.q32.push_back(to_float(q));
                }
            pieces_.push_back(std::move(p));
        }
        if (m.op == Mutation::Op::sign) {
            pieces_[m.p].q[m.i * c_ + m.j] = -pieces_[m.p].q[m.i * c_ + m.j];
            pieces_[m.p].q32[m.i * c_ + m.j] = -pieces_[m.p].q32[m.i * c_ + m.j];
        }
    }

    void eval(const double* in, double* out, double*, std::size_t count, ImplStatus* status) override {
        for (std::size_t n = 0; n < count; ++n, in += c_, out += c_) {
            if (m_.op == Mutation::Op::float32)
                eval32(in, out);
            else
                eval64(in, out);
            status[n] = ImplStatus::ok;
        }
    }
    std::unique_ptr<Implementation> clone() const override { return std::make_unique<PlainLaw>(model_, m_); }
    std::string describe() const override {
        return m_.op == Mutation::Op::none ? "the law's plain double evaluation" : "mutant " + m_.id() + " of the law's plain double evaluation";
    }
    std::string replay_flags() const override { return "--mutant " + m_.id(); }

  private:
    struct Piece {
        std::vector<double> rinv, q;
        std::vector<float> rinv32, q32;
    };
    const Model& model_;
    Mutation m_;
    std::size_t c_;
    std::vector<Piece> pieces_;

    bool tested(std::size_t p, std::size_t k) const {
        return !(m_.op == Mutation::Op::facet_drop && m_.p == p && m_.i == k);
    }
    template <class T> bool passes(std::size_t p, std::size_t k, T t, T allowance) const {
        return m_.op == Mutation::Op::facet_flip && m_.p == p && m_.i == k ? t <= allowance : t >= -allowance;
    }
    // `if (gamma in cone 0) ... else` the last piece, in T (double, or float for float32): a
    // cone test allows rel times its row's absolute sum plus `tiny`, above the rounding of t_k.
    template <class T>
    std::size_t choose_piece(const T* g, std::vector<T> Piece::*rinv, T rel, T tiny) const {
        for (std::size_t p = 0; p + 1 < pieces_.size(); ++p) {
            const std::vector<T>& r = pieces_[p].*rinv;
            bool inside = true;
            for (std::size_t k = 0; k < c_ && inside; ++k) {
                T t = 0, a = 0;
                for (std::size_t j = 0; j < c_; ++j) {
                    const T term = r[k * c_ + j] * g[j];
                    t += term;
                    a += std::fabs(term);
                }
                if (tested(p, k) && !passes(p, k, t, a * rel + tiny))
                    inside = false;
            }
            if (inside)
                return p;
        }
        return pieces_.size() - 1;
    }
    std::size_t formula_of(std::size_t p) const { return m_.op == Mutation::Op::formula && m_.p == p ? m_.q : p; }

    void eval64(const double* in, double* out) const {
        double g[kMaxDim];
        double big = 0;
        for (std::size_t j = 0; j < c_; ++j) {
            g[j] = in[j];
            big = std::fmax(big, std::fabs(g[j]));
        }
        for (std::size_t j = 0; j < c_; ++j) {
            if (m_.op == Mutation::Op::dead_zone && std::fabs(g[j]) < m_.param)
                g[j] = 0;
            if (m_.op == Mutation::Op::slow_contact && std::fabs(g[j]) < m_.param * big)
                g[j] = 0;
            if (m_.op == Mutation::Op::flush_subnormal && std::fabs(g[j]) < DBL_MIN)
                g[j] = 0;
        }
        double norm = 1;
        if (m_.op == Mutation::Op::naive_norm) {
            double s = 0;
            for (std::size_t j = 0; j < c_; ++j)
                s += g[j] * g[j];
            norm = std::sqrt(s);
            if (norm == 0) {
                for (std::size_t j = 0; j < c_; ++j)
                    out[j] = 0;
                return;
            }
            for (std::size_t j = 0; j < c_; ++j)
                g[j] /= norm;
        }
        // The cone tests allow their own rounding (2^-46 of the row's absolute sum, plus an
        // underflow term), so that a point is never pushed out of its own cone by rounding alone.
        const std::size_t chosen = choose_piece(g, &Piece::rinv, 0x1p-46, 0x1p-1069);
        const Piece& f = pieces_[formula_of(chosen)];
        for (std::size_t i = 0; i < c_; ++i) {
            double y = 0;
            for (std::size_t j = 0; j < c_; ++j)
                y += f.q[i * c_ + j] * g[j];
            if (m_.op == Mutation::Op::separating && m_.i == i && in[i] > 0)
                y = -0.5 * g[i];
            if (m_.op == Mutation::Op::naive_norm)
                y *= norm;
            if (m_.op == Mutation::Op::flush_subnormal && std::fabs(y) < DBL_MIN)
                y = 0;
            out[i] = y;
        }
    }

    void eval32(const double* in, double* out) const {
        float g[kMaxDim];
        for (std::size_t j = 0; j < c_; ++j)
            g[j] = to_float(in[j]);
        const std::size_t chosen = choose_piece(g, &Piece::rinv32, 0x1p-17f, 0x1p-140f);
        const Piece& f = pieces_[chosen];
        for (std::size_t i = 0; i < c_; ++i) {
            float y = 0;
            for (std::size_t j = 0; j < c_; ++j)
                y += f.q32[i * c_ + j] * g[j];
            out[i] = static_cast<double>(y);
        }
    }
};

std::size_t index_in(std::string_view text, std::size_t bound, const std::string& id, const char* what) {
    std::size_t v = 0;
    if (text.empty() || text.size() > 9)
        throw InputError("--mutant " + id + ": expected a " + what + " index");
    for (char ch : text) {
        if (ch < '0' || ch > '9')
            throw InputError("--mutant " + id + ": expected a " + what + " index, got \"" + std::string(text) + "\"");
        v = v * 10 + static_cast<std::size_t>(ch - '0');
    }
    if (v >= bound)
        throw InputError("--mutant " + id + ": " + what + " " + std::to_string(v) + " out of range (the law has " +
                         std::to_string(bound) + ")");
    return v;
}

bool same_doubles(const Model& model, std::size_t p, std::size_t q) {
    const std::size_t c = model.contacts();
    for (std::size_t i = 0; i < c; ++i)
        for (std::size_t j = 0; j < c; ++j) {
            const double a = nearest_double(model.pieces()[p].Q(i, j)), b = nearest_double(model.pieces()[q].Q(i, j));
            if (!(a == b && std::signbit(a) == std::signbit(b)))
                return false;
        }
    return true;
}

} // namespace

std::string Mutation::id() const {
    const std::string name = op_name(op);
    switch (op) {
    case Op::dead_zone:
    case Op::slow_contact:
        return name + ":" + shortest_decimal(param);
    case Op::facet_flip:
    case Op::facet_drop:
        return name + ":" + std::to_string(p) + ":" + std::to_string(i);
    case Op::sign:
        return name + ":" + std::to_string(p) + ":" + std::to_string(i) + ":" + std::to_string(j);
    case Op::formula:
        return name + ":" + std::to_string(p) + ":" + std::to_string(q);
    case Op::separating:
        return name + ":" + std::to_string(i);
    default:
        return name;
    }
}

std::string Mutation::what(const Model& model) const {
    auto piece = [&](std::size_t k) { return "piece " + model.pieces()[k].name; };
    const std::string c = std::to_string(i + 1);
    switch (op) {
    case Op::none:
        return "no mutation (the control)";
    case Op::dead_zone:
        return "contact velocities of magnitude below " + shortest_decimal(param) + " read as 0 (a velocity threshold)";
    case Op::slow_contact:
        return "contact velocities below " + shortest_decimal(param) + " times the largest read as 0 (a relative tolerance)";
    case Op::facet_flip:
        return piece(p) + ": cone test " + std::to_string(i + 1) + " reversed";
    case Op::facet_drop:
        return piece(p) + ": cone test " + std::to_string(i + 1) + " missing (a missing clamp)";
    case Op::sign:
        return piece(p) + ": entry (" + std::to_string(i + 1) + "," + std::to_string(j + 1) + ") of Q negated";
    case Op::formula:
        return piece(p) + " computes " + piece(q) + "'s formula";
    case Op::separating:
        return "restitution 1/2 applied to contact coordinate " + c + " when it separates";
    case Op::float32:
        return "every operation in single precision (float)";
    case Op::naive_norm:
        return "input scaled by sqrt(sum of squares) and back (overflow, underflow)";
    case Op::flush_subnormal:
        return "subnormal inputs and outputs read as 0 (flush to zero)";
    case Op::constant_digits:
        return "every entry of Q rounded to 6 significant digits";
    }
    return "";
}

Mutation parse_mutation(std::string_view id, const Model& model) {
    const std::string whole(id);
    std::vector<std::string_view> parts;
    for (std::size_t start = 0;;) {
        const auto colon = id.find(':', start);
        parts.push_back(id.substr(start, colon == std::string_view::npos ? std::string_view::npos : colon - start));
        if (colon == std::string_view::npos)
            break;
        start = colon + 1;
    }
    Mutation m;
    bool found = false;
    for (const auto& o : kOps)
        if (parts[0] == o.name) {
            m.op = o.op;
            found = true;
        }
    if (!found) {
        std::string names;
        for (const auto& o : kOps)
            names += std::string(names.empty() ? "" : ", ") + o.name;
        throw InputError("--mutant " + whole + ": unknown operator (expected one of " + names + ")");
    }
    const std::size_t pieces = model.pieces().size(), c = model.contacts();
    auto want = [&](std::size_t n, const char* form) {
        if (parts.size() != n)
            throw InputError("--mutant " + whole + ": expected " + form);
    };
    using Op = Mutation::Op;
    switch (m.op) {
    case Op::dead_zone:
    case Op::slow_contact: {
        want(2, "OPERATOR:VALUE");
        const std::string v(parts[1]);
        char* end = nullptr;
        m.param = std::strtod(v.c_str(), &end);
        if (v.empty() || !((v[0] >= '0' && v[0] <= '9') || v[0] == '.') || *end != '\0' ||
            !(m.param > 0 && std::isfinite(m.param)))
            throw InputError("--mutant " + whole + ": expected a finite value > 0");
        break;
    }
    case Op::facet_flip:
    case Op::facet_drop:
        want(3, "OPERATOR:PIECE:ROW (0-based; the last piece is the else branch, with no test)");
        m.p = index_in(parts[1], pieces, whole, "piece");
        if (m.p + 1 == pieces)
            throw InputError("--mutant " + whole + ": the last piece is the else branch of the plain evaluation: it has no cone test");
        m.i = index_in(parts[2], c, whole, "row");
        break;
    case Op::sign:
        want(4, "sign:PIECE:ROW:COLUMN (0-based)");
        m.p = index_in(parts[1], pieces, whole, "piece");
        m.i = index_in(parts[2], c, whole, "row");
        m.j = index_in(parts[3], c, whole, "column");
        break;
    case Op::formula:
        want(3, "formula:PIECE:OTHER (0-based)");
        m.p = index_in(parts[1], pieces, whole, "piece");
        m.q = index_in(parts[2], pieces, whole, "piece");
        break;
    case Op::separating:
        want(2, "separating:CONTACT (0-based)");
        m.i = index_in(parts[1], c, whole, "contact");
        break;
    default:
        want(1, "the operator alone");
    }
    return m;
}

std::vector<MutantSite> enumerate_mutants(const Model& model, std::uint64_t seed) {
    using Op = Mutation::Op;
    const std::size_t pieces = model.pieces().size(), c = model.contacts();
    std::vector<std::vector<MutantSite>> groups;
    auto group = [&]() -> std::vector<MutantSite>& { return groups.emplace_back(); };
    auto site = [](Op op) {
        MutantSite s;
        s.mutation.op = op;
        return s;
    };
    {
        auto& g = group();
        for (double tau : {1e-6, 1e-3}) {
            auto s = site(Op::dead_zone);
            s.mutation.param = tau;
            g.push_back(s);
        }
    }
    {
        auto& g = group();
        for (double r : {1e-6, 1e-9}) {
            auto s = site(Op::slow_contact);
            s.mutation.param = r;
            g.push_back(s);
        }
    }
    for (Op op : {Op::facet_flip, Op::facet_drop}) {
        auto& g = group();
        for (std::size_t p = 0; p + 1 < pieces; ++p) // the last piece is the `else`: no test
            for (std::size_t k = 0; k < c; ++k) {
                auto s = site(op);
                s.mutation.p = p;
                s.mutation.i = k;
                g.push_back(s);
            }
    }
    {
        auto& g = group();
        for (std::size_t p = 0; p < pieces; ++p)
            for (std::size_t i = 0; i < c; ++i)
                for (std::size_t j = 0; j < c; ++j) {
                    auto s = site(Op::sign);
                    s.mutation.p = p;
                    s.mutation.i = i;
                    s.mutation.j = j;
                    if (nearest_double(model.pieces()[p].Q(i, j)) == 0)
                        s.equivalent = "the entry is 0: negated, it gives the same doubles (up to the sign of a zero)";
                    g.push_back(s);
                }
    }
    if (pieces > 1) {
        auto& g = group();
        for (std::size_t p = 0; p < pieces; ++p) {
            auto s = site(Op::formula);
            s.mutation.p = p;
            s.mutation.q = (p + 1) % pieces;
            if (same_doubles(model, p, s.mutation.q))
                s.equivalent = "the two pieces' matrices have the same doubles";
            g.push_back(s);
        }
    }
    {
        auto& g = group();
        for (std::size_t i = 0; i < c; ++i) {
            auto s = site(Op::separating);
            s.mutation.i = i;
            g.push_back(s);
        }
    }
    for (Op op : {Op::float32, Op::naive_norm, Op::flush_subnormal})
        group().push_back(site(op));
    {
        auto s = site(Op::constant_digits);
        bool same = true;
        for (const auto& piece : model.pieces())
            for (std::size_t i = 0; i < c; ++i)
                for (std::size_t j = 0; j < c; ++j) {
                    const double q = nearest_double(piece.Q(i, j));
                    same = same && six_digits(q) == q;
                }
        if (same)
            s.equivalent = "every entry of Q already has at most 6 significant digits";
        group().push_back(s);
    }
    // Each group in a seeded order (Fisher-Yates on SplitMix64), so that --mutants N with N below
    // the total picks sites from the whole law, and another --seed picks others.
    std::uint64_t st = seed ^ 0x6d7574616e7473ULL; // "mutants"
    std::vector<MutantSite> all;
    for (auto& g : groups) {
        for (std::size_t k = g.size(); k > 1; --k)
            std::swap(g[k - 1], g[splitmix(st) % k]);
        all.insert(all.end(), g.begin(), g.end());
    }
    return all;
}

std::vector<MutantSite> select_mutants(const std::vector<MutantSite>& all, std::size_t n) {
    std::vector<std::vector<const MutantSite*>> groups;
    for (const auto& s : all) {
        if (groups.empty() || groups.back().front()->mutation.op != s.mutation.op)
            groups.emplace_back();
        groups.back().push_back(&s);
    }
    std::vector<MutantSite> out;
    for (std::size_t round = 0; out.size() < n; ++round) {
        bool any = false;
        for (const auto& g : groups)
            if (round < g.size() && out.size() < n) {
                out.push_back(*g[round]);
                any = true;
            }
        if (!any)
            break;
    }
    return out;
}

std::unique_ptr<Implementation> plain_law(const Model& model, const Mutation& mutation) {
    return std::make_unique<PlainLaw>(model, mutation);
}

bool exact_violation(const Model& model, const Options& options, const double* x, const double* y, std::string* what,
                     bool velocities) {
    const std::size_t c = velocities ? model.balls() : model.contacts();
    const Matrix& metric = velocities ? model.M() : model.H();
    Vector gx;
    for (std::size_t j = 0; j < c; ++j)
        gx.push_back(exact_double(x[j], "exact_violation"));
    auto values = model.values_at(velocities ? model.contact_velocities(gx) : gx);
    if (values.empty())
        return false;
    if (velocities)
        for (auto& v : values)
            v = model.post_impact_velocities(gx, model.contact_velocities(gx), v);
    bool finite = true;
    for (std::size_t i = 0; i < c; ++i)
        finite = finite && std::isfinite(y[i]);
    for (const auto& v : values) {
        bool off = false;
        if (options.tolerance == Tolerance::relative) {
            if (!finite) {
                off = true;
                if (what)
                    *what = "a non-finite output";
            } else {
                Vector e, a;
                Matrix habs = metric;
                for (std::size_t i = 0; i < c; ++i) {
                    e.push_back(exact_double(y[i], "exact_violation") - v[i]);
                    a.push_back(exact_double(static_cast<double>(c) * 0x1p-1074, "exact_violation"));
                    for (std::size_t j = 0; j < c; ++j)
                        if (sign_of(habs(i, j)) == Sign::negative)
                            habs(i, j) = -habs(i, j);
                }
                const Rational R = exact_double(options.max_rel_error, "exact_violation");
                off = bilinear(e, metric, e) > R * R * bilinear(gx, metric, gx) + bilinear(a, habs, a);
                if (off && what)
                    *what = std::string(velocities ? "|y - S(x)|_M > " : "|y - S(x)|_H > ") + shortest_decimal(options.max_rel_error) +
                            (velocities ? " |x|_M" : " |x|_H") + " (exactly)";
            }
        } else {
            const std::uint64_t K = options.tolerance == Tolerance::ulps ? options.max_ulps : 0;
            for (std::size_t i = 0; i < c && !off; ++i) {
                const double r = nearest_double(v[i]);
                if (std::isnan(y[i]) || (!std::isfinite(y[i]) && std::isfinite(r)) || ulp_distance(y[i], r) > K) {
                    off = true;
                    if (what)
                        *what = "component " + std::to_string(i + 1) + " more than " + std::to_string(K) +
                                " ulp from the correctly rounded value (exactly)";
                }
            }
        }
        if (!off)
            return false; // within the tolerance of one of the law's values
    }
    return true;
}

namespace {

// The cheap filter of the witness search (a double approximation of the relative error; ulps
// exactly): candidates it passes are decided by exact_violation.
bool maybe_violation(const LawReference& ref, const Options& o, const double* x, const double* y, RefPoint& r) {
    ref.eval(x, r, false);
    if (!r.in_domain)
        return false;
    const std::size_t m = ref.in_dim(), c = ref.out_dim();
    for (std::size_t i = 0; i < c; ++i)
        if (!std::isfinite(y[i]))
            return true;
    double big = 0;
    for (std::size_t j = 0; j < m; ++j)
        big = std::fmax(big, std::fabs(x[j]));
    for (std::size_t v = 0; v < r.values; ++v) {
        if (o.tolerance == Tolerance::relative) {
            if (big == 0) {
                bool zero = true;
                for (std::size_t i = 0; i < c; ++i)
                    zero = zero && y[i] == 0;
                if (zero)
                    return false;
                continue;
            }
            const int s = -std::ilogb(big);
            double e2 = 0, x2 = 0;
            for (std::size_t i = 0; i < c; ++i) {
                const double e = std::ldexp(y[i], s) - std::ldexp(r.value[v][i], s);
                e2 += e * e;
            }
            for (std::size_t j = 0; j < m; ++j)
                x2 += std::ldexp(x[j], s) * std::ldexp(x[j], s);
            // Euclidean norms in place of H's, with a margin of 10^4 in the squares: a filter
            // only (H's conditioning beyond that can drop a candidate, never admit a false one).
            if (!(e2 > 1e-4 * o.max_rel_error * o.max_rel_error * x2))
                return false;
        } else {
            bool off = false;
            for (std::size_t i = 0; i < c; ++i)
                off = off || ulp_distance(y[i], r.value[v][i]) > o.max_ulps;
            if (!off)
                return false;
        }
    }
    return true;
}

struct Witness {
    std::vector<double> x, y;
    bool extreme = false;
    std::string what;
};

// Looks for an input where the mutant breaks the gate's tolerance, beyond what the gate sampled:
// the law's probes rescaled to powers of two from 2^-1070 to 2^1020, and with one component made
// slow (2^-8 .. 2^-48 of the largest). Non-extreme witnesses first.
std::optional<Witness> search_witness(const LawReference& ref, const Options& o, Implementation& impl,
                                      Implementation& control) {
    const std::size_t m = ref.in_dim();
    const Generator gen(ref);
    std::vector<std::vector<double>> shapes;
    const std::uint64_t probes = gen.prefix_count();
    const std::uint64_t step = std::max<std::uint64_t>(1, probes / 400);
    for (std::uint64_t k = 0; k < probes; k += step) {
        Sample s;
        gen.make(o.seed, k, s);
        for (const double* p : {s.a, s.b}) {
            double big = 0;
            for (std::size_t j = 0; j < m; ++j)
                big = std::fmax(big, std::fabs(p[j]));
            if (big == 0 || !std::isfinite(big))
                continue;
            std::vector<double> v(p, p + m);
            const int shift = -std::ilogb(big);
            for (auto& x : v)
                x = std::ldexp(x, shift);
            shapes.push_back(std::move(v));
            if (!s.pair)
                break;
        }
    }
    std::vector<int> scales = {0}; // moderate scales first: the witness a developer can use
    for (int e = 6; e <= 498; e += 6) {
        scales.push_back(-e);
        scales.push_back(e);
    }
    for (int e : {-1070, -1040, -1022, -1000, -800, -600, -510, 510, 600, 800, 1000, 1020})
        scales.push_back(e);
    std::vector<double> in, out(m * 64), yc(m);
    std::vector<ImplStatus> status(64);
    RefPoint r;
    std::optional<Witness> extreme;
    auto try_batch = [&]() -> std::optional<Witness> {
        const std::size_t n = in.size() / m;
        out.resize(n * m);
        status.resize(n);
        impl.eval(in.data(), out.data(), nullptr, n, status.data());
        for (std::size_t k = 0; k < n; ++k) {
            const double* x = &in[k * m];
            const double* y = &out[k * m];
            bool finite_in = true;
            for (std::size_t j = 0; j < m; ++j)
                finite_in = finite_in && std::isfinite(x[j]);
            if (!finite_in || !maybe_violation(ref, o, x, y, r))
                continue;
            Witness w;
            if (!exact_violation(ref.model(), o, x, y, &w.what))
                continue;
            // A difference the mutation makes: the control is within the tolerance there.
            ImplStatus cs;
            control.eval(x, yc.data(), nullptr, 1, &cs);
            if (exact_violation(ref.model(), o, x, yc.data()))
                continue;
            w.x.assign(x, x + m);
            w.y.assign(y, y + m);
            w.extreme = extreme_input(x, m);
            if (!w.extreme)
                return w;
            if (!extreme)
                extreme = w;
        }
        in.clear();
        return std::nullopt;
    };
    auto add = [&](const std::vector<double>& v, int e) -> std::optional<Witness> {
        for (double x : v)
            in.push_back(std::ldexp(x, e));
        if (in.size() / m == 64)
            return try_batch();
        return std::nullopt;
    };
    for (int e : scales)
        for (const auto& v : shapes)
            if (auto w = add(v, e))
                return w;
    for (int e : {0, -20, 20})
        for (const auto& v : shapes)
            for (std::size_t j = 0; j < m; ++j)
                for (int k = 8; k <= 48; k += 8)
                    for (double sign : {1.0, -1.0}) {
                        auto u = v;
                        u[j] = sign * std::ldexp(1.0, -k);
                        if (auto w = add(u, e))
                            return w;
                    }
    if (!in.empty())
        if (auto w = try_batch())
            return w;
    return extreme;
}

} // namespace

MutantsReport run_mutants(const Options& options, const LawReference& reference, const Properties& properties,
                          std::size_t count, const std::function<void(std::size_t, std::size_t)>& progress) {
    const Model& model = reference.model();
    MutantsReport rep;
    const auto all = enumerate_mutants(model, options.seed);
    rep.enumerated = all.size();
    const auto chosen = select_mutants(all, count);
    const auto control = plain_law(model, Mutation{});
    rep.control = run(options, reference, *control, properties, nullptr);
    // A gate that fails the control measures nothing: its examples would be the control's own.
    if (rep.control.fails(options.allow_extreme) || rep.control.samples == 0)
        return rep;
    const std::size_t m = reference.in_dim();
    for (std::size_t k = 0; k < chosen.size(); ++k) {
        MutantResult res;
        res.site = chosen[k];
        if (!res.site.equivalent.empty()) {
            res.status = MutantResult::Status::equivalent;
            ++rep.equivalent;
            rep.mutants.push_back(std::move(res));
            if (progress)
                progress(k + 1, chosen.size());
            continue;
        }
        const auto impl = plain_law(model, res.site.mutation);
        Options om = options;
        om.stop_on_failure = true;
        const Summary s = run(om, reference, *impl, properties, nullptr);
        res.samples = s.samples;
        res.seconds = s.seconds;
        if (s.fails(options.allow_extreme)) {
            res.status = MutantResult::Status::unconfirmed;
            for (const auto& v : s.examples) {
                if (options.allow_extreme && v.extreme)
                    continue;
                if (res.status == MutantResult::Status::killed)
                    break;
                // Evaluated again and decided by the second route, point a and (for a pair) b.
                for (const auto* x : {&v.input, &v.input_b}) {
                    if (x->size() != m || res.status == MutantResult::Status::killed)
                        continue;
                    std::vector<double> y(m);
                    ImplStatus st;
                    impl->eval(x->data(), y.data(), nullptr, 1, &st);
                    std::string what;
                    std::vector<double> yc(m);
                    control->eval(x->data(), yc.data(), nullptr, 1, &st);
                    if (exact_violation(model, options, x->data(), y.data(), &what) &&
                        !exact_violation(model, options, x->data(), yc.data())) {
                        res.status = MutantResult::Status::killed;
                        res.witness = *x;
                        res.output = y;
                        res.witness_extreme = v.extreme;
                        res.witness_what = what;
                        res.kill_index = v.index;
                        res.kill_kind = v.kind;
                    }
                }
            }
            if (res.status == MutantResult::Status::killed)
                ++rep.killed;
            else
                ++rep.unconfirmed;
        } else {
            auto searcher = impl->clone();
            const auto w = search_witness(reference, options, *searcher, *control);
            if (w) {
                res.witness = w->x;
                res.output = w->y;
                res.witness_extreme = w->extreme;
                res.witness_what = w->what;
            }
            if (w && !(w->extreme && options.allow_extreme))
                ++rep.survived_witness;
            else if (w)
                ++rep.extreme_only;
            else
                ++rep.survived_unknown;
        }
        rep.mutants.push_back(std::move(res));
        if (progress)
            progress(k + 1, chosen.size());
    }
    return rep;
}

} // namespace impactcert::fuzz
