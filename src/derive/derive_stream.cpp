// SPDX-License-Identifier: GPL-3.0-or-later
// derive_stream.cpp -- the sequential law streamed to its file (derive.hpp,
// derive_sequential_streamed): regions spilled by map to bucket files during the exploration,
// then merged, triangulated and written bucket by bucket.
//
// Why buckets give the in-memory law: merging only ever joins regions of one map (merge_group),
// and every region of a map lands in the same bucket (the bucket is a hash of the map's text), so
// each group is merged exactly as in memory, in key order; a piece's name, map and rays depend on
// its group alone. The declarations that look across groups are rebuilt from what was written:
// the single impacts (the piece of each one-letter word), the identities (each longer word's
// factorisation into those pieces, written after the pieces from a spill file of names and
// words) and the outcomes (OutcomeTracker, one piece at a time).
#include "derive/derive.hpp"
#include "derive/derive_regions.hpp"
#include "derive/derived_law.hpp"

#include "base/errors.hpp"
#include "base/output_file.hpp"

#include <atomic>
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <signal.h>
#include <unistd.h>

namespace impactcert {

using namespace derive_detail;

namespace {

// A directory of spill files beside the output, removed with everything in it on every way out:
// its destructor, and SIGINT, SIGTERM or SIGHUP (unless the process ignores them: nohup, a
// background job). The handler only calls unlink() and rmdir(), which are async-signal-safe, on
// the names registered (the spill files and the output's temporary file), then dies of the
// signal as it would have. Only a kill leaves the directory, its name saying what it is. One at a
// time per process.
constexpr std::size_t kMaxSpillFiles = 256;
std::atomic<const char*> g_spill_files[kMaxSpillFiles];
std::atomic<const char*> g_spill_dir{nullptr};

extern "C" void remove_spill_and_die(int sig) {
    for (auto& f : g_spill_files)
        if (const char* name = f.load())
            ::unlink(name);
    if (const char* dir = g_spill_dir.load())
        ::rmdir(dir);
    std::signal(sig, SIG_DFL);
    raise(sig);
}

class SpillDirectory {
  public:
    explicit SpillDirectory(const std::string& output) {
        const auto slash = output.rfind('/');
        const std::string dir = slash == std::string::npos ? "." : output.substr(0, slash + 1);
        const std::string base = slash == std::string::npos ? output : output.substr(slash + 1);
        // Named for the output when the name leaves room (NAME_MAX 255), else generically.
        const std::string stem = base.size() <= 200 ? "." + base + ".derive-spill-" : ".impactcert-derive-spill-";
        std::string pattern = dir + (dir.back() == '/' ? "" : "/") + stem + "XXXXXX";
        std::vector<char> buf(pattern.begin(), pattern.end());
        buf.push_back('\0');
        if (!mkdtemp(buf.data()))
            throw InputError(output + ": cannot make a spill directory beside it: " + std::strerror(errno));
        path_ = buf.data();
        files_.reserve(kMaxSpillFiles); // names stay where the handler reads them
        g_spill_dir = path_.c_str();
        for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
            struct sigaction now{}, before{};
            if (sigaction(sig, nullptr, &before) != 0 || before.sa_handler == SIG_IGN)
                continue; // ignored (nohup, a background job): it stays ignored
            now.sa_handler = remove_spill_and_die;
            sigemptyset(&now.sa_mask);
            if (sigaction(sig, &now, nullptr) == 0)
                previous_.emplace_back(sig, before);
        }
    }
    ~SpillDirectory() {
        // The handlers first, then the names they read.
        for (const auto& [sig, before] : previous_)
            sigaction(sig, &before, nullptr);
        for (auto& f : g_spill_files)
            f = nullptr;
        g_spill_dir = nullptr;
        for (const auto& f : files_)
            std::remove(f.c_str());
        ::rmdir(path_.c_str());
    }
    SpillDirectory(const SpillDirectory&) = delete;
    SpillDirectory& operator=(const SpillDirectory&) = delete;
    std::string file(const std::string& name) {
        if (watched_ == kMaxSpillFiles) // before the vector grows: the handler holds its names
            throw std::logic_error("derive --stream: more spill files than the handler holds");
        files_.push_back(path_ + "/" + name);
        watch(files_.back());
        return files_.back();
    }
    // A file outside the directory the handler also removes (the output's temporary file); the
    // destructor leaves it to its owner.
    void watch(const std::string& path) {
        if (watched_ == kMaxSpillFiles)
            throw std::logic_error("derive --stream: more spill files than the handler holds");
        outside_.reserve(kMaxSpillFiles);
        const std::string* name = &path;
        if (std::find(files_.begin(), files_.end(), path) == files_.end()) {
            outside_.push_back(path);
            name = &outside_.back();
        }
        g_spill_files[watched_++] = name->c_str();
    }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
    std::vector<std::string> files_, outside_;
    std::size_t watched_ = 0;
    std::vector<std::pair<int, struct sigaction>> previous_;
};

// One region per line: name ; word (contacts, comma-separated) ; the map's entries ; the cone's
// constraints a (a . x >= 0), each c integers, separated by '|'.
void spill_region(std::ostream& out, const Region& r, std::size_t c) {
    out << r.name << ';';
    for (std::size_t i = 0; i < r.key.size(); ++i)
        out << (i ? "," : "") << r.key[i];
    out << ';';
    for (std::size_t i = 0; i < c; ++i)
        for (std::size_t j = 0; j < c; ++j)
            out << (i + j ? " " : "") << to_string(r.M(i, j));
    out << ';';
    bool first = true;
    for (const auto& k : r.cone.minimized_constraints()) {
        const auto a = constraint_vector(k, c);
        if (!a)
            continue;
        if (k.is_equality())
            throw std::logic_error("derive --stream: a full-dimensional region with an equality");
        out << (first ? "" : "|");
        first = false;
        for (std::size_t i = 0; i < c; ++i)
            out << (i ? " " : "") << to_string((*a)[i]);
    }
    out << '\n';
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        const auto at = s.find(sep, start);
        out.push_back(s.substr(start, at == std::string::npos ? std::string::npos : at - start));
        if (at == std::string::npos)
            return out;
        start = at + 1;
    }
}

