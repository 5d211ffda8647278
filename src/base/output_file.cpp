// SPDX-License-Identifier: GPL-3.0-or-later
#include "base/output_file.hpp"

#include "base/errors.hpp"
#include "model/law_json.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>

namespace impactcert {

OutputFile::OutputFile(std::string path) : OutputFile(std::move(path), false) {}

OutputFile::OutputFile(std::string path, bool defer_in_place) : path_(std::move(path)) {
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
    if (temporary_.empty() && defer_in_place) {
        // Could it be opened? Without opening it (a FIFO's reader would see an end of file),
        // truncating it, or creating it: a regular file opened and closed, anything else asked
        // (access), and a name that leads nowhere yet (absent, a dangling link) by its directory.
        errno = 0;
        bool can = false;
        struct stat target {};
        if (::stat(path_.c_str(), &target) == 0) {
            if (S_ISREG(target.st_mode)) {
                const int fd = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
                can = fd >= 0;
                if (fd >= 0)
                    ::close(fd);
            } else {
                can = !S_ISDIR(target.st_mode) && ::access(path_.c_str(), W_OK) == 0;
            }
        } else {
            const auto slash = path_.rfind('/');
            const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path_.substr(0, slash);
            can = ::access(dir.c_str(), W_OK | X_OK) == 0;
        }
        if (!can)
            throw InputError(path_ + ": cannot write" + (errno ? std::string(": ") + std::strerror(errno) : ""));
        deferred_ = true;
        return;
    }
    if (temporary_.empty()) {
        errno = 0;
        out_.open(path_, std::ios::binary | std::ios::trunc);
    }
    if (!out_)
        throw InputError(path_ + ": cannot write" + (errno ? std::string(": ") + std::strerror(errno) : ""));
}

void OutputFile::open_in_place() {
    if (!deferred_)
        return;
    errno = 0;
    out_.open(path_, std::ios::binary | std::ios::trunc);
    if (!out_)
        throw InputError(path_ + ": cannot write" + (errno ? std::string(": ") + std::strerror(errno) : ""));
    deferred_ = false;
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

} // namespace impactcert
