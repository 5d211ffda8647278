// SPDX-License-Identifier: GPL-3.0-or-later
// identities -- proofs/README.md, "identities".
// Claim: the declared factorisations hold, e.g. Q_IIb = Q_IVa Q_IIa.
// Check: exact matrix products, one per identity. A failure reports the unit vector e_j of the
// first column where the two sides differ, with both images.
#include "prover/obligations/prover.hpp"

namespace impactcert::detail {

Outcome Prover::identities() {
    Outcome o;
    o.method = "exact matrix products";
    const auto& decls = m_.law().identities;
    for (std::size_t i = 0; i < decls.size(); ++i) {
        const Matrix& lhs = pieces_[m_.piece_index(decls[i].lhs)].Q;
        Matrix product = Matrix::identity(c_);
        Json names = Json::array();
        for (const auto& f : decls[i].product) {
            product = product * pieces_[m_.piece_index(f)].Q;
            names.push_back(f);
        }
        ++o.checks;
        o.data["products"].push_back(Json{{"lhs", decls[i].lhs}, {"product", names},
                                          {"lhs_matrix", to_json(lhs)}, {"product_matrix", to_json(product)}});
        if (lhs == product)
            continue;
        std::size_t col = 0;
        while (lhs.column(col) == product.column(col))
            ++col;
        const Vector e = unit_vector(c_, col);
        return refute(o, Json{{"identity", i}, {"lhs", decls[i].lhs}, {"product", names},
                              {"gamma", to_json(e)}, {"lhs_image", to_json(lhs * e)},
                              {"product_image", to_json(product * e)}});
    }
    return o;
}

} // namespace impactcert::detail