Rational spilled_number(const std::string& text) {
    const auto x = parse_rational(text);
    if (!x)
        throw std::logic_error("derive --stream: a spill file holds \"" + text + "\", not a number");
    return *x;
}

std::vector<std::size_t> spilled_word(const std::string& text) {
    std::vector<std::size_t> word;
    if (!text.empty())
        for (const auto& letter : split(text, ','))
            word.push_back(static_cast<std::size_t>(std::stoul(letter)));
    return word;
}

Region read_region(const std::string& line, std::size_t c) {
    const auto fields = split(line, ';');
    if (fields.size() != 4)
        throw std::logic_error("derive --stream: a spill line of " + std::to_string(fields.size()) + " fields");
    Region r{PPL::C_Polyhedron(c, PPL::UNIVERSE), Matrix(c, c), spilled_word(fields[1]), fields[0]};
    const auto entries = split(fields[2], ' ');
    if (entries.size() != c * c)
        throw std::logic_error("derive --stream: a spilled map of " + std::to_string(entries.size()) + " entries");
    for (std::size_t i = 0; i < c; ++i)
        for (std::size_t j = 0; j < c; ++j)
            r.M(i, j) = spilled_number(entries[i * c + j]);
    std::vector<Vector> constraints;
    if (!fields[3].empty())
        for (const auto& text : split(fields[3], '|')) {
            Vector a;
            for (const auto& x : split(text, ' '))
                a.push_back(spilled_number(x));
            constraints.push_back(std::move(a));
        }
    r.cone = cone_of(c, constraints);
    return r;
}

void check_written(std::ostream& out, const std::string& what) {
    out.flush();
    if (!out)
        throw InputError(what + ": cannot write (disk full?)");
}

} // namespace

