// SPDX-License-Identifier: GPL-3.0-or-later
// impactcert-check's command line: the limits as options, one certificate file, one line out
// (stdout when verified, stderr otherwise), the status of check_text as the exit status.
#include "checker.hpp"

#include <algorithm>
#include <exception>
#include <new>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using impactcert_check::detail::Limits;
using impactcert_check::detail::one_line;

// The stream to its end into `text`. Not `text << in.rdbuf()`: a string buffer that cannot grow
// ends that copy early without an error, and a shortened certificate would be reported as
// malformed JSON. Here a failed allocation is std::bad_alloc, a failed read is false.
bool read_all(std::ifstream& in, std::string& text) {
    std::vector<char> buffer(1 << 16);
    for (;;) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
        if (!in)
            return !in.bad() && in.eof();
    }
}

const char* const kUsage =
    "usage: impactcert-check [--jobs J] [--max-faces N] [--max-chambers N] [--max-subsets N]\n"
    "                        [--max-pieces N] [--max-memory MB] [--max-product-bits N] CERTIFICATE.json\n"
    "       impactcert-check [options] [--merged FILE] PART.json... (the parts of certify --shard K/N:\n"
    "                        every shard once, merged in order, coverage checked, then checked as one certificate)\n"
    "exit 0 verified, 1 rejected, 2 malformed (or not checked: usage, unreadable, out of memory),\n"
    "3 undecided (a limit would be exceeded; the message names the option that raises it)\n"
    "limits (defaults as the prover's): --max-faces 16384 (KKT faces of one copositivity check),\n"
    "--max-chambers 200000 (steps of the chamber enumeration), --max-subsets 5000000 (constraint\n"
    "subsets for intersections of cones), --max-pieces 500000 (pieces of a compact law, generated included),\n"
    "--max-memory 640 (megabytes of a compact law's generated pieces, by the size of their numbers);\n"
    "the checker's own: --max-product-bits 4194304 (bits of\n"
    "an entry of a declared identity's product); --jobs J threads for the pair forms (default: all\n"
    "cores; the outcome does not depend on it)\n"
    "--help and --version alone print and exit 0; given with a certificate, nothing is checked (exit 2)\n"
    "examples:\n"
    "  impactcert-check proofs/newton3/certificate.json\n"
    "  impactcert-check --merged cert.json part-1.json part-2.json part-3.json\n";

int usage_error(const std::string& why) {
    std::cerr << "impactcert-check: " << one_line(why) << " (see --help)\n";
    return impactcert_check::kMalformed;
}

} // namespace

int main(int argc, char** argv) {
    Limits limits;
    limits.jobs = std::max(1u, std::thread::hardware_concurrency());
    limits.progress = true;
    std::vector<std::string> files;
    std::string merged_path;
    bool options_done = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (!options_done && (arg == "--help" || arg == "-h" || arg == "--version")) {
            // Alone, the conventions of every program: print, exit 0. With anything else on the
            // line, usage is not a verification: a gate given `--help CERT` must not pass (exit 2).
            if (arg == "--version")
                std::cout << "impactcert-check " << IMPACTCERT_CHECK_VERSION << "\n";
            else
                std::cout << kUsage;
            if (argc == 2)
                return 0;
            std::cerr << "impactcert-check: " << arg << " with other arguments: nothing was checked\n";
            return impactcert_check::kMalformed;
        }
        if (!options_done && arg == "--") {
            options_done = true;
            continue;
        }
        if (!options_done && arg.size() > 1 && arg[0] == '-') {
            std::string name = arg, value;
            if (const auto eq = arg.find('='); eq != std::string::npos) {
                name = arg.substr(0, eq);
                value = arg.substr(eq + 1);
            } else if (i + 1 < argc) {
                value = argv[++i];
            } else {
                return usage_error("option " + arg + " needs a value");
            }
            if (name == "--merged") {
                if (value.empty())
                    return usage_error("--merged needs a file name");
                merged_path = value;
                continue;
            }
            std::size_t* target = name == "--max-faces"          ? &limits.max_faces
                                  : name == "--max-chambers"     ? &limits.max_chambers
                                  : name == "--max-subsets"      ? &limits.max_subsets
                                  : name == "--max-product-bits" ? &limits.max_product_bits
                                  : name == "--max-pieces"       ? &limits.max_pieces
                                  : name == "--max-memory"       ? &limits.max_memory
                                  : name == "--jobs"             ? &limits.jobs
                                                                 : nullptr;
            if (target == nullptr)
                return usage_error("unknown option " + name);
            const bool digits = !value.empty() && value.size() <= 19 &&
                                std::all_of(value.begin(), value.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
            if (!digits)
                return usage_error(name + " needs a non-negative integer, got \"" + value + "\"");
            *target = static_cast<std::size_t>(std::stoull(value));
            if (name == "--jobs" && (limits.jobs < 1 || limits.jobs > 256))
                return usage_error("--jobs needs a number of threads in 1..256, got \"" + value + "\"");
            continue;
        }
        files.push_back(arg);
    }
    if (files.empty())
        return usage_error("no certificate given");
    std::string label;
    for (const auto& f : files)
        label += (label.empty() ? "" : " ") + one_line(f);
    try {
        std::vector<std::string> texts;
        for (const auto& file : files) {
            std::ifstream in(file, std::ios::binary);
            std::string text;
            if (in && !read_all(in, text)) {
                std::cerr << "impactcert-check: " << one_line(file) << ": cannot read file: read error\n";
                return impactcert_check::kMalformed;
            }
            if (!in && !in.eof()) {
                std::cerr << "impactcert-check: " << one_line(file) << ": cannot read file\n";
                return impactcert_check::kMalformed;
            }
            texts.push_back(std::move(text));
        }
        const bool parts = files.size() > 1 || impactcert_check::is_part_text(texts[0]);
        if (!parts && !merged_path.empty())
            return usage_error("--merged applies to the parts of a sharded run");
        std::string merged;
        const auto outcome = parts ? impactcert_check::check_parts(texts, files, limits, merged_path.empty() ? nullptr : &merged)
                                   : impactcert_check::check_text(texts[0], limits);
        if (parts && !merged_path.empty() && outcome.status == impactcert_check::kVerified) {
            std::ofstream out(merged_path, std::ios::binary);
            out << merged;
            out.close();
            if (!out) {
                std::cerr << "impactcert-check: " << one_line(merged_path) << ": cannot write\n";
                return impactcert_check::kMalformed;
            }
        }
        (outcome.status == impactcert_check::kVerified ? std::cout : std::cerr)
            << "impactcert-check: " << label << ": " << outcome.message << "\n";
        // A verdict that cannot be written is not given (a full disk must not read as "verified").
        std::cout.flush();
        if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
            std::cerr << "impactcert-check: standard output: cannot write\n";
            return impactcert_check::kMalformed;
        }
        return outcome.status;
    } catch (const std::bad_alloc&) {
        std::cerr << "impactcert-check: " << label << ": error: out of memory while reading (status 2: not checked)\n";
        return impactcert_check::kMalformed;
    } catch (const std::exception& e) {
        std::cerr << "impactcert-check: " << label << ": error: " << one_line(e.what()) << "\n";
        return impactcert_check::kMalformed;
    }
}
