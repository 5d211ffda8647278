// SPDX-License-Identifier: GPL-3.0-or-later
#include "prover/smt.hpp"

#include <functional>

namespace impactcert {

namespace {

std::string num(const Rational& r) {
    const std::string s = to_string(abs_of(r));
    const auto slash = s.find('/');
    const std::string magnitude =
        slash == std::string::npos ? s : "(/ " + s.substr(0, slash) + " " + s.substr(slash + 1) + ")";
    return sign_of(r) == Sign::negative ? "(- " + magnitude + ")" : magnitude;
}

// sum_k coeffs[k] * vars[k]
std::string linear(const Vector& coeffs, const std::vector<std::string>& vars) {
    std::string terms;
    for (std::size_t k = 0; k < coeffs.size(); ++k)
        if (sign_of(coeffs[k]) != Sign::zero)
            terms += " (* " + num(coeffs[k]) + " " + vars[k] + ")";
    return terms.empty() ? "0" : "(+ 0" + terms + ")";
}

std::vector<std::string> image(const Matrix& A, const std::vector<std::string>& vars) {
    std::vector<std::string> out;
    for (std::size_t i = 0; i < A.rows(); ++i)
        out.push_back(linear(A.row(i), vars));
    return out;
}

// x^T A x for expressions x.
std::string quadratic(const Matrix& A, const std::vector<std::string>& x) {
    std::string terms;
    for (std::size_t i = 0; i < A.rows(); ++i)
        for (std::size_t j = 0; j < A.cols(); ++j)
            if (sign_of(A(i, j)) != Sign::zero)
                terms += " (* " + num(A(i, j)) + " " + x[i] + " " + x[j] + ")";
    return terms.empty() ? "0" : "(+ 0" + terms + ")";
}

std::string conj(const std::vector<std::string>& parts, const char* op = "and") {
    if (parts.empty())
        return std::string(op) == "and" ? "true" : "false";
    if (parts.size() == 1)
        return parts.front();
    std::string s = std::string("(") + op;
    for (const auto& p : parts)
        s += " " + p;
    return s + ")";
}

class Writer {
  public:
    explicit Writer(const Model& m) : m_(m), c_(m.contacts()) {}

    std::vector<std::string> vars(const std::string& prefix) const {
        std::vector<std::string> v;
        for (std::size_t k = 0; k < c_; ++k)
            v.push_back(prefix + std::to_string(k + 1));
        return v;
    }

    // gamma in the closed (or open) cone of piece p: R^-1 gamma >= 0 (> 0).
    std::string in_cone(std::size_t p, const std::vector<std::string>& g, bool open = false) const {
        std::vector<std::string> parts;
        for (std::size_t k = 0; k < c_; ++k)
            parts.push_back(std::string("(") + (open ? ">" : ">=") + " " +
                            linear(m_.pieces()[p].R_inv.row(k), g) + " 0)");
        return conj(parts);
    }

    std::string covered(const std::vector<std::string>& g) const {
        std::vector<std::string> parts;
        for (std::size_t p = 0; p < m_.pieces().size(); ++p)
            parts.push_back(in_cone(p, g));
        return conj(parts, "or");
    }

    // Component k of S(g), as nested ite over the pieces (the first containing piece wins; a
    // point in no cone falls through to 0, and `covered` is asserted alongside).
    std::string S(const std::vector<std::string>& g, std::size_t k) const {
        std::string expr = "0";
        for (std::size_t p = m_.pieces().size(); p-- > 0;)
            expr = "(ite " + in_cone(p, g) + " " + linear(m_.pieces()[p].Q.row(k), g) + " " + expr + ")";
        return expr;
    }

    std::string header(const std::string& id, const std::string& negated, std::size_t copies) const {
        std::string s = "; impactcert smt: law \"" + m_.law().name + "\", claim " + id + "\n";
        s += "; asserts the negation: " + negated + "\n; unsat = the claim holds, sat = a counterexample\n";
        s += "(set-logic QF_NRA)\n";
        for (const char* prefix : {"g", "a", "b"}) {
            if (copies == 0)
                break;
            --copies;
            for (const auto& v : vars(prefix))
                s += "(declare-const " + v + " Real)\n";
        }
        return s;
    }

    std::string finish(const std::string& assertion) const {
        return "(assert " + assertion + ")\n(check-sat)\n(exit)\n";
    }

