// SPDX-License-Identifier: GPL-3.0-or-later
#include "report/figure.hpp"

#include "base/errors.hpp"
#include "base/output_file.hpp"
#include "prover/verdict_output.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>

extern char** environ;

namespace impactcert {
namespace {

constexpr std::size_t kMaxPdfBytes = std::size_t{256} << 20;

// The number in attribute NAME="..." of the first tag of svg (0 when absent).
double first_tag_number(const std::string& svg, const std::string& name) {
    const auto end = svg.find('>');
    const std::string tag = svg.substr(0, end);
    const auto at = tag.find(" " + name + "=\"");
    if (at == std::string::npos)
        return 0;
    return std::strtod(tag.c_str() + at + name.size() + 3, nullptr);
}

std::string px(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", x);
    return buf;
}

// The executable NAME in a directory of PATH, or empty.
std::string on_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const auto colon = dirs.find(':', start);
        const std::string dir = dirs.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
        const std::string candidate = (dir.empty() ? "." : dir) + "/" + name;
        struct stat st {};
        if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
            return candidate;
        if (colon == std::string::npos)
            break;
        start = colon + 1;
    }
    return "";
}

// rsvg-convert -f pdf SVG, its standard output into pdf_path (whole or absent).
void convert_to_pdf(const std::string& converter, const std::string& svg_path, const std::string& pdf_path,
                    int seconds) {
    OutputFile out(pdf_path); // first: a PDF that cannot be written fails before anything runs
    int pipe_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0)
        throw InputError(pdf_path + ": cannot start " + converter + ": " + std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    std::string a0 = converter, a1 = "-f", a2 = "pdf", a3 = (svg_path[0] == '-' ? "./" : "") + svg_path;
    char* argv[] = {a0.data(), a1.data(), a2.data(), a3.data(), nullptr};
    // Its own process group, so that a deadline ends whatever it started too.
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
    // Reproducible PDFs: cairo writes SOURCE_DATE_EPOCH as the creation date; without one in the
    // environment, a fixed 0 (1970-01-01), so that the same figures give the same bytes.
    std::vector<std::string> env_text;
    bool has_epoch = false;
    for (char** e = environ; e && *e; ++e) {
        env_text.emplace_back(*e);
        has_epoch = has_epoch || env_text.back().rfind("SOURCE_DATE_EPOCH=", 0) == 0;
    }
    if (!has_epoch)
        env_text.emplace_back("SOURCE_DATE_EPOCH=0");
    std::vector<char*> envp;
    for (auto& e : env_text)
        envp.push_back(e.data());
    envp.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, converter.c_str(), &actions, &attributes, argv, envp.data());
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    ::close(pipe_fds[1]);
    if (spawned != 0) {
        ::close(pipe_fds[0]);
        throw InputError(pdf_path + ": cannot start " + converter + ": " + std::strerror(spawned));
    }
    std::string failure;
    {
        std::size_t total = 0;
        char buffer[1 << 16];
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
        for (;;) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
            pollfd wait_for{pipe_fds[0], POLLIN, 0};
            const int ready = left.count() > 0 ? ::poll(&wait_for, 1, static_cast<int>(left.count())) : 0;
            if (ready < 0 && errno == EINTR)
                continue;
            if (ready == 0) {
                ::kill(-pid, SIGKILL);
                failure = "the converter did not finish in " + std::to_string(seconds) + " s";
                break;
            }
            const ssize_t got = ::read(pipe_fds[0], buffer, sizeof buffer);
            if (got < 0 && errno == EINTR)
                continue;
            if (got <= 0)
                break;
            total += static_cast<std::size_t>(got);
            if (total > kMaxPdfBytes) {
                ::kill(-pid, SIGKILL);
                failure = "the converter wrote more than 256 MiB";
                break;
            }
            out.stream().write(buffer, got);
        }
        ::close(pipe_fds[0]);
        // Its exit is awaited, within the same deadline (a converter may close its output and go
        // on), without reaping it (WNOWAIT): while it is a zombie its process group id cannot be
        // reused, so killing what it left behind in the group hits nothing else.
        for (bool killed = false;;) {
            siginfo_t exited{};
            const int r = ::waitid(P_PID, static_cast<id_t>(pid), &exited, WEXITED | WNOWAIT | WNOHANG);
            if (r < 0 && errno == EINTR)
                continue;
            if (r < 0 || exited.si_pid != 0)
                break;
            if (!killed && std::chrono::steady_clock::now() >= deadline) {
                ::kill(-pid, SIGKILL);
                killed = true;
                if (failure.empty())
                    failure = "the converter did not finish in " + std::to_string(seconds) + " s";
            }
            ::usleep(10000);
        }
        ::kill(-pid, SIGKILL);
        int status = 0;
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        if (failure.empty() && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
            failure = WIFEXITED(status) ? converter + " exited with status " + std::to_string(WEXITSTATUS(status))
                                        : converter + " was ended by signal " + std::to_string(WTERMSIG(status));
        if (failure.empty() && total < 5)
            failure = converter + " wrote no PDF";
        if (failure.empty())
            out.commit(); // else the temporary file is removed: no PDF rather than part of one
    }
    if (!failure.empty())
        throw InputError(pdf_path + ": " + failure);
}

} // namespace

