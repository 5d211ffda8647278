// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/common.hpp"

#include <algorithm>

#include <sstream>

#include "model/law_json.hpp"
#include "model/paper_law.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <random>

namespace impactcert::cli {

namespace {
std::string& name_storage() {
    static std::string name = "impactcert";
    return name;
}
} // namespace

void set_program_name(const std::string& name) { name_storage() = name; }

namespace {
std::string& argv0_storage() {
    static std::string argv0;
    return argv0;
}
} // namespace

void set_invocation(const char* argv0) { argv0_storage() = argv0 ? argv0 : ""; }

namespace {
// A word the shell reads as itself stays bare; anything else is quoted.
std::string shell_word(const std::string& s) {
    const bool plain = !s.empty() && s.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                         "0123456789_./,:=+-") == std::string::npos;
    if (plain)
        return s;
    std::string q = "'";
    for (char ch : s)
        q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return q + "'";
}
} // namespace

std::string replay_command(const std::string& subcommand) {
    std::string program = argv0_storage();
    if (program.empty())
        program = program_name();
    std::string prefix;
    std::vector<char> buf(4096);
    // A working directory too long for the buffer (or removed) leaves the replay relative.
    if (::getcwd(buf.data(), buf.size()) != nullptr)
        prefix = "cd " + shell_word(buf.data()) + " && ";
    return prefix + shell_word(program) + " " + subcommand;
}
const std::string& program_name() { return name_storage(); }

Model load_model(const std::string& law_path, const Limits& limits) {
    if (limits.claims.empty())
        return load_model(law_path, limits.max_pieces, limits.max_memory_mb);
    Law law = law_path.empty() ? paper_law() : load_law_declaration(law_path);
    if (limits.claims.back() == ',' || limits.claims.front() == ',')
        throw InputError("--claims: \"" + limits.claims + "\": an empty obligation id (ids separated by commas, or all)");
    if (limits.claims == "all") {
        law.claims.reset(); // every obligation that applies
    } else {
        std::vector<std::string> ids;
        std::string item;
        std::stringstream in(limits.claims);
        while (std::getline(in, item, ',')) {
            if (!is_obligation_id(item) || (item == "coulomb" && law.friction.empty())) {
                std::string names;
                for (const char* id : obligation_ids(!law.friction.empty()))
                    names += std::string(names.empty() ? "" : ", ") + id;
                throw InputError("--claims: \"" + item + "\" is not an obligation of this law (" + names + ", or all)");
            }
            if (!law_applies(law, item))
                throw InputError("--claims: " + item + " does not apply to this law (" +
                                 (item == "P3" ? std::string("not with friction") : "the law declares nothing for it") + ")");
            if (std::find(ids.begin(), ids.end(), item) != ids.end())
                throw InputError("--claims: " + item + " given twice");
            ids.push_back(item);
        }
        if (ids.empty())
            throw InputError("--claims: no obligation given (ids separated by commas, or all)");
        law.claims = ids;
    }
    try {
        return Model(std::move(law), limits.max_pieces, limits.max_memory_mb);
    } catch (const InputError& e) {
        throw InputError((law_path.empty() ? std::string("the paper's law") : law_path) + ": " + e.what());
    }
}

Model load_model(const std::string& law_path, std::size_t max_pieces, std::size_t max_memory_mb) {
    return law_path.empty() ? Model(paper_law(), max_pieces, max_memory_mb)
                            : load_model_file(law_path, max_pieces, max_memory_mb);
}

TerminalProgress::TerminalProgress() : enabled_(isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}

TerminalProgress::~TerminalProgress() {
    if (shown_)
        std::fprintf(stderr, "\r\033[K");
}

Progress TerminalProgress::callback() {
    if (!enabled_)
        return {};
    return [this](const std::string& id, const std::string& status) {
        const auto now = std::chrono::steady_clock::now();
        if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(200))
            return;
        last_ = now;
        shown_ = true;
        std::fprintf(stderr, "\r\033[K%s: %s %s", program_name().c_str(), id.c_str(), status.c_str());
        std::fflush(stderr);
    };
}

void write_stdout(const std::string& text) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::cout.flush(); // synchronised with stdio: its writes went to stdout's buffer
    if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout)
        throw InputError(std::string("standard output: cannot write: ") + std::strerror(errno));
}

} // namespace impactcert::cli
