// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/common.hpp"

#include "law_json.hpp"
#include "paper_law.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

namespace impactcert::cli {

std::string one_line_text(const std::string& text) {
    static const char* hex = "0123456789abcdef";
    auto escape = [&](std::string& out, unsigned code) {
        out += "\\u";
        for (int shift = 12; shift >= 0; shift -= 4)
            out += hex[(code >> shift) & 15];
    };
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const unsigned char ch = static_cast<unsigned char>(text[i]);
        const unsigned char next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
        const unsigned char third = i + 2 < text.size() ? static_cast<unsigned char>(text[i + 2]) : 0;
        if (ch == '\\')
            out += "\\\\";
        else if (ch == '\n')
            out += "\\n";
        else if (ch == '\r')
            out += "\\r";
        else if (ch == '\t')
            out += "\\t";
        else if (ch < 0x20 || ch == 0x7f)
            escape(out, ch);
        else if (ch == 0xc2 && next >= 0x80 && next <= 0x9f) { // U+0080..U+009F
            escape(out, next);
            ++i;
        } else if (ch == 0xe2 && next == 0x80 && (third == 0xa8 || third == 0xa9)) { // U+2028, U+2029
            escape(out, 0x2000u + third - 0x80u);
            i += 2;
        } else {
            out += static_cast<char>(ch);
        }
    }
    return out;
}

namespace {
std::string& name_storage() {
    static std::string name = "impactcert";
    return name;
}
} // namespace

void set_program_name(const std::string& name) { name_storage() = name; }
const std::string& program_name() { return name_storage(); }

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

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
    // Through a temporary file only where the rename leaves the file as writing it in place
    // would: a new file, or a regular file of ours (one link, our user, writable by us), whose
    // mode the temporary file takes. Anything else -- a symbolic link (a rename would replace the
    // link), a device such as /dev/stdout or /dev/full, a pipe, a file of another user, a read-only
    // file, a file with hard links -- is written in place, as before.
    struct stat st {};
    const bool exists = ::lstat(path_.c_str(), &st) == 0;
    const bool ours = exists && S_ISREG(st.st_mode) && st.st_nlink == 1 && st.st_uid == ::geteuid() &&
                      ::access(path_.c_str(), W_OK) == 0;
    if (!exists || ours) {
        // The temporary file's name is unpredictable and the file is created here, new
        // (O_EXCL, O_NOFOLLOW): a link planted at a name we might use is never followed. It is
        // then opened through /proc/self/fd, the file just created and no other.
        std::random_device random;
        int fd = -1;
        for (int attempt = 0; attempt < 64 && fd < 0; ++attempt) {
            char suffix[32];
            std::snprintf(suffix, sizeof suffix, ".partial-%08x%08x", random(), random());
            temporary_ = path_ + suffix;
            fd = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
            if (fd < 0 && errno != EEXIST)
                break;
        }
        if (fd >= 0) {
            out_.open("/proc/self/fd/" + std::to_string(fd), std::ios::binary | std::ios::trunc);
            ::close(fd);
        }
        if (fd < 0) {
            // A directory we may not write in (or a name too long for the suffix): in place. The
            // name tried is not ours: nothing is removed.
            temporary_.clear();
        } else if (!out_ || (ours && ::chmod(temporary_.c_str(), st.st_mode & 07777) != 0)) {
            out_.close();
            std::remove(temporary_.c_str());
            temporary_.clear();
        }
    }
    if (temporary_.empty()) {
        errno = 0;
        out_.open(path_, std::ios::binary | std::ios::trunc);
    }
    if (!out_)
        throw InputError(path_ + ": cannot write" + (errno ? std::string(": ") + std::strerror(errno) : ""));
}

OutputFile::~OutputFile() {
    if (!committed_ && !temporary_.empty()) {
        out_.close();
        std::remove(temporary_.c_str());
    }
}

void OutputFile::commit() {
    out_.close();
    if (!out_)
        throw InputError(path_ + ": cannot write");
    if (!temporary_.empty() && std::rename(temporary_.c_str(), path_.c_str()) != 0) {
        // A destination that cannot be renamed over (a bind mount, another file system under the
        // same name): the complete text is copied into it in place.
        const std::string text = read_file_text(temporary_);
        std::remove(temporary_.c_str());
        std::ofstream out(path_, std::ios::binary | std::ios::trunc);
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
        out.close();
        if (!out)
            throw InputError(path_ + ": cannot write");
    }
    committed_ = true;
}

void write_file(const std::string& path, const std::string& text) {
    OutputFile out(path);
    out.stream() << text;
    out.commit();
}

void write_stdout(const std::string& text) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::cout.flush(); // synchronised with stdio: its writes went to stdout's buffer
    if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout)
        throw InputError(std::string("standard output: cannot write: ") + std::strerror(errno));
}

} // namespace impactcert::cli