// Words into lines of at most `width` characters (a longer word stands alone).
std::vector<std::string> wrap(const std::string& text, std::size_t width) {
    std::vector<std::string> lines;
    std::string line, word;
    std::istringstream in(text);
    while (in >> word) {
        if (!line.empty() && line.size() + 1 + word.size() > width) {
            lines.push_back(line);
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty())
        lines.push_back(line);
    return lines;
}

std::string standalone_figure(const std::string& full_title, const std::string& caption, const std::string& drawing,
                              const std::vector<LegendItem>& full_legend) {
    // Names come from the law file: a title of 200,000 characters made a page of 1.7 M pixels that
    // the converter laid out for minutes. The full names stay in the drawing's hover titles.
    const std::string title = shortened(full_title, 120);
    std::vector<LegendItem> legend = full_legend;
    for (auto& item : legend)
        item.label = shortened(item.label, 40);
    const double margin = 14, w = first_tag_number(drawing, "width"), h = first_tag_number(drawing, "height");
    // Text widths estimated at 0.6 em per character (sans-serif; the figure scales, nothing clips).
    auto label_width = [](const LegendItem& item) { return 30 + 6.6 * static_cast<double>(item.label.size()) + 14; };
    double legend_w = 0;
    for (const auto& item : legend)
        legend_w += label_width(item);
    const double inner = std::max({w, 480.0, std::min(legend_w, 900.0)});
    const auto lines = wrap(caption, static_cast<std::size_t>(inner / 6.0));
    // Without a title (report --bare-figures) neither title nor caption is drawn: a paper sets them.
    const double title_h = title.empty() ? 0 : 26, caption_h = 15 * static_cast<double>(lines.size()),
                 top = title.empty() && lines.empty() ? margin : margin + title_h + caption_h + 6;
    // Legend rows no wider than the figure.
    std::vector<std::vector<const LegendItem*>> rows(legend.empty() ? 0 : 1);
    double row_w = 0;
    for (const auto& item : legend) {
        if (row_w > 0 && row_w + label_width(item) > inner) {
            rows.emplace_back();
            row_w = 0;
        }
        rows.back().push_back(&item);
        row_w += label_width(item);
    }
    const double width = std::max(inner, 8.4 * static_cast<double>(title.size())) + 2 * margin;
    const double height = top + h + 22 * static_cast<double>(rows.size()) + margin + (rows.empty() ? 0 : 8);
    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + px(width) + "\" height=\"" + px(height) +
                    "\" viewBox=\"0 0 " + px(width) + " " + px(height) + "\" font-family=\"sans-serif\">\n";
    s += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
    if (!title.empty())
        s += "<text x=\"" + px(margin) + "\" y=\"" + px(margin + 16) + "\" font-size=\"15\" font-weight=\"bold\" fill=\"#000000\">" +
             xml_escape(title) + "</text>\n";
    for (std::size_t k = 0; k < lines.size(); ++k)
        s += "<text x=\"" + px(margin) + "\" y=\"" + px(margin + title_h + 8 + 15 * static_cast<double>(k)) +
             "\" font-size=\"11\" fill=\"#333333\" class=\"caption\">" + xml_escape(lines[k]) + "</text>\n";
    // The drawing as a nested <svg> placed below the title.
    const auto open = drawing.find("<svg");
    if (open == std::string::npos)
        throw std::logic_error("standalone_figure: the drawing is not an SVG document");
    s += drawing.substr(0, open) + "<svg x=\"" + px(margin) + "\" y=\"" + px(top) + "\"" + drawing.substr(open + 4);
    if (s.back() != '\n')
        s += "\n";
    for (std::size_t r = 0; r < rows.size(); ++r) {
        double x = margin;
        const double y = top + h + 8 + 22 * static_cast<double>(r);
        for (const LegendItem* item : rows[r]) {
            using Shape = LegendItem::Shape;
            if (item->shape == Shape::dot)
                s += "<circle cx=\"" + px(x + 12) + "\" cy=\"" + px(y + 7) + "\" r=\"4\" fill=\"" + xml_escape(item->colour) + "\" stroke=\"#000000\"/>";
            else if (item->shape == Shape::square)
                s += "<rect x=\"" + px(x + 5) + "\" y=\"" + px(y) + "\" width=\"14\" height=\"14\" fill=\"" + xml_escape(item->colour) +
                     "\" stroke=\"#555555\" stroke-width=\"0.5\"/>";
            else
                s += "<line x1=\"" + px(x) + "\" y1=\"" + px(y + 7) + "\" x2=\"" + px(x + 24) + "\" y2=\"" + px(y + 7) +
                     "\" stroke=\"" + xml_escape(item->colour) + "\" stroke-width=\"2\"" +
                     (item->shape == Shape::dashed ? " stroke-dasharray=\"5,4\"" : "") + "/>";
            s += "<text x=\"" + px(x + 30) + "\" y=\"" + px(y + 11.5) + "\" font-size=\"11\" fill=\"#000000\">" +
                 xml_escape(item->label) + "</text>\n";
            x += label_width(*item);
        }
    }
    return s + "</svg>\n";
}

std::string pdf_unavailable_reason() {
    if (on_path("rsvg-convert").empty())
        return "PDF figures not written: rsvg-convert is not on PATH (Debian: apt-get install librsvg2-bin)";
    return "";
}

std::vector<std::string> write_figure(const std::string& stem, const std::string& svg, int converter_seconds) {
    std::vector<std::string> written = {stem + ".svg"};
    write_file(written[0], svg);
    const std::string converter = on_path("rsvg-convert");
    if (!converter.empty()) {
        convert_to_pdf(converter, written[0], stem + ".pdf", converter_seconds);
        written.push_back(stem + ".pdf");
    }
    return written;
}

} // namespace impactcert