DeriveResult derive_sequential_streamed(const DeriveOptions& options, const std::string& path, std::size_t bucket_count) {
    const Mechanics mech = make_mechanics(options);
    if (mech.has_friction())
        throw InputError("--stream: not with friction (the sequential law with friction is derived in memory)");
    const std::size_t n = mech.balls(), c = mech.contacts();
    if (c < 3 || options.polyhedral) {
        // Two contacts: sectors of the plane, a handful of pieces.
        DeriveResult r = derive_sequential(options);
        if (r.law) {
            set_expected_claims(*r.law, options.restitution);
            write_file(path, law_file_text(*r.law));
            r.pieces = r.law->pieces.size();
        }
        return r;
    }
    validate(options, c);
    if (bucket_count == 0 || bucket_count + 3 > kMaxSpillFiles)
        throw std::logic_error("derive --stream: 1 to 253 buckets");
    const PplScope ppl;
    std::vector<Matrix> Qk;
    for (std::size_t k = 0; k < c; ++k) {
        Qk.push_back(two_body_impact(mech.G, k, options.restitution[k]));
        check_bits(Qk.back(), options.max_bits, "the impact matrix of contact " + std::to_string(k + 1));
    }
    DeriveResult result;
    SpillDirectory spill(path);
    std::vector<std::string> bucket_paths;
    std::vector<std::ofstream> buckets;
    for (std::size_t b = 0; b < bucket_count; ++b) {
        bucket_paths.push_back(spill.file("bucket-" + std::to_string(b)));
        buckets.emplace_back(bucket_paths.back());
        if (!buckets.back())
            throw InputError(spill.path() + ": cannot write a spill file");
    }
    // The output first, so that one that cannot be written is said before the exploration. Whole
    // or absent: its temporary file is removed on a signal too; an output written in place (a
    // link, a device) is opened only at the end, and gets the law from a spill file in one piece.
    OutputFile out(path, true);
    std::optional<std::ofstream> staged;
    if (out.in_place())
        staged.emplace(spill.file("law"));
    else
        spill.watch(out.temporary_path());
    // 1. The words, depth first: each final region to the bucket of its map.
    RegionBudget budget(options.max_memory_mb);
    const std::hash<std::string> hash;
    const Explored explored = explore_words(options, Qk, budget, [&](Region&& region) {
        spill_region(buckets[hash(map_key(region.M)) % bucket_count], region, c);
    });
    for (auto& b : buckets) {
        check_written(b, spill.path());
        b.close();
    }
    if (explored.not_finite) {
        result.not_finite = explored.not_finite;
        result.word = explored.word;
        return result;
    }
    result.regions = explored.regions;
    result.max_word = explored.max_word;

    // 2. Bucket by bucket: the regions of each map merged in key order, triangulated, written.
    const Law head = law_header(options, n);
    std::ostream& law_text = staged ? static_cast<std::ostream&>(*staged) : out.stream();
    LawTextWriter writer(law_text, head);
    std::optional<OutcomeTracker> outcomes;
    if (options.outcomes_override.empty())
        outcomes.emplace(head, outcome_simulation(options));
    std::map<std::size_t, std::string> letter_piece;
    const std::string words_path = spill.file("words");
    std::ofstream words(words_path); // name;word of every piece of a word of two letters or more
    for (std::size_t b = 0; b < bucket_count; ++b) {
        if (options.progress)
            options.progress("stream", b, bucket_count);
        std::map<std::string, std::vector<Region>> groups;
        std::size_t held = 0;
        {
            std::ifstream in(bucket_paths[b]);
            if (!in)
                throw InputError(bucket_paths[b] + ": cannot read the spill file back (removed?)");
            for (std::string line; std::getline(in, line);) {
                Region r = read_region(line, c);
                const std::size_t bytes = RegionBudget::bytes_of(r);
                budget.add(bytes, "regions of one bucket");
                held += bytes;
                groups[map_key(r.M)].push_back(std::move(r));
            }
            if (in.bad())
                throw InputError(bucket_paths[b] + ": cannot read the spill file back");
        }
        std::remove(bucket_paths[b].c_str());
        for (auto& [key, group] : groups) {
            sort_by_key(group);
            merge_group(group, c);
            for (const Region& region : group) {
                const auto pieces = region_pieces(region, c);
                if (region.key.size() == 1 && !pieces.empty())
                    letter_piece.emplace(region.key[0], pieces.front().name);
                for (const auto& piece : pieces) {
                    writer.piece(piece);
                    if (outcomes)
                        outcomes->add(piece);
                    if (region.key.size() >= 2) {
                        words << piece.name << ';';
                        for (std::size_t i = 0; i < region.key.size(); ++i)
                            words << (i ? "," : "") << region.key[i];
                        words << '\n';
                    }
                }
            }
        }
        budget.remove(held);
    }
    check_written(words, spill.path());
    words.close();
    // 3. The identities, from the words spilled beside the pieces.
    bool identities = false;
    {
        std::ifstream in(words_path);
        if (!in)
            throw InputError(words_path + ": cannot read the spill file back (removed?)");
        for (std::string line; std::getline(in, line);) {
            const auto at = line.find(';');
            if (auto id = identity_of(line.substr(0, at), spilled_word(line.substr(at + 1)), letter_piece)) {
                writer.identity(*id);
                identities = true;
            }
        }
        if (in.bad())
            throw InputError(words_path + ": cannot read the spill file back");
    }
    Law tail = head;
    tail.single_impacts = single_impacts_of(letter_piece, options.restitution);
    tail.outcomes = outcomes ? outcomes->outcomes() : options.outcomes_override;
    // The claims derive sets (derived_law.hpp) see the identities declared (written already).
    if (identities)
        tail.identities.push_back(IdentityDecl{});
    set_expected_claims(tail, options.restitution);
    writer.finish(tail);
    if (staged) {
        check_written(*staged, spill.path());
        staged->close();
        out.open_in_place();
        std::ifstream in(spill.path() + "/law", std::ios::binary);
        if (!in)
            throw InputError(spill.path() + "/law: cannot read the spill file back (removed?)");
        out.stream() << in.rdbuf();
    }
    out.commit();
    result.pieces = writer.pieces();
    result.peak_bytes = budget.peak();
    return result;
}

} // namespace impactcert
