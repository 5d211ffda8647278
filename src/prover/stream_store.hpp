// SPDX-License-Identifier: GPL-3.0-or-later
// stream_store.hpp -- internal to stream*.cpp: a compact law expanded into ids (stream.hpp).
//
// Contract: Expansion(law, base, limits) closes the listed pieces of `law` (validated as `base`,
// a Model of the listed pieces alone) under the symmetries exactly as Model does: for each
// piece in order and each symmetry in order, the cone P C is added unless a piece has those
// primitive rays, with the same names and input errors. A piece is stored as the ids of its c
// primitive rays (ascending) and, for each, the id of its image Q r; a generated piece's images
// are (P' Q r) / s where P r = s r', r' primitive (so Q' = P' Q P^-1 on the rays of P C).
// While closing, every (piece, symmetry) whose image cone exists already is checked for
// Q_sigma(i) P r = P' Q_i r on each ray (condition (iii) of "Symmetries"); the first failure is
// kept. Orbits come from union-find over the listed pieces (a generated piece is in the orbit of
// the listed piece its path starts from). With limits.jobs > 1 the images of a block of pieces
// are mapped and looked up on threads first (read-only), then added in the same order as on one
// thread: the same pieces, ids, names, checks and errors whatever the number of threads. The
// block's records (64 to 4,096 pieces, at most 1/64 of --max-memory where 64 pieces fit) are
// not counted against --max-memory, so that the limit stops one thread's run at the same step.
#pragma once

#include "exact/int_kernel.hpp"
#include "model/law.hpp"
#include "base/limits.hpp"
#include "prover/obligations.hpp"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace impactcert::stream {

using u32 = std::uint32_t;
using intk::i64;
inline constexpr u32 kListed = 0xffffffffu;
inline constexpr u32 kNone = 0xffffffffu;

// Pieces as ids, in chunks (no reallocation of the whole), with an open-addressing index by
// their sorted ray ids.
class Store {
  public:
    explicit Store(std::size_t c) : c_(c), stride_(2 * c + 4) {}
    std::size_t size() const { return n_; }
    const u32* rays(std::size_t p) const { return record(p); }            // ascending ids
    const u32* images(std::size_t p) const { return record(p) + c_; }     // image id per ray
    u32 parent(std::size_t p) const { return record(p)[2 * c_]; }         // itself when listed
    u32 generator(std::size_t p) const { return record(p)[2 * c_ + 1]; }  // kListed when listed
    u32 root(std::size_t p) const { return record(p)[2 * c_ + 2]; }       // the listed piece its path starts from
    u32 name_length(std::size_t p) const { return record(p)[2 * c_ + 3]; }
    std::optional<u32> find(const u32* sorted_rays) const;
    u32 add(const u32* sorted_rays, const u32* images, u32 parent, u32 generator, u32 root, u32 name_length);
    std::size_t bytes() const { return chunks_.size() * (kChunk * stride_ * 4) + slots_.size() * 4; }

  private:
    static constexpr std::size_t kChunk = 1u << 15;
    std::size_t c_, stride_, n_ = 0;
    std::vector<std::unique_ptr<u32[]>> chunks_;
    std::vector<u32> slots_; // piece + 1; 0 empty
    const u32* record(std::size_t p) const { return chunks_[p / kChunk].get() + (p % kChunk) * stride_; }
    std::uint64_t hash(const u32* rays) const;
    void grow();
};

struct SymmetryFailure { // Q_q P r != P' Q_p r for r = ray `position` of piece p
    u32 piece, image_piece, symmetry, position;
};

class Expansion {
  public:
    Expansion(const Law& law, const Model& base, const Limits& limits, const Progress& progress);

    const Law& law;
    const Model& base; // mechanics and the listed pieces
    std::size_t c;
    Store store;
    std::vector<std::vector<i64>> rays; // distinct primitive rays
    std::vector<Vector> images;         // distinct images of rays
    std::optional<SymmetryFailure> failure;
    std::size_t symmetry_checks = 0;       // (piece, symmetry) pairs checked
    std::vector<u32> representatives;      // the least piece of each orbit, ascending
    std::size_t bytes = 0;                 // counted against --max-memory

    Vector ray(u32 id) const { return intk::to_vector(rays[id]); }
    std::string name(u32 p) const;
    Matrix R(u32 p) const;                 // columns: the primitive rays
    Matrix image_columns(u32 p) const;     // columns: their images, Q R
    Matrix Q(u32 p) const;                 // Q R R^-1
    PieceDecl decl(u32 p) const;           // name, Q and rays, as a law file would list it
    std::optional<u32> resolve(const std::string& name) { return walk(name, false); } // a piece by its name

  private:
    const Limits& limits_;
    std::vector<std::optional<intk::IntMatrix>> P_int_;
    std::map<std::vector<i64>, u32> ray_index_;
    std::map<Vector, u32> image_index_;
    std::vector<std::vector<u32>> ray_map_, ray_scale_id_; // per symmetry, by ray id
    std::vector<Rational> scales_;
    std::vector<std::vector<std::vector<u32>>> image_map_;  // per symmetry and scale, by image id
    std::size_t max_bits_ = 0, table_bytes_ = 0;
    std::vector<std::pair<u32, u32>> scratch_; // map_piece's (ray, image) pairs

    u32 intern_ray(const std::vector<i64>& r);
    u32 intern_image(const Vector& v);
    void map_ray(u32 g, u32 r, u32& image, u32& scale);
    u32 map_image(u32 g, u32 scale, u32 image, u32 from_piece);
    void map_piece(u32 p, u32 g, u32* rays_out, u32* images_out); // sorted by ray id
    // The same from the maps as they are, without growing them (for threads): false where a ray
    // or an image has not been mapped under g yet. `pairs` is the caller's scratch.
    bool map_piece_known(u32 p, u32 g, u32* rays_out, u32* images_out, std::vector<std::pair<u32, u32>>& pairs) const;
    std::optional<u32> walk(const std::string& name, bool generated_only);
    std::map<std::string, u32> symmetry_index_;
    std::unordered_multimap<std::uint64_t, u32> listed_by_hash_; // listed names by name_hash
    static std::uint64_t name_hash(std::uint64_t h, char ch) { return (h ^ static_cast<unsigned char>(ch)) * 0x100000001b3ull; }
    static constexpr std::uint64_t kNameHashStart = 0xcbf29ce484222325ull;
    std::optional<u32> listed_named(const std::string& name, std::size_t length, std::uint64_t hash) const;
    // The readings of `name` as <listed name>.<s1>...<sk>, k >= 1: the listed piece and the
    // symmetries, one per "." whose prefix is a listed name and whose rest is symmetry names.
    // Linear in the name's length (a hash of each prefix, compared exactly only on a match).
    std::vector<std::pair<u32, std::vector<u32>>> paths(const std::string& name) const;
    void check_budget();
};

} // namespace impactcert::stream
