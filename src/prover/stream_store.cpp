// SPDX-License-Identifier: GPL-3.0-or-later
// stream_store.cpp -- the compact law as ids (stream_store.hpp), closed under its symmetries as
// Model closes it (proofs/README.md, "Symmetries", "Compact laws"; "Streamed laws").
#include "prover/stream.hpp"
#include "prover/stream_store.hpp"

#include "base/parallel.hpp"

#include <algorithm>
#include <numeric>

namespace impactcert::stream {

// ---------------------------------------------------------------------------------------------
// Store

std::uint64_t Store::hash(const u32* rays) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (std::size_t k = 0; k < c_; ++k) {
        h ^= rays[k] + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xbf58476d1ce4e5b9ull;
    }
    return h ^ (h >> 31);
}

std::optional<u32> Store::find(const u32* sorted_rays) const {
    if (slots_.empty())
        return std::nullopt;
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = hash(sorted_rays) & mask;; s = (s + 1) & mask) {
        const u32 v = slots_[s];
        if (v == 0)
            return std::nullopt;
        if (std::equal(sorted_rays, sorted_rays + c_, rays(v - 1)))
            return v - 1;
    }
}

void Store::grow() {
    std::vector<u32> bigger(slots_.empty() ? 1024 : slots_.size() * 2, 0);
    const std::size_t mask = bigger.size() - 1;
    for (std::size_t p = 0; p < n_; ++p) {
        std::size_t s = hash(rays(p)) & mask;
        while (bigger[s] != 0)
            s = (s + 1) & mask;
        bigger[s] = static_cast<u32>(p + 1);
    }
    slots_.swap(bigger);
}

u32 Store::add(const u32* sorted_rays, const u32* images, u32 parent, u32 generator, u32 root, u32 name_length) {
    if (n_ >= 0xfffffff0u)
        throw std::logic_error("stream store: more than 2^32 pieces"); // --max-pieces stops far earlier
    if (2 * (n_ + 1) > slots_.size())
        grow();
    if (n_ % kChunk == 0)
        chunks_.push_back(std::make_unique<u32[]>(kChunk * stride_));
    u32* r = chunks_.back().get() + (n_ % kChunk) * stride_;
    std::copy(sorted_rays, sorted_rays + c_, r);
    std::copy(images, images + c_, r + c_);
    r[2 * c_] = parent;
    r[2 * c_ + 1] = generator;
    r[2 * c_ + 2] = root;
    r[2 * c_ + 3] = name_length;
    const std::size_t mask = slots_.size() - 1;
    std::size_t s = hash(sorted_rays) & mask;
    while (slots_[s] != 0)
        s = (s + 1) & mask;
    slots_[s] = static_cast<u32>(n_ + 1);
    return static_cast<u32>(n_++);
}

// ---------------------------------------------------------------------------------------------
// Expansion

namespace {

std::size_t vector_bytes(const Vector& v) {
    std::size_t b = 64;
    for (const auto& x : v)
        b += 96 + 8 * (mpz_size(mpq_numref(x.mpq())) + mpz_size(mpq_denref(x.mpq())));
    return b;
}

std::size_t find_root(std::vector<u32>& uf, u32 x) {
    while (uf[x] != x)
        x = uf[x] = uf[uf[x]];
    return x;
}

} // namespace

u32 Expansion::intern_ray(const std::vector<i64>& r) {
    auto [it, added] = ray_index_.emplace(r, static_cast<u32>(rays.size()));
    if (added) {
        rays.push_back(r);
        table_bytes_ += 2 * (64 + 8 * r.size()) + 64;
    }
    return it->second;
}

u32 Expansion::intern_image(const Vector& v) {
    auto [it, added] = image_index_.emplace(v, static_cast<u32>(images.size()));
    if (added) {
        images.push_back(v);
        table_bytes_ += 2 * vector_bytes(v) + 64;
    }
    return it->second;
}

void Expansion::check_budget() {
    bytes = store.bytes() + table_bytes_;
    for (const auto& m : ray_map_)
        bytes += 8 * m.size();
    for (const auto& per_scale : image_map_)
        for (const auto& m : per_scale)
            bytes += 4 * m.size();
    const std::size_t max_bytes =
        limits_.max_memory_mb > (SIZE_MAX >> 20) ? SIZE_MAX : limits_.max_memory_mb << 20;
    if (bytes > max_bytes)
        input_error("$.symmetries", "the generated pieces need more than " + std::to_string(limits_.max_memory_mb) +
                                        " MB (" + std::to_string(store.size()) + " pieces so far; raise it with --max-memory)");
}

