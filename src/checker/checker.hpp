// SPDX-License-Identifier: GPL-3.0-or-later
// checker.hpp -- internal to src/checker/: impactcert-check, the independent checker of
// impactcert-certificate/1 documents.
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
//
// Files: reading (strict JSON, rationals, errors), linalg (exact linear algebra), sha256,
// checked_law (the law and its validation), tiling (chambers, walls), copositivity_evidence;
// the Checker's members by concept: obligations.cpp (verdicts, limits, evidence of each
// obligation), fan.cpp (the fan, S as a function), p1.cpp (P1's pairs, intersections and shared
// rays), witnesses.cpp (counterexamples); check.cpp (the document, check_text); main.cpp.
#pragma once

#include "checked_law.hpp"
#include "copositivity_evidence.hpp"
#include "impactcert_check.hpp"
#include "linalg.hpp"
#include "reading.hpp"

#include <algorithm>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace impactcert_check {
namespace detail {

// The prover's limits (src/base/limits.hpp), with the same defaults and options, counted the same
// way and checked before the work is done.
struct Limits {
    std::size_t max_faces = 16384;     // --max-faces: simplex faces of one KKT enumeration
    std::size_t max_chambers = 200000; // --max-chambers: steps of the chamber enumeration
    std::size_t max_subsets = 5000000; // --max-subsets: constraint subsets for cone intersections
    // The checker's own: the bits of an entry of a declared identity's product (about 1.26
    // million decimal digits), bounded from the factors before multiplying; a product of many
    // large factors grows without a bound the prover checks.
    std::size_t max_product_bits = 4194304; // --max-product-bits
    std::size_t max_pieces = 500000;        // --max-pieces: pieces of a law with symmetries, listed and generated
    std::size_t max_memory = 640;           // --max-memory: megabytes of generated pieces, by the size of their numbers
    // Not a limit: threads for the pair forms (--jobs; default all cores). Never changes the outcome.
    std::size_t jobs = 1;
    bool progress = false; // impactcert-check: the obligation being checked, on a terminal, after a second
};

// A pair block of nonexpansive from a sharded run that lies beyond the first block failing or
// stopping in the single run's order (parts.cpp): not in the merged certificate, but every entry,
// counterexample and limit it lists is checked like the certificate's own, so that nothing a part
// says goes unexamined.
struct ExtraBlock {
    std::size_t first = 0;       // the index of its first pair, in the single run's order
    std::size_t block_pairs = 0; // pairs per block (the run's --shard-block)
    const Json* pairs = nullptr; // its entries, when the part records them
    const Json* counterexample = nullptr;
    const Json* limit = nullptr;
    std::string path;            // the part file and the block, for messages
};

class Checker {
  public:
    Checker(const Law& law, const Json& obligations, const Limits& limits, const std::vector<ExtraBlock>& extra = {})
        : law_(law), obl_(obligations), limits_(limits), extra_(extra) {}

    enum class Truth { proved, refuted, undecided };

    // Decides obligation k's truth; rejects evidence or witnesses that are wrong, and a verdict
    // that does not follow. Dependencies run one way only (fan and P1 depend on nothing else),
    // so this never recurses without bound.
    Truth holds(std::size_t k);
    // After every obligation: the blocks of a sharded run beyond its cut (ExtraBlock).
    void check_extra_blocks() {
        for (const auto& x : extra_)
            check_extra_block(x);
    }

  private:
    const Law& law_;
    const Json& obl_;
    const Limits& limits_;
    const std::vector<ExtraBlock>& extra_;
    const Json* pair_entry_ = nullptr; // check_witness: the failing pair entry, when not the certificate's last
    void check_extra_block(const ExtraBlock& x);
    std::map<std::string, Truth> decided_;
    std::vector<Vec> fan_points_;              // the fan's validated test points (when decided)
    std::vector<std::size_t> fan_cover_;       // how many open cones contain each of them
    std::optional<bool> face_to_face_;        // the fast path of the fan holds
    std::optional<bool> walls_tile_;          // the cones tile R^c (decided by walls)
    std::optional<std::optional<Json>> domain_; // the canonical domain witness, if any
    std::vector<std::size_t> q_class_, next_other_; // see number_matrices
    std::size_t distinct_pairs_ = 0;
    std::map<std::size_t, Mat> products_;       // identity index -> its product

