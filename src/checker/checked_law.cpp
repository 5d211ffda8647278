// SPDX-License-Identifier: GPL-3.0-or-later
// The law of a certificate, read and re-derived (checked_law.hpp).
#include "checked_law.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace impactcert_check::detail {

namespace {

// The declarations that make identities, single-impacts and outcomes apply (non-empty lists;
// read_law has checked that each is an array when present).
bool declares(const Json& law, const char* key) { return law.contains(key) && !law.at(key).empty(); }

// Whether the H-isometry P has finite order (the prover's rule, proofs/README.md Lemma S0): the
// characteristic polynomial det(xI - P) has integer coefficients. Its coefficients from the
// traces of P, P^2, ..., P^c (Newton's identities), each required to be an integer as soon as
// it is known.
bool integral_characteristic_polynomial(const Mat& P) {
    const std::size_t c = P.size();
    std::vector<Q> e{Q(1)}, traces{Q(0)};
    Mat power = P;
    for (std::size_t k = 1; k <= c; ++k) {
        if (k > 1)
            power = mul(power, P);
        Q trace = 0;
        for (std::size_t i = 0; i < c; ++i)
            trace += power[i][i];
        traces.push_back(trace);
        Q sum = 0;
        for (std::size_t i = 1; i <= k; ++i)
            sum += (i % 2 == 1 ? 1 : -1) * e[k - i] * traces[i];
        Q ek = sum / static_cast<long>(k);
        ek.canonicalize();
        if (ek.get_den() != 1)
            return false;
        e.push_back(ek);
    }
    return true;
}

} // namespace

bool has_friction(const Json& law) {
    const Json& c = law.at("contacts");
    return c.is_object() && c.contains("friction") && !c.at("friction").empty();
}

bool applies(const Json& law, const std::string& id, bool redundant) {
    if (id == "coulomb")
        return has_friction(law);
    if (id == "P3") // no sign for a tangent, no orthant on a basis of dependent columns
        return !has_friction(law) && !redundant;
    if (id == "identities")
        return declares(law, "identities");
    if (id == "single-impacts")
        return declares(law, "single_impacts");
    if (id == "outcomes")
        return declares(law, "outcomes");
    if (id == "symmetries")
        return declares(law, "symmetries");
    return true;
}

namespace {

std::size_t bits_of(const Q& q) {
    return mpz_sizeinbase(q.get_num_mpz_t(), 2) + mpz_sizeinbase(q.get_den_mpz_t(), 2);
}

std::size_t bits_of(const Mat& m) {
    std::size_t b = 0;
    for (const auto& row : m)
        for (const auto& q : row)
            b = std::max(b, bits_of(q));
    return b;
}

std::size_t bytes_of(const Mat& m) {
    std::size_t b = 0;
    for (const auto& row : m)
        for (const auto& q : row)
            b += 96 + 8 * (mpz_size(q.get_num_mpz_t()) + mpz_size(q.get_den_mpz_t()));
    return b;
}

// A friction polygon: at least three facets, none zero, each turn from a_j to a_{j+1} strictly
// counterclockwise and less than a half turn, once around the origin (the turns' angles sum to
// one full turn: the facets pass the direction of the positive x axis once), and each vertex
// strictly inside the other facets.
Polygon read_polygon(const Json& facets, const std::string& path) {
    if (!facets.is_array())
        malformed(path, "expected an array");
    const std::size_t k = facets.size();
    require(k >= 3, path, "a friction polygon needs at least three facets");
    require(k <= 1024, path, "a friction polygon has at most 1024 facets"); // the format's bound, as the prover's
    Polygon poly;
    for (std::size_t j = 0; j < k; ++j) {
        Vec a = vec(facets[j], at(path, j));
        require(a.size() == 2, at(path, j), "needs two entries");
        require(sgn(a[0]) != 0 || sgn(a[1]) != 0, at(path, j), "is zero");
        poly.a.push_back(std::move(a));
    }
    std::size_t passes = 0;
    for (std::size_t j = 0; j < k; ++j) {
        const Vec& a = poly.a[j];
        const Vec& b = poly.a[(j + 1) % k];
        const Q det = a[0] * b[1] - a[1] * b[0];
        require(sgn(det) > 0, at(path, (j + 1) % k), "does not turn counterclockwise by less than a half turn");
        // The direction (1, 0) lies strictly inside the turn from a to b, or is b itself.
        const bool b_on_axis = sgn(b[1]) == 0 && sgn(b[0]) > 0;
        const bool inside = sgn(a[1]) < 0 && sgn(b[1]) > 0; // cross(a, e) > 0 and cross(e, b) > 0
        if (b_on_axis || inside)
            ++passes;
        Vec v{(b[1] - a[1]) / det, (a[0] - b[0]) / det};
        poly.v.push_back(std::move(v));
    }
    require(passes == 1, path, "does not go once around the origin");
    for (std::size_t j = 0; j < k; ++j)
        for (std::size_t i = 0; i < k; ++i)
            if (i != j && i != (j + 1) % k)
                require(poly.a[i][0] * poly.v[j][0] + poly.a[i][1] * poly.v[j][1] < 1, at(path, i), "is not an edge of the polygon");
    return poly;
}

} // namespace