void Expansion::map_ray(u32 g, u32 r, u32& image, u32& scale) {
    auto& map = ray_map_[g];
    if (map.size() <= r) {
        map.resize(rays.size(), kNone);
        ray_scale_id_[g].resize(rays.size(), kNone);
    }
    if (map[r] == kNone) {
        std::vector<i64> v(c);
        if (!P_int_[g] || !intk::apply(*P_int_[g], rays[r].data(), v.data()))
            throw StreamRefused("the image of a ray under symmetry \"" + law.symmetries[g].name +
                                "\" leaves int64 (--stream keeps rays in int64)");
        i64 gcd = 0;
        for (auto x : v)
            gcd = std::gcd(gcd, x < 0 ? -x : x); // |x| <= INT64_MAX: intk::apply keeps the symmetric range
        for (auto& x : v)
            x /= gcd;
        const Rational s = Rational(static_cast<long>(gcd)) / Rational(static_cast<long>(P_int_[g]->den));
        u32 sid = 0;
        while (sid < scales_.size() && scales_[sid] != s)
            ++sid;
        if (sid == scales_.size()) {
            scales_.push_back(s);
            for (auto& per_scale : image_map_)
                per_scale.emplace_back();
        }
        const u32 id = intern_ray(v); // may grow the table: keep the maps sized
        ray_map_[g].resize(rays.size(), kNone);
        ray_scale_id_[g].resize(rays.size(), kNone);
        ray_map_[g][r] = id;
        ray_scale_id_[g][r] = sid;
    }
    image = ray_map_[g][r];
    scale = ray_scale_id_[g][r];
}

u32 Expansion::map_image(u32 g, u32 scale, u32 image, u32 from_piece) {
    auto& map = image_map_[g][scale];
    if (map.size() <= image)
        map.resize(images.size(), kNone);
    if (map[image] == kNone) {
        const Vector v = (Rational(1) / scales_[scale]) * (law.symmetries[g].P_prime * images[image]);
        const std::size_t grown = matrix_bits(Matrix::from_columns({v}));
        if (grown > max_bits_) {
            const std::string name = this->name(from_piece) + "." + law.symmetries[g].name;
            input_error("$.symmetries", "generated piece " + in_quotes(name.substr(0, 60)) + " has an entry of " +
                                            std::to_string(grown) + " bits, more than 16 times those of the "
                                            "listed data: the numbers grow (a symmetry of infinite order?)");
        }
        const u32 id = intern_image(v);
        image_map_[g][scale].resize(images.size(), kNone);
        image_map_[g][scale][image] = id;
    }
    return image_map_[g][scale][image];
}

void Expansion::map_piece(u32 p, u32 g, u32* rays_out, u32* images_out) {
    auto& pairs = scratch_;
    pairs.resize(c);
    for (std::size_t k = 0; k < c; ++k) {
        u32 r = 0, s = 0;
        map_ray(g, store.rays(p)[k], r, s);
        pairs[k] = {r, map_image(g, s, store.images(p)[k], p)};
    }
    std::sort(pairs.begin(), pairs.end());
    for (std::size_t k = 0; k < c; ++k) {
        rays_out[k] = pairs[k].first;
        images_out[k] = pairs[k].second;
    }
}

bool Expansion::map_piece_known(u32 p, u32 g, u32* rays_out, u32* images_out,
                                std::vector<std::pair<u32, u32>>& pairs) const {
    pairs.resize(c);
    const auto& rmap = ray_map_[g];
    for (std::size_t k = 0; k < c; ++k) {
        const u32 r = store.rays(p)[k];
        if (r >= rmap.size() || rmap[r] == kNone)
            return false;
        const u32 s = ray_scale_id_[g][r];
        const auto& imap = image_map_[g][s];
        const u32 i = store.images(p)[k];
        if (i >= imap.size() || imap[i] == kNone)
            return false;
        pairs[k] = {rmap[r], imap[i]};
    }
    std::sort(pairs.begin(), pairs.end());
    for (std::size_t k = 0; k < c; ++k) {
        rays_out[k] = pairs[k].first;
        images_out[k] = pairs[k].second;
    }
    return true;
}