    std::vector<SmtProblem> all() const {
        const auto& pieces = m_.pieces();
        const std::size_t P = pieces.size();
        const auto g = vars("g"), a = vars("a"), b = vars("b");
        std::vector<SmtProblem> out;
        auto per_piece = [&](const std::function<std::string(std::size_t)>& f) {
            std::vector<std::string> parts;
            for (std::size_t p = 0; p < P; ++p)
                parts.push_back(f(p));
            return conj(parts, "or");
        };

        // fan: some gamma in no cone, or in the interiors of two cones.
        // S is not a function (SPEC section 3): some gamma in no cone, or in the interiors of two
        // cones whose matrices differ there; then kinematic and nonexpansive fail with it.
        std::vector<std::string> bad_fan = {"(not " + covered(g) + ")"};
        std::vector<std::string> not_function = {"(not " + covered(g) + ")"};
        for (std::size_t i = 0; i < P; ++i)
            for (std::size_t j = i + 1; j < P; ++j) {
                const std::string both = "(and " + in_cone(i, g, true) + " " + in_cone(j, g, true);
                bad_fan.push_back(both + ")");
                std::vector<std::string> differ;
                const auto qi = image(pieces[i].Q, g), qj = image(pieces[j].Q, g);
                for (std::size_t k = 0; k < c_; ++k)
                    differ.push_back("(not (= " + qi[k] + " " + qj[k] + "))");
                not_function.push_back(both + " " + conj(differ, "or") + ")");
            }
        const std::string fan_fails = conj(bad_fan, "or");
        const std::string s_not_function = conj(not_function, "or");
        out.push_back({"fan", header("fan", "exists gamma uncovered, or in two open cones", 1) + finish(fan_fails)});
        {   // P1: two pieces disagree at a common point
            std::vector<std::string> bad;
            for (std::size_t i = 0; i < P; ++i)
                for (std::size_t j = i + 1; j < P; ++j) {
                    std::vector<std::string> differ;
                    const auto qi = image(pieces[i].Q, g), qj = image(pieces[j].Q, g);
                    for (std::size_t k = 0; k < c_; ++k)
                        differ.push_back("(not (= " + qi[k] + " " + qj[k] + "))");
                    bad.push_back("(and " + in_cone(i, g) + " " + in_cone(j, g) + " " + conj(differ, "or") + ")");
                }
            out.push_back({"P1", header("P1", "exists gamma in two cones whose matrices disagree there", 1) +
                                     finish(conj(bad, "or"))});
        }
        out.push_back({"P2", header("P2", "exists piece i and gamma with |Q_i gamma|_H != |gamma|_H", 1) +
                                 finish(per_piece([&](std::size_t p) {
                                     return "(not (= " + quadratic(m_.H(), image(pieces[p].Q, g)) + " " +
                                            quadratic(m_.H(), g) + "))";
                                 }))});
        out.push_back({"P3", header("P3", "exists piece i: a point of C_i maps outside the orthant, or a point "
                                          "of the orthant is not the image of a point of C_i", 1) +
                                 finish(per_piece([&](std::size_t p) {
                                     std::vector<std::string> outside, parts;
                                     const auto img = image(pieces[p].Q, g);
                                     for (const auto& e : img)
                                         outside.push_back("(< " + e + " 0)");
                                     parts.push_back("(and " + in_cone(p, g) + " " + conj(outside, "or") + ")");
                                     if (auto q_inv = inverse(pieces[p].Q)) {
                                         std::vector<std::string> orthant;
                                         for (const auto& v : g)
                                             orthant.push_back("(>= " + v + " 0)");
                                         parts.push_back("(and " + conj(orthant) + " (not " +
                                                         in_cone(p, image(*q_inv, g)) + "))");
                                     } else {
                                         parts.push_back("true"); // a singular Q cannot be onto
                                     }
                                     return conj(parts, "or");
                                 }))});
        out.push_back({"kinematic", header("kinematic", "S is not a function, or a piece gives a "
                                                        "negative gamma+ inside its cone", 1) +
                                        finish(conj({s_not_function, per_piece([&](std::size_t p) {
                                                         std::vector<std::string> neg;
                                                         for (const auto& e : image(pieces[p].Q, g))
                                                             neg.push_back("(< " + e + " 0)");
                                                         return "(and " + in_cone(p, g) + " " + conj(neg, "or") + ")";
                                                     })},
                                                    "or"))});
        out.push_back({"kinetic", header("kinetic", "exists piece i and gamma in C_i with H (Q_i - I) gamma "
                                                    "not >= 0", 1) +
                                      finish(per_piece([&](std::size_t p) {
                                          std::vector<std::string> neg;
                                          const Matrix K = m_.H() * (pieces[p].Q - Matrix::identity(c_));
                                          for (const auto& e : image(K, g))
                                              neg.push_back("(< " + e + " 0)");
                                          return "(and " + in_cone(p, g) + " " + conj(neg, "or") + ")";
                                      }))});
        out.push_back({"energetic", header("energetic", "exists piece i and gamma in C_i with |Q_i gamma|_H > "
                                                        "|gamma|_H", 1) +
                                        finish(per_piece([&](std::size_t p) {
                                            return "(and " + in_cone(p, g) + " (> " +
                                                   quadratic(m_.H(), image(pieces[p].Q, g)) + " " +
                                                   quadratic(m_.H(), g) + "))";
                                        }))});
        {   // nonexpansive: S undefined somewhere, or |S(a) - S(b)|_H > |a - b|_H
            std::vector<std::string> d_out, d_in;
            for (std::size_t k = 0; k < c_; ++k) {
                d_out.push_back("(- " + S(a, k) + " " + S(b, k) + ")");
                d_in.push_back("(- " + a[k] + " " + b[k] + ")");
            }
            const std::string violation = "(and " + covered(a) + " " + covered(b) + " (> " +
                                          quadratic(m_.H(), d_out) + " " + quadratic(m_.H(), d_in) + "))";
            std::string s = header("nonexpansive", "S is not a function, or a, b with |S(a) - S(b)|_H > "
                                                   "|a - b|_H (S as nested ite over the cones)", 3);
            out.push_back({"nonexpansive", s + finish("(or " + s_not_function + " " + violation + ")")});
        }
        return out;
    }

  private:
    const Model& m_;
    std::size_t c_;
};

} // namespace

std::vector<SmtProblem> smt_problems(const Model& model) { return Writer(model).all(); }

} // namespace impactcert