    // The symmetries re-decided (symmetries.cpp).
    struct SymmetryCheck {
        bool hold = false;                          // declared, and every one holds
        std::size_t failing = 0;                    // the first that fails (when !hold)
        Json witness;                               // its canonical witness (when !hold)
        std::vector<Json> evidence;                 // of those before it
        std::vector<std::vector<std::size_t>> sigma;
        std::vector<std::size_t> representatives;   // least piece of each orbit (when hold)
    };
    std::optional<SymmetryCheck> sym_;
    // Per-piece products of the pair forms (pair_form), computed once.
    struct PairData {
        Mat R, QR, HR, HQR, E;
    };
    mutable std::vector<std::optional<PairData>> pair_data_;

    Truth holds(const std::string& id) {
        return holds(static_cast<std::size_t>(std::find(ids_of(law_).begin(), ids_of(law_).end(), id) - ids_of(law_).begin()));
    }
    const Piece& pc(std::size_t p) const { return law_.pieces[p]; }
    std::size_t index_of(const std::string& id) const {
        const auto& ids = ids_of(law_);
        return static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin());
    }
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

    // ---- obligations.cpp: verdicts, limits and the evidence of each obligation
    void could_be_undecided(const std::string& id, const std::string& limit, const std::string& path);
    bool evidence(const std::string& id, const Json& data, const std::string& dp);
    bool check_outcome_pieces(const Json& l, const std::string& lp, const Vec& u, const Vec& g, const Vec& declared);
    const Json& last_entry(const std::string& id, const char* key) const;
    std::size_t factor_bits(std::size_t p) const;
    const Mat& identity_product(std::size_t i);
    Mat pair_form(std::size_t i, std::size_t j) const;

    // ---- fan.cpp: the fan re-decided, and whether S is a function
    std::vector<Vec> rays_by_angle() const;
    std::vector<std::size_t> planar_cover(const std::vector<Vec>& sorted) const;
    bool fan_planar(const Json& data, const std::string& dp);
    std::size_t ray_id(const Vec& r) const { return law_.ray_index.at(r); }
    const std::map<std::vector<std::size_t>, std::vector<std::pair<std::size_t, int>>>& all_facets() const;
    mutable std::optional<std::map<std::vector<std::size_t>, std::vector<std::pair<std::size_t, int>>>> facets_;
    mutable std::optional<Vec> generic_point_;
    std::vector<Vec> facet_rays(const std::vector<std::size_t>& ids) const;
    std::vector<Vec> listed_rays(const Json& l, const std::string& path) const;
    std::vector<std::string> listed_names(const Json& l, const std::string& path) const;
    Vec generic_point() const;
    bool fan_facets(const Json& data, const std::string& dp);
    bool facet_criterion() const;
    bool walls_tile();
    // The prover's gap point beside a facet with one cone (proofs/README.md, "Check, gaps").
    struct GapPoint {
        std::vector<std::size_t> ids; // the facet's rays
        std::size_t piece;            // its one cone
        Vec point;                    // in no closed cone
    };
    std::optional<GapPoint> gap_point() const;
    bool face_to_face();
    std::vector<Vec> facet_hyperplanes() const;
    bool fan_chambers(const Json& data, const std::string& dp);
    bool s_is_a_function(const std::string& path);
    std::optional<Json> domain_witness();

    // ---- p1.cpp: P1 re-decided
    std::vector<std::pair<std::size_t, std::size_t>> across_walls() const;
    std::vector<Vec> intersection_rays(std::size_t i, std::size_t j) const;
    std::size_t subsets_per_pair() const;
    void number_matrices();
    bool next_distinct_pair(std::size_t& i, std::size_t& j) const;
    bool p1_intersections(const Json& data, const std::string& dp);
    std::vector<std::tuple<std::size_t, std::size_t, Vec>> shared_rays(std::size_t limit);
    bool first_differing_shared_ray(); // any shared ray on which two pieces differ

    // ---- symmetries.cpp: the symmetries re-decided; firsts() is one piece per orbit when they
    // hold (the reduced lists of P1, P2, energetic, nonexpansive, nonexpansive-lemma), else all
    const SymmetryCheck& symmetry_check();
    std::vector<std::size_t> firsts();
    std::vector<std::size_t> orthant_firsts(); // P3 and kinematic: firsts() when every P' keeps the orthant
    bool symmetries_evidence(const Json& data, const std::string& dp);
    void check_symmetries_witness(const Json& w, const std::string& wp);