Expansion::Expansion(const Law& law_, const Model& base_, const Limits& limits, const Progress& progress)
    : law(law_), base(base_), c(base_.contacts()), store(base_.contacts()), limits_(limits) {
    if (base.has_friction())
        input_error("$.contacts.friction", "verify --stream does not take laws with friction (verify without --stream does)");
    const auto& syms = law.symmetries;
    const auto& H = base.H();
    // As Model: a compact law's P and P' are H-isometries of finite order, checked before
    // anything is generated.
    validate_compact_symmetries(law, H);
    for (std::size_t g = 0; g < syms.size(); ++g)
        P_int_.push_back(intk::to_int(syms[g].P));
    for (const auto& sym : syms) // after every input rule on the symmetries
        if (sym.name.find('.') != std::string::npos)
            throw StreamRefused("symmetry name " + in_quotes(sym.name) +
                                " contains \".\" (--stream reads generated names as <piece>.<symmetry>...)");
    std::size_t listed_bits = 0;
    for (const auto& p : base.pieces())
        listed_bits = std::max({listed_bits, matrix_bits(p.Q), matrix_bits(p.R)});
    for (std::size_t g = 0; g < syms.size(); ++g)
        listed_bits = std::max({listed_bits, matrix_bits(syms[g].P), matrix_bits(syms[g].P_prime),
                                matrix_bits(base.symmetry_P_inv()[g])});
    max_bits_ = 16 * listed_bits + 1024;
    ray_map_.resize(syms.size());
    ray_scale_id_.resize(syms.size());
    image_map_.resize(syms.size());

    // The listed pieces, in order.
    std::vector<u32> sorted_rays(c), sorted_images(c);
    std::vector<std::pair<u32, u32>> pairs(c);
    for (std::size_t p = 0; p < base.pieces().size(); ++p) {
        const Piece& piece = base.pieces()[p];
        for (std::size_t k = 0; k < c; ++k) {
            const Vector r = piece.R.column(k);
            const auto r_int = intk::to_int_vector(r);
            if (!r_int)
                throw StreamRefused("a ray of piece " + in_quotes(piece.name) + " leaves int64 (--stream keeps rays in int64)");
            pairs[k] = {intern_ray(*r_int), intern_image(piece.Q * r)};
        }
        std::sort(pairs.begin(), pairs.end());
        for (std::size_t k = 0; k < c; ++k) {
            sorted_rays[k] = pairs[k].first;
            sorted_images[k] = pairs[k].second;
        }
        if (const auto q = store.find(sorted_rays.data()))
            throw StreamRefused("the listed pieces " + in_quotes(base.pieces()[*q].name) + " and " + in_quotes(piece.name) +
                                " have the same cone (--stream needs one piece per cone)");
        if (piece.name.size() > 0xfffffff0u)
            throw StreamRefused("a piece name longer than 2^32 characters");
        store.add(sorted_rays.data(), sorted_images.data(), static_cast<u32>(p), kListed, static_cast<u32>(p),
                  static_cast<u32>(piece.name.size()));
    }
    check_budget();
    for (u32 g = 0; g < syms.size(); ++g)
        symmetry_index_.emplace(syms[g].name, g);
    for (u32 p = 0; p < base.pieces().size(); ++p) {
        std::uint64_t h = kNameHashStart;
        for (const char ch : base.pieces()[p].name)
            h = name_hash(h, ch);
        listed_by_hash_.emplace(h, p);
    }

    // As Model: a generated name may not be a listed one. A listed name <listed>.<s1>...<sk> is
    // followed along its path while the pieces are generated; the step that would generate it
    // is the error, at the moment Model reports it.
    struct Taken {
        std::size_t listed;       // the listed piece whose name it is
        std::vector<u32> path;    // its symmetries
    };
    std::vector<Taken> taken;
    std::map<u32, std::vector<std::pair<std::size_t, std::size_t>>> following; // piece -> (taken, step)
    for (std::size_t t = 0; t < base.pieces().size(); ++t)
        for (auto& [prefix, path] : paths(base.pieces()[t].name)) {
            following[prefix].emplace_back(taken.size(), 0);
            taken.push_back(Taken{t, std::move(path)});
        }

    // Breadth first: each piece in order, each symmetry in order. With several jobs, a block of
    // pieces (all stored already) is first mapped and looked up on threads, read-only: a
    // (piece, symmetry) whose rays or images are not mapped yet is left to the ordered pass,
    // and one not found is looked up again there (an earlier step of the block may have added
    // it). The ordered pass below then adds exactly what one thread would, in the same order.
    std::vector<u32> uf(base.pieces().size());
    std::iota(uf.begin(), uf.end(), 0u);
    const std::size_t G = syms.size(), jobs = std::max<std::size_t>(1, limits.jobs);
    // The block's records take at most 1/64 of --max-memory (and blocks hold 64 to 4,096 pieces):
    // outside the count, so that the errors and their order stay one thread's.
    const std::size_t record_bytes = std::max<std::size_t>(1, G * (2 * c + 1) * 4);
    const std::size_t budget = limits.max_memory_mb > (SIZE_MAX >> 26) ? SIZE_MAX : (limits.max_memory_mb << 20) / 64;
    const std::size_t kBlock = std::clamp<std::size_t>(budget / record_bytes, 64, 4096);
    constexpr u32 kUnknown = 0xfffffffeu; // not mapped on a thread
    std::vector<u32> pre;                 // per (piece, symmetry) of the block: found, then rays, images
    std::size_t block_begin = 0, block_end = 0;
    const std::size_t record = 2 * c + 1;
    auto prepare = [&](std::size_t begin) {
        block_begin = begin;
        block_end = std::min(store.size(), begin + kBlock);
        const std::size_t count = block_end - block_begin;
        pre.assign(count * G * record, kUnknown);
        const std::size_t shares = std::min(jobs, count);
        run_shares(shares, [&](std::size_t t) {
            std::vector<std::pair<u32, u32>> scratch;
            for (std::size_t i = count * t / shares; i < count * (t + 1) / shares; ++i)
                for (u32 g = 0; g < G; ++g) {
                    u32* slot = pre.data() + (i * G + g) * record;
                    slot[0] = kUnknown;
                    if (!map_piece_known(static_cast<u32>(block_begin + i), g, slot + 1, slot + 1 + c, scratch))
                        continue;
                    const auto q = store.find(slot + 1);
                    slot[0] = q ? *q : kNone;
                }
        });
    };
    for (std::size_t p = 0; p < store.size(); ++p) {
        if (progress && p % 65536 == 0)
            progress("expansion", std::to_string(p) + "/" + std::to_string(store.size()) + " pieces");
        if (jobs > 1 && p >= block_end)
            prepare(p);
        while (!following.empty() && following.begin()->first < p)
            following.erase(following.begin()); // pieces before p: nothing more is generated from them
        for (u32 g = 0; g < syms.size(); ++g) {
            const u32* slot = jobs > 1 ? pre.data() + ((p - block_begin) * G + g) * record : nullptr;
            std::optional<u32> found;
            if (slot && slot[0] != kUnknown) {
                std::copy(slot + 1, slot + 1 + c, sorted_rays.begin());
                std::copy(slot + 1 + c, slot + 1 + 2 * c, sorted_images.begin());
                found = slot[0] != kNone ? std::optional<u32>(slot[0]) : store.find(sorted_rays.data());
            } else {
                map_piece(static_cast<u32>(p), g, sorted_rays.data(), sorted_images.data());
                found = store.find(sorted_rays.data());
            }
            if (const auto q = found) {
                ++symmetry_checks;
                if (!failure && !std::equal(sorted_images.begin(), sorted_images.end(), store.images(*q))) {
                    // The ray of p whose image ray carries a different image.
                    for (u32 k = 0; k < c; ++k) {
                        u32 r = 0, s = 0;
                        map_ray(g, store.rays(p)[k], r, s);
                        const u32 pos = static_cast<u32>(std::find(sorted_rays.begin(), sorted_rays.end(), r) - sorted_rays.begin());
                        if (store.images(*q)[pos] != sorted_images[pos]) {
                            failure = SymmetryFailure{static_cast<u32>(p), *q, g, k};
                            break;
                        }
                    }
                }
                const std::size_t a = find_root(uf, store.root(p)), b = find_root(uf, store.root(*q));
                uf[std::max(a, b)] = static_cast<u32>(std::min(a, b));
                continue;
            }
            if (store.size() >= limits.max_pieces)
                input_error("$.symmetries", "the symmetries generate more than " + std::to_string(limits.max_pieces) +
                                                " pieces (raise it with --max-pieces)");
            const std::size_t length = std::size_t{store.name_length(p)} + 1 + syms[g].name.size();
            if (length > kMaxGeneratedName)
                input_error("$.symmetries", "generated piece name longer than " + std::to_string(kMaxGeneratedName) +
                                                " characters (a symmetry of infinite order?)");
            if (!following.empty())
                if (const auto f = following.find(static_cast<u32>(p)); f != following.end())
                    for (const auto& [t, step] : f->second)
                        if (taken[t].path[step] == g) {
                            if (step + 1 == taken[t].path.size())
                                input_error(idx("$.symmetries", g) + ".name",
                                            "generated piece name " + in_quotes(base.pieces()[taken[t].listed].name) + " is taken");
                            following[static_cast<u32>(store.size())].emplace_back(t, step + 1);
                        }
            store.add(sorted_rays.data(), sorted_images.data(), static_cast<u32>(p), g, store.root(p),
                      static_cast<u32>(length));
            if (store.size() % 4096 == 0)
                check_budget();
        }
    }
    check_budget();
    for (u32 p = 0; p < base.pieces().size(); ++p)
        if (find_root(uf, p) == p)
            representatives.push_back(p);
}

