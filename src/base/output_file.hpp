// SPDX-License-Identifier: GPL-3.0-or-later
// output_file.hpp -- every file a run writes is whole or absent (the command line, sweep's
// outputs and parts).
#pragma once

#include <fstream>
#include <string>

namespace impactcert {

// An output file written completely or not at all. A new file, or a regular file of ours (one
// link, our user, writable), is written to a temporary file beside it (PATH.partial-RANDOM, created
// new, never through a link, with the old file's mode), which commit() renames over it: a run that ends early (out of memory, a full
// disk, a signal) leaves the previous file or none, never a shortened one. Anything else (a
// symbolic link, /dev/stdout, a pipe, /dev/full, another user's or a read-only file) is written in
// place, as before. commit() and the constructor throw InputError naming the path when the file
// cannot be written.
class OutputFile {
  public:
    explicit OutputFile(std::string path);
    // With defer_in_place, a file to be written in place is not opened, nor truncated, until
    // open_in_place() (a writer that takes long stages its text elsewhere and copies it at the
    // end): the constructor only checks that it could be opened.
    OutputFile(std::string path, bool defer_in_place);
    void open_in_place();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;
    ~OutputFile(); // without commit(): the temporary file is removed
    std::ostream& stream() { return out_; }
    void commit();
    // Written in place (a link, a device, another's file: see above), so not whole-or-absent by
    // itself; else the temporary file's path (a writer that takes long may remove it on a signal).
    bool in_place() const { return temporary_.empty(); }
    const std::string& temporary_path() const { return temporary_; }

  private:
    std::string path_, temporary_; // temporary_ empty: written in place
    std::ofstream out_;
    bool committed_ = false, deferred_ = false;
};

void write_file(const std::string& path, const std::string& text); // checked, through OutputFile

} // namespace impactcert