Law read_law(const Json& j, const std::string& path, std::size_t max_pieces, std::size_t max_memory) {
    Law law;
    law.json = j;
    // The prover's input rules (SPEC section 4): a law it rejects is never verified.
    expect_keys(j, path, {"format", "name", "contacts", "pieces"},
                {"masses", "M", "coordinates", "identities", "single_impacts", "outcomes", "claims", "symmetries",
                 "pieces_listed"});
    require(field(j, path, "format") == "impactcert-law/1", at(path, "format"), "is not \"impactcert-law/1\"");
    require(!str(field(j, path, "name"), at(path, "name")).empty(), at(path, "name"), "empty law name");
    // The mass matrix: diagonal ("masses") or symmetric positive definite ("M"), exactly one.
    require(j.contains("masses") != j.contains("M"), path, "needs exactly one of \"masses\" and \"M\"");
    Mat M;
    if (j.contains("masses")) {
        law.masses = vec(field(j, path, "masses"), at(path, "masses"));
        law.n = law.masses.size();
        require(law.n >= 1, at(path, "masses"), "no balls");
        for (std::size_t i = 0; i < law.n; ++i)
            require(sgn(law.masses[i]) > 0, at(at(path, "masses"), i), "mass must be positive");
        M = zeros(law.n, law.n);
        for (std::size_t i = 0; i < law.n; ++i)
            M[i][i] = law.masses[i];
    } else {
        M = mat(field(j, path, "M"), at(path, "M"));
        law.n = M.size();
        require(M[0].size() == law.n, at(path, "M"), "not square");
        for (std::size_t i = 0; i < law.n; ++i)
            for (std::size_t k = 0; k < i; ++k)
                require(M[i][k] == M[k][i], at(at(at(path, "M"), i), k), "M is not symmetric");
        // Positive definite iff every leading principal minor is positive (Sylvester).
        for (std::size_t r = 1; r <= law.n; ++r) {
            Mat lead = zeros(r, r);
            for (std::size_t i = 0; i < r; ++i)
                for (std::size_t k = 0; k < r; ++k)
                    lead[i][k] = M[i][k];
            require(sgn(det(lead)) > 0, at(path, "M"), "not positive definite");
        }
    }
    const Json& contacts = field(j, path, "contacts");
    if (contacts.is_string() && contacts == "chain") {
        require(law.n >= 2, at(path, "masses"), "a chain needs two balls");
        law.W = zeros(law.n, law.n - 1);
        for (std::size_t k = 0; k + 1 < law.n; ++k) {
            law.W[k][k] = -1;
            law.W[k + 1][k] = 1;
        }
    } else {
        expect_keys(contacts, at(path, "contacts"), {"W"}, {"friction"});
        law.W = mat(field(contacts, at(path, "contacts"), "W"), at(at(path, "contacts"), "W"));
        require(law.W.size() == law.n, at(at(path, "contacts"), "W"), "needs one row per ball");
        law.normals = law.W[0].size();
        if (contacts.contains("friction")) {
            // SPEC section 9: each entry adds its tangents as columns of W after the normals.
            const std::string fp = at(at(path, "contacts"), "friction");
            const Json& fr = field(contacts, at(path, "contacts"), "friction");
            if (!fr.is_array())
                malformed(fp, "expected an array");
            for (std::size_t i = 0; i < fr.size(); ++i) {
                const std::string ep = at(fp, i);
                expect_keys(fr[i], ep, {"contact", "mu", "tangents"}, {"restitution_tangential", "facets"});
                const std::size_t k = natural(field(fr[i], ep, "contact"), at(ep, "contact"));
                require(k >= 1 && k <= law.normals, at(ep, "contact"), "no such contact");
                require(law.tangents.empty() || law.tangents.back().contact < k - 1, at(ep, "contact"),
                        "contacts must be listed once each, in increasing order");
                const Q mu = rat(field(fr[i], ep, "mu"), at(ep, "mu"));
                require(sgn(mu) >= 0, at(ep, "mu"), "negative friction coefficient");
                Q e_T = 0;
                if (fr[i].contains("restitution_tangential")) {
                    e_T = rat(field(fr[i], ep, "restitution_tangential"), at(ep, "restitution_tangential"));
                    require(sgn(e_T) >= 0 && e_T <= 1, at(ep, "restitution_tangential"), "not in [0, 1]");
                }
                const Json& ts = field(fr[i], ep, "tangents");
                if (!ts.is_array())
                    malformed(at(ep, "tangents"), "expected an array");
                require(ts.size() == 1 || ts.size() == 2, at(ep, "tangents"), "needs one or two tangents");
                for (std::size_t t = 0; t < ts.size(); ++t) {
                    const Vec column = vec(ts[t], at(at(ep, "tangents"), t));
                    require(column.size() == law.n, at(at(ep, "tangents"), t), "needs one entry per ball");
                    for (std::size_t r = 0; r < law.n; ++r)
                        law.W[r].push_back(column[r]);
                    law.tangents.push_back(Tangent{k - 1, mu, e_T});
                }
                law.polygons.resize(law.normals);
                if (fr[i].contains("facets")) {
                    require(ts.size() == 2, at(ep, "facets"), "a friction polygon needs two tangents");
                    law.polygons[k - 1] = read_polygon(field(fr[i], ep, "facets"), at(ep, "facets"));
                }
            }
        }
    }
    if (law.normals == 0)
        law.normals = law.W[0].size();
    law.polygons.resize(law.normals);
    law.c = law.W[0].size();
    // Dependent columns: each column kept when the Gram matrix of those kept with it stays
    // non-singular; every other column w_j is W_B x_j with x_j from the normal equations
    // (W_B^T W_B) x_j = W_B^T w_j, checked exactly.
    {
        std::vector<Vec> kept;
        for (std::size_t k = 0; k < law.c; ++k) {
            std::vector<Vec> trial = kept;
            trial.push_back(col(law.W, k));
            const Mat B = from_cols(trial);
            if (sgn(det(mul(tr(B), B))) != 0) {
                kept = std::move(trial);
                law.basis.push_back(k);
            }
        }
        require(!law.basis.empty(), at(path, "contacts"), "every column is zero (rank 0)");
        if (law.basis.size() < law.c) {
            law.redundant = true;
            law.d = law.c;
            law.all_W = law.W;
            law.W = from_cols(kept);
            const Mat gram = mul(tr(law.W), law.W);
            law.C = zeros(kept.size(), law.d);
            for (std::size_t k = 0; k < law.d; ++k) {
                const Vec w = col(law.all_W, k);
                Vec x;
                require(solve(gram, mul(tr(law.W), w), x) && mul(law.W, x) == w, at(path, "contacts"),
                        "a column outside the span of the columns kept");
                for (std::size_t i = 0; i < kept.size(); ++i)
                    law.C[i][k] = x[i];
            }
            law.Ct = tr(law.C);
            law.c = kept.size();
            require(!j.contains("symmetries"), at(path, "symmetries"), "a law on dependent contact columns declares no symmetries");
            require(!j.contains("single_impacts"), at(path, "single_impacts"),
                    "a law on dependent contact columns declares no single impacts");
        }
    }
    if (j.contains("coordinates")) {
        // Names only (informational), held to the prover's rules: one per velocity and per normal contact.
        const std::string cp = at(path, "coordinates");
        const Json& co = field(j, path, "coordinates");
        expect_keys(co, cp, {"velocities", "contacts"});
        for (const auto& [key, want] : {std::pair<const char*, std::size_t>{"velocities", law.n}, {"contacts", law.normals}}) {
            const Json& names = field(co, cp, key);
            if (!names.is_array())
                malformed(at(cp, key), "expected an array");
            require(names.size() == want, at(cp, key), "expected " + std::to_string(want) + " names");
            for (std::size_t i = 0; i < names.size(); ++i)
                str(names[i], at(at(cp, key), i));
        }
    }
    require(invert(M, law.M_inv), at(path, "M"), "M is singular");
    law.G = mul(mul(tr(law.W), law.M_inv), law.W);
    require(invert(law.G, law.H), at(path, "contacts"), "G is singular");
    const Json& pieces = field(j, path, "pieces");
    if (!pieces.is_array())
        malformed(at(path, "pieces"), "expected an array");
    require(!pieces.empty(), at(path, "pieces"), "no pieces");
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        const std::string pp = at(at(path, "pieces"), p);
        expect_keys(pieces[p], pp, {"name", "Q"}, {"rays", "impulses"});
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
        require(pieces[p].contains("impulses") == law.redundant, law.redundant ? pp : at(pp, "impulses"),
                law.redundant ? "needs \"impulses\" (dependent contact columns)" : "impulses on independent contact columns");
        if (law.redundant) {
            piece.L = mat(field(pieces[p], pp, "impulses"), at(pp, "impulses"));
            require(piece.L.size() == law.d && piece.L[0].size() == law.c, at(pp, "impulses"), "not d x c");
        }
        for (const auto& r : piece.rays)
            if (law.ray_index.emplace(r, law.distinct_rays.size()).second)
                law.distinct_rays.push_back(r);
        law.pieces.push_back(std::move(piece));
    }
    law.listed_pieces = law.pieces.size();
    // Symmetries, and with orbit representatives the pieces they generate.
    if (j.contains("symmetries")) {
        const Json& syms = field(j, path, "symmetries");
        if (!syms.is_array())
            malformed(at(path, "symmetries"), "expected an array");
        std::set<std::string> names;
        for (std::size_t g = 0; g < syms.size(); ++g) {
            const std::string sp = at(at(path, "symmetries"), g);
            expect_keys(syms[g], sp, {"name", "P", "P_prime"});
            Symmetry sym;
            sym.name = str(field(syms[g], sp, "name"), at(sp, "name"));
            require(!sym.name.empty(), at(sp, "name"), "empty symmetry name");
            require(names.insert(sym.name).second, at(sp, "name"), "duplicate symmetry name");
            sym.P = mat(field(syms[g], sp, "P"), at(sp, "P"));
            sym.P_prime = mat(field(syms[g], sp, "P_prime"), at(sp, "P_prime"));
            for (const char* key : {"P", "P_prime"}) {
                const Mat& m = std::string(key) == "P" ? sym.P : sym.P_prime;
                require(m.size() == law.c && m[0].size() == law.c, at(sp, key), "not c x c");
            }
            require(invert(sym.P, sym.P_inv), at(sp, "P"), "singular P");
            law.symmetries.push_back(std::move(sym));
        }
    }
    if (j.contains("pieces_listed")) {
        const std::string listed = str(field(j, path, "pieces_listed"), at(path, "pieces_listed"));
        require(listed == "all" || listed == "orbit-representatives", at(path, "pieces_listed"),
                "expected \"all\" or \"orbit-representatives\"");
        if (listed == "orbit-representatives") {
            require(!law.symmetries.empty(), at(path, "pieces_listed"), "orbit representatives need symmetries");
            // The prover's input rules: a compact law's symmetries are H-isometries, each P of
            // finite order, and generated names stay within 4,096 characters.
            for (std::size_t g = 0; g < law.symmetries.size(); ++g) {
                const Symmetry& sym = law.symmetries[g];
                const std::string sp = at(at(path, "symmetries"), g);
                require(mul(mul(tr(sym.P), law.H), sym.P) == law.H, at(sp, "P"), "not an H-isometry in a compact law");
                require(mul(mul(tr(sym.P_prime), law.H), sym.P_prime) == law.H, at(sp, "P_prime"),
                        "not an H-isometry in a compact law");
                // c <= 32 (kMaxOrderCheckContacts of the prover); beyond, the growth rule below.
                require(sym.P.size() > 32 || integral_characteristic_polynomial(sym.P), at(sp, "P"),
                        "of infinite order (its characteristic polynomial has a coefficient that is not an "
                        "integer): it generates pieces without end");
            }
            std::map<std::vector<std::size_t>, std::size_t> by_rays;
            auto key = [&](const std::vector<Vec>& rays) {
                std::vector<std::size_t> ids;
                for (const auto& r : rays) {
                    auto it = law.ray_index.find(r);
                    ids.push_back(it == law.ray_index.end() ? SIZE_MAX : it->second);
                }
                std::sort(ids.begin(), ids.end());
                return ids;
            };
            for (std::size_t p = 0; p < law.pieces.size(); ++p)
                by_rays.emplace(key(law.pieces[p].rays), p);
            std::size_t listed_bits = 0, bytes = 0;
            for (const auto& piece : law.pieces) {
                listed_bits = std::max({listed_bits, bits_of(piece.Q_), bits_of(from_cols(piece.rays))});
                bytes += bytes_of(piece.Q_) + bytes_of(piece.R) + bytes_of(piece.R_inv); // as the prover counts
            }
            for (const Symmetry& sym : law.symmetries)
                listed_bits = std::max({listed_bits, bits_of(sym.P), bits_of(sym.P_prime), bits_of(sym.P_inv)});
            const std::size_t max_bits = 16 * listed_bits + 1024;
            const std::size_t max_bytes = max_memory > (SIZE_MAX >> 20) ? SIZE_MAX : max_memory << 20;
            for (std::size_t p = 0; p < law.pieces.size(); ++p)
                for (const Symmetry& sym : law.symmetries) {
                    Piece image;
                    for (const auto& r : law.pieces[p].rays)
                        image.rays.push_back(primitive(mul(sym.P, r)));
                    const auto k = key(image.rays);
                    if (k.back() != SIZE_MAX && by_rays.count(k))
                        continue;
                    if (law.pieces.size() >= max_pieces)
                        undecided("--max-pieces", at(path, "symmetries"),
                                  "the symmetries generate more than " + std::to_string(max_pieces) + " pieces");
                    image.name = law.pieces[p].name + "." + sym.name;
                    require(image.name.size() <= 4096, at(path, "symmetries"),
                            "generated piece name longer than 4096 characters");
                    require(law.piece_index.emplace(image.name, law.pieces.size()).second, at(path, "symmetries"),
                            "generated piece name \"" + image.name + "\" is taken");
                    image.Q_ = mul(mul(sym.P_prime, law.pieces[p].Q_), sym.P_inv);
                    image.R = from_cols(image.rays);
                    require(std::max(bits_of(image.Q_), bits_of(image.R)) <= max_bits, at(path, "symmetries"),
                            "generated piece \"" + image.name.substr(0, 60) +
                                "\" has numbers of more than 16 times the bits of the listed data (a symmetry of infinite order?)");
                    require(invert(image.R, image.R_inv), at(path, "symmetries"), "a generated cone is degenerate");
                    bytes += bytes_of(image.Q_) + bytes_of(image.R) + bytes_of(image.R_inv) + 2 * image.name.size() + 512;
                    for (const auto& r : image.rays)
                        if (law.ray_index.emplace(r, law.distinct_rays.size()).second) {
                            law.distinct_rays.push_back(r);
                            bytes += 2 * (bytes_of(Mat{r}) + 64);
                        }
                    if (bytes > max_bytes)
                        undecided("--max-memory", at(path, "symmetries"),
                                  "the generated pieces need more than " + std::to_string(max_memory) + " MB (" +
                                      std::to_string(law.pieces.size() + 1) + " pieces so far)");
                    by_rays.emplace(key(image.rays), law.pieces.size());
                    law.pieces.push_back(std::move(image));
                }
        }
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
        require(d.contact <= law.normals, at(ip, "contact"), "a friction tangent: single impacts are declared at normals");
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
            require(std::find(kFrictionIds.begin(), kFrictionIds.end(), id) != kFrictionIds.end(), at(at(path, "claims"), i), "unknown obligation");
            require(law.claimed_ids.insert(id).second, at(at(path, "claims"), i), "claimed twice");
            require(applies(j, id, law.redundant), at(at(path, "claims"), i), "claimed but the law declares nothing for it");
        }
    }
    return law;
}

} // namespace impactcert_check::detail