std::string Expansion::name(u32 p) const {
    std::vector<u32> path;
    while (store.generator(p) != kListed) {
        path.push_back(store.generator(p));
        p = store.parent(p);
    }
    std::string out = base.pieces()[p].name;
    for (auto it = path.rbegin(); it != path.rend(); ++it)
        out += "." + law.symmetries[*it].name;
    return out;
}

std::optional<u32> Expansion::listed_named(const std::string& name, std::size_t length, std::uint64_t hash) const {
    const auto [first, last] = listed_by_hash_.equal_range(hash);
    for (auto it = first; it != last; ++it) {
        const std::string& listed = base.pieces()[it->second].name;
        if (listed.size() == length && name.compare(0, length, listed) == 0)
            return it->second;
    }
    return std::nullopt;
}

std::vector<std::pair<u32, std::vector<u32>>> Expansion::paths(const std::string& name) const {
    std::vector<std::pair<u32, std::vector<u32>>> out;
    if (name.size() > kMaxGeneratedName)
        return out; // longer than any generated name
    // The dots after which every segment is a symmetry name: a suffix of the dots.
    std::vector<std::size_t> dots;
    for (std::size_t at = name.size(); at > 0;) {
        const std::size_t dot = name.rfind('.', at - 1);
        if (dot == std::string::npos || !symmetry_index_.count(name.substr(dot + 1, at - dot - 1)))
            break;
        dots.push_back(dot);
        at = dot;
    }
    if (dots.empty())
        return out;
    std::uint64_t h = kNameHashStart;
    std::size_t next = dots.size(); // dots[next - 1] is the leftmost dot not yet reached
    for (std::size_t i = 0; i < name.size() && next > 0; ++i) {
        if (i == dots[next - 1]) {
            --next;
            if (const auto p = listed_named(name, i, h)) {
                std::vector<u32> path;
                for (std::size_t k = next + 1; k-- > 0;) {
                    const std::size_t from = dots[k] + 1, to = k == 0 ? name.size() : dots[k - 1];
                    path.push_back(symmetry_index_.at(name.substr(from, to - from)));
                }
                out.emplace_back(*p, std::move(path));
            }
        }
        h = name_hash(h, name[i]);
    }
    return out;
}

