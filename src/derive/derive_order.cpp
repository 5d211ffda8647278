// SPDX-License-Identifier: GPL-3.0-or-later
// derive_order.cpp -- does the sequential law depend on the order of the impacts? (derive.hpp)
//
// Every admissible word is a path in a tree of cells (not necessarily closed polyhedral cones,
// PPL's NNC_Polyhedron): the root is the whole space with the identity map; the child of a cell
// R with map A by contact k is R n {(A x)_k < 0} with map Q^(k) A; the final cell of a node is
// R n {A x >= 0}. Two final cells with maps A != B that meet at a point x with A x != B x show
// that the order matters at x. The argument is in proofs/README.md ("Order independence").
#include "derive/derive.hpp"
#include "derive/derive_regions.hpp"
#include "base/errors.hpp"

namespace impactcert {

using namespace derive_detail;

namespace {

using Cell = PPL::NNC_Polyhedron;

// A final cell with its minimized constraints and generators as exact vectors, for the
// separation test.
struct Final {
    Cell cell;
    Matrix map;
    std::vector<std::size_t> word;
    std::vector<std::pair<Vector, bool>> constraints; // a . x >= 0, or > 0 when the flag is set
    std::vector<std::pair<Vector, int>> generators;   // 0 point, 1 closure point, 2 ray, 3 line
};

Final make_final(Cell cell, const Matrix& map, const std::vector<std::size_t>& word, std::size_t c) {
    Final f{std::move(cell), map, word, {}, {}};
    for (const auto& k : f.cell.minimized_constraints()) {
        const auto v = constraint_vector(k, c);
        if (!v || is_zero(*v))
            continue; // holds everywhere (a non-empty cell has no 0 > 0)
        const Vector& a = *v;
        if (k.is_equality()) {
            f.constraints.push_back({a, false});
            f.constraints.push_back({Rational(-1) * a, false});
        } else {
            f.constraints.push_back({a, k.is_strict_inequality()});
        }
    }
    for (const auto& g : f.cell.minimized_generators())
        f.generators.push_back({generator_vector(g, c), g.is_point() ? 0 : g.is_closure_point() ? 1 : g.is_ray() ? 2 : 3});
    return f;
}

// True when some constraint of `a` excludes every point of `b`: b lies in {x : not (a . x >= 0)}
// (or not (a . x > 0) for a strict one). Every point of b is a combination of its generators with
// a positive weight on some point: if every generator has a . g <= 0 (0 on lines) and every point
// generator a . g < 0, then a . x < 0 on b; for a strict constraint a . g <= 0 everywhere suffices.
bool separated(const Final& a, const Final& b) {
    for (const auto& [n, strict] : a.constraints) {
        bool out = true;
        for (const auto& [g, kind] : b.generators) {
            const Sign s = sign_of(dot(n, g));
            if (kind == 3 ? s != Sign::zero : s == Sign::positive) {
                out = false;
                break;
            }
            if (kind == 0 && !strict && s == Sign::zero) {
                out = false;
                break;
            }
        }
        if (out)
            return true;
    }
    return false;
}

// A point of a non-empty cell, as a primitive integer vector (cells are cones: any positive
// multiple of a point is a point), with the other generators: x0 + g lies in the cell for every
// point, ray and closure point g, and x0 +- l for a line l (for a closure point: x0 / 2 + g / 2
// satisfies every strict constraint, as x0 does strictly and g weakly).
std::vector<Vector> probes(const Cell& cell, std::size_t c) {
    const PPL::Generator_System& gs = cell.minimized_generators();
    std::optional<Vector> x0;
    for (const auto& g : gs)
        if (g.is_point()) {
            x0 = generator_vector(g, c);
            break;
        }
    if (!x0)
        throw std::logic_error("derive --rule any: a non-empty cell without a point");
    std::vector<Vector> out{*x0};
    for (const auto& g : gs) {
        const Vector v = generator_vector(g, c);
        out.push_back(*x0 + v);
        if (g.is_line())
            out.push_back(*x0 - v);
    }
    return out;
}

std::vector<Vector> outcome_rows(const Matrix& A, std::size_t c) {
    std::vector<Vector> rows;
    for (std::size_t j = 0; j < c; ++j)
        rows.push_back(A.row(j));
    return rows;
}

} // namespace

OrderResult order_independence(const DeriveOptions& options, std::size_t max_words) {
    const Mechanics mech = make_mechanics(options);
    const std::size_t c = mech.contacts();
    if (options.restitution.size() != c)
        throw InputError("--restitution: expected one value or " + std::to_string(c) + " (one per contact), got " +
                         std::to_string(options.restitution.size()));
    const PplScope ppl;
    std::vector<Matrix> Qk;
    for (std::size_t k = 0; k < c; ++k) {
        Qk.push_back(two_body_impact(mech.G, k, options.restitution[k]));
        check_bits(Qk.back(), options.max_bits, "the impact matrix of contact " + std::to_string(k + 1));
    }

    OrderResult result;
    std::vector<Final> finals;
    std::vector<std::string> keys; // each final cell's map, as text (cells of one map never disagree)
    // Compares final cell j with every earlier one of a different map, as soon as j is found (a
    // refutation ends the walk early). True when a witness was found.
    auto compare_new = [&](std::size_t j) {
        for (std::size_t i = 0; i < j; ++i) {
            if (keys[i] == keys[j])
                continue;
            if (++result.pairs > kPairsPerWord * max_words)
                throw DeriveLimit("derive --rule any: more than " + std::to_string(kPairsPerWord * max_words) +
                                  " pairs of final cells to compare (--max-words " + std::to_string(max_words) + ")");
            if (options.progress && result.pairs % 65536 == 0)
                options.progress("order pairs", result.pairs, 0);
            if (separated(finals[i], finals[j]) || separated(finals[j], finals[i]))
                continue;
            Cell meet = finals[i].cell;
            meet.intersection_assign(finals[j].cell);
            if (meet.is_empty())
                continue;
            for (const Vector& x : probes(meet, c)) {
                if (finals[i].map * x == finals[j].map * x)
                    continue;
                OrderWitness w{primitive_ray(x), finals[i].word, finals[j].word, {}, {}};
                w.gamma_a = finals[i].map * w.gamma_minus;
                w.gamma_b = finals[j].map * w.gamma_minus;
                if (!order_witness_holds(options, options.restitution, w))
                    throw std::logic_error("derive --rule any: a witness the simulation does not confirm");
                result.witness = std::move(w);
                return true;
            }
        }
        return false;
    };
    struct Node {
        Cell cell;
        Matrix map;
        std::vector<std::size_t> word;
    };
    std::vector<Node> work;
    work.push_back({Cell(static_cast<PPL::dimension_type>(c), PPL::UNIVERSE), Matrix::identity(c), {}});
    std::size_t nodes = 0;
    while (!work.empty()) {
        Node node = std::move(work.back());
        work.pop_back();
        if (++nodes > max_words)
            throw DeriveLimit("derive --rule any: more than " + std::to_string(max_words) +
                              " admissible words (--max-words)");
        if (options.progress && nodes % 256 == 0)
            options.progress("orders", nodes, 0);
        // The final cell: no contact approaches after the word.
        Cell end = node.cell;
        for (const auto& row : outcome_rows(node.map, c))
            if (!is_zero(row))
                end.add_constraint(form(row) >= 0);
        if (!end.is_empty()) {
            result.max_word = std::max(result.max_word, node.word.size());
            finals.push_back(make_final(std::move(end), node.map, node.word, c));
            std::string key;
            for (const auto& row : outcome_rows(node.map, c))
                key += to_string(row) + ";";
            keys.push_back(key);
            if (compare_new(finals.size() - 1)) {
                result.words = finals.size();
                return result;
            }
        }
        // The children: contact k approaches after the word (a zero row never does).
        for (std::size_t k = c; k-- > 0;) {
            const Vector row = node.map.row(k);
            if (is_zero(row))
                continue;
            Cell next = node.cell;
            next.add_constraint(form(row) < 0);
            if (next.is_empty())
                continue;
            auto word = node.word;
            word.push_back(k);
            if (node.word.size() == options.max_impacts) {
                result.not_finite = probes(next, c).front();
                result.long_word = word;
                return result;
            }
            Matrix map = Qk[k] * node.map;
            check_bits(map, options.max_bits, "the map of word " + word_text(word, c));
            work.push_back({std::move(next), std::move(map), std::move(word)});
        }
    }
    result.words = finals.size();
    return result;
}

bool order_witness_holds(const System& system, const std::vector<Rational>& restitution, const OrderWitness& w) {
    const Mechanics mech = make_mechanics(system);
    const std::size_t c = mech.contacts();
    if (w.gamma_minus.size() != c || restitution.size() != c)
        return false;
    auto run = [&](const std::vector<std::size_t>& word, const Vector& expected) {
        Vector g = w.gamma_minus;
        for (const std::size_t k : word) {
            if (k >= c || sign_of(g[k]) != Sign::negative)
                return false; // not admissible: contact k does not approach
            // The impulse of contact k: gamma <- gamma - (1 + e) gamma_k G e_k / G_kk.
            const Rational scale = (Rational(1) + restitution[k]) * g[k] / mech.G(k, k);
            for (std::size_t j = 0; j < c; ++j)
                g[j] = g[j] - scale * mech.G(j, k);
        }
        for (std::size_t j = 0; j < c; ++j)
            if (sign_of(g[j]) == Sign::negative)
                return false; // the word does not end the process
        return g == expected;
    };
    return run(w.word_a, w.gamma_a) && run(w.word_b, w.gamma_b) && w.gamma_a != w.gamma_b;
}

} // namespace impactcert