    // ---- witnesses.cpp: counterexamples, re-validated from scratch
    void check_witness(const std::string& id, const Json& w, const std::string& wp, bool local);
    // coulomb.cpp: the first failure of Coulomb's law in the prover's order (pieces in order;
    // at each, the friction cone at the rays, then every tangent: the slip sign opposite to
    // -mu, then to +mu), recomputed by Lemma F; and a refutation checked against it.
    struct CoulombFailure {
        std::size_t piece = 0, tangent = 0;
        int kind = 0; // 0: impulse outside the friction cone at a ray; +1: xi_T > 0 with
                      // Lambda_T != -mu Lambda_N; -1: xi_T < 0 with Lambda_T != +mu Lambda_N
        Vec gamma;
    };
    std::optional<CoulombFailure> first_coulomb_failure() const;
    void check_coulomb_witness(const Json& w, const std::string& wp);
    // Friction polygons (proofs/README.md, "Polygonal friction cones", Lemma P): the forms, one
    // per (piece, contact with a polygon, vertex) in that order, and A of one of them,
    // -(B + B^T) / 2 with B(a, b) = (Lambda_T(r_a) - mu Lambda_N(r_a) v) . xi_T(r_b) (their evidence
    // is checked with the obligations, as energetic's).
    struct PolygonForm {
        std::size_t piece = 0, contact = 0, vertex = 0;
    };
    std::vector<PolygonForm> polygon_forms() const;
    Mat polygon_form(const PolygonForm& f) const;
};

// The whole document (check.cpp): 0, or throws Malformed, Rejected, Undecided or a JSON error.
// A sharded run's claim of how many pairs nonexpansive has (every part's slice.pairs, equal):
// checked against the law the certificate names (first pieces times pieces).
struct SliceClaim {
    std::size_t pairs = 0;
    std::string path;
};
int check(const Json& cert, const Limits& limits, const std::vector<ExtraBlock>& extra = {},
          const std::optional<SliceClaim>& slice = std::nullopt);

// The certificate's "worst_case" (worst_case.cpp), when present; the Lipschitz bound is there
// exactly when the law is a continuous tiling (fan and P1 hold).
void check_worst_case(const Law& law, const Json& worst_case, bool continuous_tiling, const Limits& limits);

// One line: control characters and backslashes escaped (check.cpp).
std::string one_line(const std::string& text);

} // namespace detail

// check_text (impactcert_check.hpp) with the limits of impactcert-check's options.
Outcome check_text(const std::string& text, const detail::Limits& limits);


// check.cpp: the document checks, shared by check_text and check_parts (parts.cpp).

std::size_t nesting_depth(const std::string& text);
// What the key pass refuses before anything is parsed: a repeated key, an object of more than
// 4096 keys, or a NUL byte (nlohmann's reader stops at one, so whatever follows it -- a repeated
// key, a second document -- would never be read).
struct RefusedText {
    enum class Kind { repeated, too_many, nul_byte };
    std::string path, key;
    Kind kind = Kind::repeated;
    std::string message() const {
        switch (kind) {
        case Kind::too_many: return path + ": more than 4096 keys in one object";
        case Kind::nul_byte: return path + ": a NUL character (nothing may follow the end of the document)";
        case Kind::repeated: break;
        }
        return path + ": duplicate key \"" + key + "\"";
    }
};
detail::Json parse_unique_keys(const std::string& text);

// check.cpp: runs `checks` (which returns the text after "verified (") and turns a rejection,
// a malformed or undecided document into its status and one-line message (check_text, check_parts).
Outcome outcome_of(const std::function<std::string()>& checks);

// parts.cpp: the parts of a sharded certify run, assembled (coverage checked) and checked; the
// assembled certificate in `merged` when given (the content of a single run's certificate).
bool is_part_text(const std::string& text);
Outcome check_parts(const std::vector<std::string>& texts, const std::vector<std::string>& names,
                    const detail::Limits& limits, std::string* merged = nullptr);

} // namespace impactcert_check