// The piece named `name`: a listed name, or <listed name>.<symmetry>.<symmetry>... along a path
// whose every step generated its piece (symmetry names have no ".").
std::optional<u32> Expansion::walk(const std::string& name, bool generated_only) {
    if (!generated_only) {
        std::uint64_t h = kNameHashStart;
        for (const char ch : name)
            h = name_hash(h, ch);
        if (const auto p = listed_named(name, name.size(), h))
            return p;
    }
    std::vector<u32> r(c), im(c);
    for (const auto& [listed, path] : paths(name)) {
        u32 q = listed;
        bool ok = true;
        for (const u32 g : path) {
            map_piece(q, g, r.data(), im.data());
            const auto child = store.find(r.data());
            ok = child && store.generator(*child) == g && store.parent(*child) == q;
            if (!ok)
                break;
            q = *child;
        }
        if (ok)
            return q;
    }
    return std::nullopt;
}

Matrix Expansion::R(u32 p) const {
    std::vector<Vector> cols;
    for (std::size_t k = 0; k < c; ++k)
        cols.push_back(ray(store.rays(p)[k]));
    return Matrix::from_columns(cols);
}

Matrix Expansion::image_columns(u32 p) const {
    std::vector<Vector> cols;
    for (std::size_t k = 0; k < c; ++k)
        cols.push_back(images[store.images(p)[k]]);
    return Matrix::from_columns(cols);
}

Matrix Expansion::Q(u32 p) const {
    const auto R_inv = inverse(R(p));
    if (!R_inv)
        throw std::logic_error("stream: a stored cone is not full-dimensional");
    return image_columns(p) * *R_inv;
}

PieceDecl Expansion::decl(u32 p) const {
    std::vector<Vector> rs;
    for (std::size_t k = 0; k < c; ++k)
        rs.push_back(ray(store.rays(p)[k]));
    return PieceDecl{name(p), Q(p), rs};
}

} // namespace impactcert::stream
