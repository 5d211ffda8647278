// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/fuzz_impl.hpp"

#include "fuzz/float_eval.hpp"

#include <impactcert/float_law.hpp>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <map>
#include <memory>
#include <vector>

namespace impactcert::fuzz {

// ---------------------------------------------------------------------------------------------
// Text

char* hex_to(double x, char* out) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    if (b >> 63)
        *out++ = '-';
    const int e = static_cast<int>((b >> 52) & 0x7ff);
    std::uint64_t mant = b & ((std::uint64_t{1} << 52) - 1);
    auto put = [&](const char* s) {
        while (*s)
            *out++ = *s++;
    };
    if (e == 0x7ff) {
        put(mant ? "nan" : "inf");
        return out;
    }
    if (e == 0 && mant == 0) {
        put("0x0p+0");
        return out;
    }
    put(e == 0 ? "0x0" : "0x1");
    if (mant) {
        *out++ = '.';
        int digits = 13;
        while ((mant & 0xf) == 0) {
            mant >>= 4;
            --digits;
        }
        for (int k = digits - 1; k >= 0; --k)
            *out++ = "0123456789abcdef"[(mant >> (4 * k)) & 0xf];
    }
    int exponent = e == 0 ? -1022 : e - 1023;
    *out++ = 'p';
    *out++ = exponent < 0 ? '-' : '+';
    exponent = std::abs(exponent);
    char digits[8];
    int nd = 0;
    do {
        digits[nd++] = static_cast<char>('0' + exponent % 10);
        exponent /= 10;
    } while (exponent);
    while (nd)
        *out++ = digits[--nd];
    return out;
}

std::string shortest_decimal(double x) {
    char buf[40];
    for (int digits = 1; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, x);
        if (std::strtod(buf, nullptr) == x)
            break;
    }
    return buf;
}

std::string hex(double x) {
    char buf[40];
    return std::string(buf, hex_to(x, buf));
}

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char ch : s)
        q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return q + "'";
}

namespace {

// ---------------------------------------------------------------------------------------------
// Built-ins and shared objects

class PaperImpl final : public Implementation {
  public:
    explicit PaperImpl(bool velocities) : velocities_(velocities) {}
    void eval(const double* in, double* out, double*, std::size_t count, ImplStatus* status) override {
        const std::size_t m = velocities_ ? 3 : 2;
        for (std::size_t i = 0; i < count; ++i, in += m, out += m) {
            status[i] = ImplStatus::ok;
            if (velocities_) {
                std::memcpy(out, in, 3 * sizeof(double));
                fp::sort_velocities(out);
            } else {
                fp::S(in[0], in[1], out);
            }
        }
    }
    std::unique_ptr<Implementation> clone() const override { return std::make_unique<PaperImpl>(velocities_); }
    std::string describe() const override { return "built-in float law (paper)"; }
    std::string replay_flags() const override { return ""; }

  private:
    bool velocities_;
};

class FloatLawImpl final : public Implementation {
  public:
    explicit FloatLawImpl(const Model& model) : model_(model), law_(model) {}
    void eval(const double* in, double* out, double* bound, std::size_t count, ImplStatus* status) override {
        const std::size_t m = model_.contacts();
        std::vector<double> x(m);
        for (std::size_t i = 0; i < count; ++i, in += m, out += m) {
            x.assign(in, in + m);
            const auto r = law_.eval(x);
            status[i] = r.ok ? ImplStatus::ok : ImplStatus::refused;
            for (std::size_t j = 0; j < m; ++j) {
                out[j] = r.ok ? r.value[j] : NAN;
                if (bound)
                    bound[i * m + j] = r.ok ? r.bound[j] : INFINITY;
            }
        }
    }
    bool states_bound() const override { return true; }
    std::unique_ptr<Implementation> clone() const override { return std::make_unique<FloatLawImpl>(model_); }
    std::string describe() const override { return "built-in float law (FloatLaw, against its stated bound)"; }
    std::string replay_flags() const override { return ""; }

  private:
    const Model& model_;
    FloatLaw law_;
};

// A law on dependent contact columns in ball velocities (proofs/README.md, "Redundant contacts"):
// y = W_B^T u-, the float law's y+, and u+ = u- + M^-1 W_B H_B (y+ - y), all in doubles.
class VelocityFloatLawImpl final : public Implementation {
  public:
    explicit VelocityFloatLawImpl(const Model& model) : model_(model), law_(model) {
        const Matrix lift = model.M_inv() * model.W() * model.H();
        n_ = model.balls();
        c_ = model.contacts();
        for (std::size_t i = 0; i < n_; ++i)
            for (std::size_t k = 0; k < c_; ++k) {
                W_.push_back(mpq_get_d(model.W()(i, k).mpq()));
                lift_.push_back(mpq_get_d(lift(i, k).mpq()));
            }
    }
    void eval(const double* in, double* out, double*, std::size_t count, ImplStatus* status) override {
        std::vector<double> y(c_);
        for (std::size_t i = 0; i < count; ++i, in += n_, out += n_) {
            for (std::size_t k = 0; k < c_; ++k) {
                y[k] = 0;
                for (std::size_t j = 0; j < n_; ++j)
                    y[k] += W_[j * c_ + k] * in[j];
            }
            const auto r = law_.eval(y);
            status[i] = r.ok ? ImplStatus::ok : ImplStatus::refused;
            for (std::size_t j = 0; j < n_; ++j) {
                double du = 0;
                for (std::size_t k = 0; k < c_ && r.ok; ++k)
                    du += lift_[j * c_ + k] * (r.value[k] - y[k]);
                out[j] = r.ok ? in[j] + du : NAN;
            }
        }
    }
    std::unique_ptr<Implementation> clone() const override { return std::make_unique<VelocityFloatLawImpl>(model_); }
    std::string describe() const override {
        return "built-in float law in ball velocities (u+ = u- + M^-1 W_B H_B (S(W_B^T u-) - W_B^T u-))";
    }
    std::string replay_flags() const override { return ""; }

  private:
    const Model& model_;
    FloatLaw law_;
    std::size_t n_ = 0, c_ = 0;
    std::vector<double> W_, lift_; // W_B (n x c) and M^-1 W_B H_B (n x c), row-major
};

using CFunction = void (*)(const double*, double*);

class SymbolImpl final : public Implementation {
  public:
    SymbolImpl(std::string spec, CFunction f, std::size_t in_dim, std::size_t out_dim)
        : spec_(std::move(spec)), f_(f), in_dim_(in_dim), out_dim_(out_dim) {}
    void eval(const double* in, double* out, double*, std::size_t count, ImplStatus* status) override {
        for (std::size_t i = 0; i < count; ++i) {
            f_(in + i * in_dim_, out + i * out_dim_);
            status[i] = ImplStatus::ok;
        }
    }
    std::unique_ptr<Implementation> clone() const override {
        return std::make_unique<SymbolImpl>(spec_, f_, in_dim_, out_dim_);
    }
    std::string describe() const override { return spec_; }
    std::string replay_flags() const override { return "--impl " + shell_quote(spec_); }
  private:
    std::string spec_;
    CFunction f_;
    std::size_t in_dim_, out_dim_;
};

// ---------------------------------------------------------------------------------------------
// A separate process

// The process groups of running commands, so that SIGINT, SIGTERM or SIGHUP to the fuzzer also
// end them (a command may fork: PR_SET_PDEATHSIG reaches only the direct child). The handler
// only calls kill(), which is async-signal-safe, then dies of the signal as it would have.
constexpr std::size_t kMaxGroups = 1024;
std::atomic<pid_t> g_groups[kMaxGroups];

extern "C" void kill_groups_and_die(int sig) {
    for (auto& g : g_groups) {
        const pid_t pgid = g.load();
        if (pgid > 0)
            kill(-pgid, SIGKILL);
    }
    std::signal(sig, SIG_DFL);
    raise(sig);
}

void register_group(pid_t pgid) {
    static const bool installed = [] {
        for (int sig : {SIGINT, SIGTERM, SIGHUP})
            std::signal(sig, kill_groups_and_die);
        return true;
    }();
    (void)installed;
    for (auto& g : g_groups) {
        pid_t empty = 0;
        if (g.compare_exchange_strong(empty, pgid))
            return;
    }
}

void unregister_group(pid_t pgid) {
    for (auto& g : g_groups) {
        pid_t expected = pgid;
        if (g.compare_exchange_strong(expected, 0))
            return;
    }
}

// The standard error of a command's processes: one anonymous file (O_TMPFILE, else a temporary
// file unlinked at once), appended to by every process of every clone.
struct StderrLog {
    int fd = -1;
    StderrLog() {
        const char* dir = std::getenv("TMPDIR");
        const std::string d = dir && *dir ? dir : "/tmp";
        fd = open(d.c_str(), O_TMPFILE | O_RDWR | O_APPEND | O_CLOEXEC, 0600);
        if (fd < 0) {
            std::string name = d + "/impactcert-stderr-XXXXXX";
            fd = mkostemp(name.data(), O_APPEND | O_CLOEXEC);
            if (fd >= 0)
                unlink(name.c_str());
        }
    }
    ~StderrLog() {
        if (fd >= 0)
            close(fd);
    }
    StderrLog(const StderrLog&) = delete;
    StderrLog& operator=(const StderrLog&) = delete;

    StderrSummary summary() const {
        StderrSummary s;
        if (fd < 0)
            return s;
        char buf[1 << 16];
        std::string line;
        bool cut = false;
        off_t at = 0;
        for (;;) {
            const ssize_t n = pread(fd, buf, sizeof buf, at);
            if (n <= 0)
                break;
            at += n;
            s.bytes += static_cast<std::uint64_t>(n);
            for (ssize_t i = 0; i < n; ++i) {
                if (buf[i] == '\n') {
                    ++s.lines;
                    if (s.first.size() < 3 && std::find(s.first.begin(), s.first.end(), line) == s.first.end())
                        s.first.push_back(line);
                    line.clear();
                    cut = false;
                } else if (line.size() < 200) {
                    line += buf[i] >= 32 && buf[i] < 127 ? buf[i] : '?';
                } else {
                    cut = true;
                }
            }
        }
        (void)cut;
        if (!line.empty()) { // a last line without its newline
            ++s.lines;
            if (s.first.size() < 3 && std::find(s.first.begin(), s.first.end(), line) == s.first.end())
                s.first.push_back(line);
        }
        return s;
    }
};

class CommandImpl final : public Implementation {
  public:
    static constexpr double kStartupGrace = 2.0; // seconds
    CommandImpl(std::string cmd, std::size_t in_dim, std::size_t out_dim, double timeout, bool quiet = false,
                std::shared_ptr<StderrLog> log = nullptr)
        : cmd_(std::move(cmd)), in_dim_(in_dim), out_dim_(out_dim), timeout_(timeout), quiet_(quiet),
          log_(std::move(log)) {}
    ~CommandImpl() override { stop(); }
    CommandImpl(const CommandImpl&) = delete;
    CommandImpl& operator=(const CommandImpl&) = delete;

    void eval(const double* in, double* out, double*, std::size_t count, ImplStatus* status) override {
        std::size_t done = 0;
        bool one_at_a_time = false; // after a nondeterministic answer (below)
        repeated_.clear();
        while (done < count) {
            if (stop_flag_ && stop_flag_->load(std::memory_order_relaxed)) { // --seconds ran out
                for (; done < count; ++done)
                    status[done] = ImplStatus::skipped;
                return;
            }
            if (one_at_a_time) {
                // After a nondeterministic answer the batch's other answers cannot be attributed
                // (a nondeterministic map may also have shifted its lines): each remaining input
                // is asked on its own, repeated in a fresh process, and checked as given.
                std::vector<double> first, second;
                const ImplStatus st = ask_repeated(in + done * in_dim_, first, second);
                if (st != ImplStatus::ok) {
                    status[done] = st;
                    for (std::size_t j = 0; j < out_dim_; ++j)
                        out[done * out_dim_ + j] = NAN;
                } else if (!same_values(first.data(), second.data(), out_dim_)) {
                    status[done] = ImplStatus::nondeterministic;
                    std::copy(first.begin(), first.end(), out + done * out_dim_);
                    repeated_[done] = second;
                } else {
                    status[done] = ImplStatus::ok;
                    std::copy(second.begin(), second.end(), out + done * out_dim_);
                }
                ++done;
                continue;
            }
            if (pid_ < 0)
                start();
            sentinel_differs_ = false;
            const std::size_t asked = count - done;
            const std::size_t answered = batch(in + done * in_dim_, out + done * out_dim_, asked, status + done);
            if (failure_ == ImplStatus::malformed && answered == asked) {
                // The repeated first input answered otherwise, or more lines than inputs: every
                // answer of this batch may belong to another input -- or the map is not a
                // function of its input. A fresh process answers the first input repeatedly: a
                // deterministic map gives the same answers (the difference was a shift of lines:
                // malformed); anything else is nondeterminism, its own finding.
                const bool differs = sentinel_differs_ && status[done] == ImplStatus::ok;
                stop();
                std::vector<double> first, second;
                const bool nondeterministic = differs && ask_repeated(in + done * in_dim_, first, second) == ImplStatus::ok &&
                                              !same_values(first.data(), second.data(), out_dim_);
                if (!nondeterministic) {
                    for (std::size_t i = done; i < count; ++i)
                        status[i] = ImplStatus::malformed;
                    return;
                }
                // Nondeterminism is a finding, not a reason to stop checking: the rest of the
                // batch is asked one input at a time (above), so every answer is checked as given
                // and each input answered differently is a finding of its own.
                status[done] = ImplStatus::nondeterministic;
                std::copy(first.begin(), first.end(), out + done * out_dim_);
                repeated_[done] = second;
                ++done;
                one_at_a_time = true;
                continue;
            }
            done += answered;
            if (done < count && failure_ == ImplStatus::skipped)
                continue; // the loop head marks the rest
            if (done < count) { // the point at `done` crashed or hung the process
                status[done] = failure_;
                for (std::size_t j = 0; j < out_dim_; ++j)
                    out[done * out_dim_ + j] = NAN;
                ++done;
                stop();
            }
        }
    }
    void set_stop_flag(const std::atomic<bool>* stop) override { stop_flag_ = stop; }
    std::unique_ptr<Implementation> clone() const override {
        return std::make_unique<CommandImpl>(cmd_, in_dim_, out_dim_, timeout_, false,
                                             log_ ? log_ : std::make_shared<StderrLog>());
    }
    std::optional<StderrSummary> stderr_summary() const override {
        if (!log_ || log_->fd < 0)
            return std::nullopt;
        return log_->summary();
    }
    std::string describe() const override { return cmd_; }
    std::size_t batch_samples() const override { return 2048; }
    std::string replay_flags() const override { return "--impl-cmd " + shell_quote(cmd_); }
    std::vector<double> repeated_answer(std::size_t point) const override {
        const auto it = repeated_.find(point);
        return it == repeated_.end() ? std::vector<double>{} : it->second;
    }

    // A fresh process gets input x kRepeats times; `first` and `second` receive its last two
    // answers. A deterministic map whose lines are shifted (a header line, a line too many)
    // answers the later repetitions alike whatever the shift (up to kRepeats - 2 lines), so only
    // an answer that changes between the last two is nondeterminism. Not ok: the process
    // crashed, hung or answered malformed lines there.
    ImplStatus ask_repeated(const double* x, std::vector<double>& first, std::vector<double>& second) {
        constexpr std::size_t kRepeats = 7;
        stop();
        start();
        std::vector<double> again_in, again(kRepeats * out_dim_, 0.0);
        for (std::size_t r = 0; r < kRepeats; ++r)
            again_in.insert(again_in.end(), x, x + in_dim_);
        std::vector<ImplStatus> st(kRepeats, ImplStatus::ok);
        const std::size_t n = batch(again_in.data(), again.data(), kRepeats, st.data());
        const ImplStatus why = failure_;
        stop();
        if (n != kRepeats || st[kRepeats - 2] != ImplStatus::ok || st[kRepeats - 1] != ImplStatus::ok)
            return why == ImplStatus::ok ? ImplStatus::malformed : why;
        first.assign(again.begin() + static_cast<std::ptrdiff_t>((kRepeats - 2) * out_dim_),
                     again.begin() + static_cast<std::ptrdiff_t>((kRepeats - 1) * out_dim_));
        second.assign(again.begin() + static_cast<std::ptrdiff_t>((kRepeats - 1) * out_dim_), again.end());
        return ImplStatus::ok;
    }

    // Why the last process ended (for the probe's error message).
    std::string last_exit() const { return last_exit_; }

  private:
    std::string cmd_;
    std::size_t in_dim_, out_dim_;
    double timeout_;
    bool quiet_; // the probe: the command's stderr goes to /dev/null (our error says it in one line)
    std::shared_ptr<StderrLog> log_; // otherwise: collected here (shared by the clones)
    pid_t pid_ = -1;
    int to_child_ = -1, from_child_ = -1;
    std::string rbuf_, wbuf_;
    ImplStatus failure_ = ImplStatus::crashed;
    std::string last_exit_;
    bool fresh_ = false; // started and not answered yet: its start-up time is not a hang
    bool pid_reaped_ = false;
    bool sentinel_differs_ = false; // batch(): the repeated first input was answered otherwise
    double sentinel_[64] = {};      // ... with this
    std::map<std::size_t, std::vector<double>> repeated_; // per nondeterministic point of the last eval(): its other answer
    pid_t guardian_ = -1;    // see start_guardian()
    int guardian_pipe_ = -1; // its write end, held by the fuzzer only
    const std::atomic<bool>* stop_flag_ = nullptr;
    static constexpr std::size_t kMaxLine = 1 << 16; // bytes without a newline: a malformed answer

    void start() {
        std::signal(SIGPIPE, SIG_IGN); // a dead child must not kill the fuzzer through a write
        // Close-on-exec from the start: a sibling's process must not inherit these pipes (it
        // would keep them open and turn this one's crash into a hang).
        int in_pipe[2], out_pipe[2];
        if (pipe2(in_pipe, O_CLOEXEC) != 0 || pipe2(out_pipe, O_CLOEXEC) != 0)
            throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
        const pid_t parent = getpid();
        const pid_t pid = fork();
        if (pid < 0)
            throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
        if (pid == 0) {
            setpgid(0, 0);                     // its own group, killed as one by stop()
            prctl(PR_SET_PDEATHSIG, SIGKILL);  // and killed if the fuzzer dies first
            if (getppid() != parent)
                _exit(127);
            std::signal(SIGPIPE, SIG_DFL);     // the fuzzer ignores it; the command should not
            dup2(in_pipe[0], STDIN_FILENO);
            dup2(out_pipe[1], STDOUT_FILENO);
            close(in_pipe[0]);
            close(in_pipe[1]);
            close(out_pipe[0]);
            close(out_pipe[1]);
            if (quiet_) {
                const int null = open("/dev/null", O_WRONLY | O_CLOEXEC);
                if (null >= 0)
                    dup2(null, STDERR_FILENO);
            } else if (log_ && log_->fd >= 0) {
                dup2(log_->fd, STDERR_FILENO); // collected, summarised at the end of the run
            }
            execl("/bin/sh", "sh", "-c", cmd_.c_str(), static_cast<char*>(nullptr));
            _exit(127);
        }
        close(in_pipe[0]);
        close(out_pipe[1]);
        setpgid(pid, pid); // also here: no race with a signal before the child's own call
        register_group(pid);
        pid_ = pid;
        to_child_ = in_pipe[1];
        from_child_ = out_pipe[0];
        fcntl(to_child_, F_SETFL, fcntl(to_child_, F_GETFL) | O_NONBLOCK);
        fcntl(from_child_, F_SETFL, fcntl(from_child_, F_GETFL) | O_NONBLOCK);
        rbuf_.clear();
        fresh_ = true;
        start_guardian(pid); // after pid_ is set: if it throws, stop() still ends the command
    }

    // The guardian: a child of the fuzzer that waits for the end of a pipe whose only writer is
    // the fuzzer, then kills the command's process group. The pipe ends when the fuzzer ends, by
    // any means (kill -9 included, which no handler sees), so background processes of the command
    // do not outlive the fuzzer; PR_SET_PDEATHSIG reaches only the direct child. A normal stop()
    // kills the guardian first, so it never signals a group that is gone.
    void start_guardian(pid_t group) {
        int g[2];
        if (pipe2(g, O_CLOEXEC) != 0)
            throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
        const pid_t guardian = fork();
        if (guardian < 0) {
            close(g[0]);
            close(g[1]);
            throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
        }
        if (guardian == 0) {
            // Only async-signal-safe calls here (the fuzzer may have threads). Every other
            // descriptor is closed: a copy of another guardian's pipe would keep it waiting.
            const int r = g[0];
            if (r > 0)
                close_range(0, static_cast<unsigned>(r) - 1, 0);
            close_range(static_cast<unsigned>(r) + 1, ~0U, 0);
            char c;
            while (read(r, &c, 1) < 0 && errno == EINTR) {
            }
            kill(-group, SIGKILL);
            _exit(0);
        }
        close(g[0]);
        guardian_ = guardian;
        guardian_pipe_ = g[1];
    }

    void stop_guardian() {
        if (guardian_ < 0)
            return;
        kill(guardian_, SIGKILL);
        int st = 0;
        while (waitpid(guardian_, &st, 0) < 0 && errno == EINTR) {
        }
        close(guardian_pipe_);
        guardian_ = -1;
        guardian_pipe_ = -1;
    }

    void stop() {
        if (pid_ < 0)
            return;
        stop_guardian();
        close(to_child_);
        close(from_child_);
        kill(-pid_, SIGKILL); // the whole group: a shell and what it started
        unregister_group(pid_);
        if (!pid_reaped_) {
            kill(pid_, SIGKILL);
            int st = 0;
            waitpid(pid_, &st, 0);
            record_exit(st);
        }
        pid_reaped_ = false;
        pid_ = -1;
        to_child_ = from_child_ = -1;
    }

    // Parses one answer line into out; false when it is not out_dim numbers.
    bool parse_line(const char* begin, const char* end, double* out) const {
        std::string line(begin, end);
        const char* p = line.c_str();
        for (std::size_t j = 0; j < out_dim_; ++j) {
            char* next = nullptr;
            out[j] = std::strtod(p, &next);
            if (next == p)
                return false;
            p = next;
        }
        while (*p == ' ' || *p == '\t' || *p == '\r')
            ++p;
        // The end of the line, not a NUL inside it ("1 2 3\0 99 garbage" is not three numbers).
        return p == line.c_str() + line.size();
    }

    // Sends `count` points and reads answers until all are in or the process fails; returns the
    // number answered (failure_ says why when fewer: crashed, hung, or skipped when the stop flag
    // was raised; malformed with all answered when the process wrote more lines than inputs).
    std::size_t batch(const double* in, double* out, std::size_t count, ImplStatus* status) {
        wbuf_.clear();
        char tmp[64];
        // The batch's first input is sent once more at its end: its two answers must agree, or
        // the answers are out of step with the inputs (a line too many or too few).
        for (std::size_t i = 0; i <= count; ++i) {
            const std::size_t which = i < count ? i : 0;
            for (std::size_t j = 0; j < in_dim_; ++j) {
                char* e = hex_to(in[which * in_dim_ + j], tmp);
                *e++ = j + 1 == in_dim_ ? '\n' : ' ';
                wbuf_.append(tmp, e);
            }
        }
        bool sentinel_read = false;
        double sentinel[64];
        failure_ = ImplStatus::ok;
        std::size_t wpos = 0, answered = 0, scanned = 0;
        auto last_progress = std::chrono::steady_clock::now(); // the last complete line
        char chunk[1 << 16];
        for (;;) {
            // Complete lines already buffered.
            std::size_t start = 0;
            for (;;) {
                const auto nl = rbuf_.find('\n', std::max(start, scanned));
                if (nl == std::string::npos) {
                    scanned = rbuf_.size();
                    break;
                }
                if (answered == count) { // the repeated first input, then nothing more
                    // A malformed answer to the first input, repeated malformed for its repetition,
                    // is that input's answer, not a shift of the others (one malformed answer must
                    // not poison its batch).
                    const bool parsed = parse_line(rbuf_.data() + start, rbuf_.data() + nl, sentinel);
                    const bool same = status[0] == ImplStatus::ok
                                          ? parsed && same_values(sentinel, out, out_dim_)
                                          : !parsed;
                    if (sentinel_read || !same) {
                        failure_ = ImplStatus::malformed;
                        if (!sentinel_read && parsed && status[0] == ImplStatus::ok) {
                            sentinel_differs_ = true; // the first input, answered otherwise
                            std::memcpy(sentinel_, sentinel, out_dim_ * sizeof(double));
                        }
                        rbuf_.clear();
                        return answered;
                    }
                    sentinel_read = true;
                    start = nl + 1;
                    continue;
                }
                const bool ok = parse_line(rbuf_.data() + start, rbuf_.data() + nl, out + answered * out_dim_);
                status[answered] = ok ? ImplStatus::ok : ImplStatus::malformed;
                if (!ok)
                    for (std::size_t j = 0; j < out_dim_; ++j)
                        out[answered * out_dim_ + j] = NAN;
                ++answered;
                start = nl + 1;
                last_progress = std::chrono::steady_clock::now();
                fresh_ = false;
            }
            rbuf_.erase(0, start);
            scanned -= std::min(scanned, start);
            if (answered == count && sentinel_read && wpos == wbuf_.size()) {
                // Anything more already written is a surplus line (checked without waiting).
                const ssize_t n = read(from_child_, chunk, sizeof chunk);
                if (n > 0)
                    rbuf_.append(chunk, static_cast<std::size_t>(n));
                if (!rbuf_.empty()) {
                    failure_ = ImplStatus::malformed;
                    rbuf_.clear();
                }
                return answered;
            }
            if (rbuf_.size() > kMaxLine) { // no newline in 64 KiB: not an answer line
                status[answered] = ImplStatus::malformed;
                for (std::size_t j = 0; j < out_dim_; ++j)
                    out[answered * out_dim_ + j] = NAN;
                failure_ = ImplStatus::malformed;
                return answered; // the caller marks this point and restarts the process
            }
            if (stop_flag_ && stop_flag_->load(std::memory_order_relaxed)) {
                failure_ = ImplStatus::skipped;
                return answered;
            }
            pollfd fds[2];
            nfds_t nfds = 0;
            fds[nfds++] = {from_child_, POLLIN, 0};
            if (wpos < wbuf_.size())
                fds[nfds++] = {to_child_, POLLOUT, 0};
            const double waited =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - last_progress).count();
            // A process that has not answered yet also gets its start-up time (an interpreter
            // on a loaded machine can take a second to start).
            const double limit = fresh_ ? timeout_ + kStartupGrace : timeout_;
            if (waited >= limit) {
                failure_ = ImplStatus::hung;
                return answered;
            }
            // Wake at least every 200 ms: the stop flag, and a process that died while something
            // else keeps its output open (a background child) is found by waitpid.
            const int wait_ms = static_cast<int>(std::min(200.0, std::ceil((limit - waited) * 1000)));
            const int r = poll(fds, nfds, std::max(wait_ms, 1));
            if (r < 0) {
                if (errno == EINTR)
                    continue;
                throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
            }
            if (r == 0) {
                int st = 0;
                if (waitpid(pid_, &st, WNOHANG) == pid_) { // it ended; its output stays open elsewhere
                    record_exit(st);
                    pid_reaped_ = true;
                    failure_ = ImplStatus::crashed;
                    return answered;
                }
                continue;
            }
            if (nfds == 2 && (fds[1].revents & (POLLOUT | POLLERR | POLLHUP))) {
                const ssize_t w = write(to_child_, wbuf_.data() + wpos, wbuf_.size() - wpos);
                if (w > 0) {
                    wpos += static_cast<std::size_t>(w);
                } else if (w < 0 && errno != EAGAIN && errno != EINTR) {
                    wpos = wbuf_.size(); // the reader is gone: wait for the end of its output
                }
            }
            if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) {
                const ssize_t n = read(from_child_, chunk, sizeof chunk);
                if (n > 0) {
                    rbuf_.append(chunk, static_cast<std::size_t>(n));
                } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
                    // End of output. A final line without a newline still counts.
                    if (!rbuf_.empty() && answered < count) {
                        const bool ok = parse_line(rbuf_.data(), rbuf_.data() + rbuf_.size(), out + answered * out_dim_);
                        status[answered] = ok ? ImplStatus::ok : ImplStatus::malformed;
                        ++answered;
                        rbuf_.clear();
                    }
                    failure_ = answered == count ? ImplStatus::ok : ImplStatus::crashed;
                    if (answered == count)
                        stop(); // it ended after answering (the repeated line unanswered): start afresh
                    return answered;
                }
            }
        }
    }

    void record_exit(int st) {
        if (WIFEXITED(st))
            last_exit_ = WEXITSTATUS(st) == 127   ? "command not found (exit status 127)"
                         : WEXITSTATUS(st) == 126 ? "not executable (exit status 126)"
                                                  : "exit status " + std::to_string(WEXITSTATUS(st));
        else if (WIFSIGNALED(st))
            last_exit_ = "signal " + std::to_string(WTERMSIG(st));
    }
};

} // namespace

std::unique_ptr<Implementation> builtin_paper(bool velocities) { return std::make_unique<PaperImpl>(velocities); }

std::unique_ptr<Implementation> builtin_float_law(const Model& model) { return std::make_unique<FloatLawImpl>(model); }

std::unique_ptr<Implementation> builtin_float_law_velocities(const Model& model) {
    return std::make_unique<VelocityFloatLawImpl>(model);
}

std::unique_ptr<Implementation> load_symbol(const std::string& spec, std::size_t in_dim, std::size_t out_dim) {
    const auto colon = spec.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size())
        throw InputError("--impl " + spec + ": expected LIB.so:SYMBOL");
    const std::string lib = spec.substr(0, colon), symbol = spec.substr(colon + 1);
    void* handle = dlopen(lib.find('/') == std::string::npos ? ("./" + lib).c_str() : lib.c_str(), RTLD_NOW);
    if (!handle) {
        const char* why = dlerror();
        throw InputError("--impl " + spec + ": cannot load: " + (why ? why : "unknown reason"));
    }
    void* f = dlsym(handle, symbol.c_str());
    if (!f)
        throw InputError("--impl " + spec + ": no symbol " + symbol + " in " + lib);
    CFunction fn;
    static_assert(sizeof fn == sizeof f);
    std::memcpy(&fn, &f, sizeof f);
    return std::make_unique<SymbolImpl>(spec, fn, in_dim, out_dim);
}

std::unique_ptr<Implementation> command(const std::string& cmd, std::size_t in_dim, std::size_t out_dim,
                                        double timeout_seconds) {
    if (cmd.empty())
        throw InputError("--impl-cmd: empty command");
    auto impl = std::make_unique<CommandImpl>(cmd, in_dim, out_dim, timeout_seconds, true);
    // A first probe: the zero vector must get one line of out_dim numbers.
    std::vector<double> zero(in_dim, 0.0), out(out_dim);
    ImplStatus st = ImplStatus::ok;
    impl->eval(zero.data(), out.data(), nullptr, 1, &st);
    if (st != ImplStatus::ok) {
        // It may fail at rest only: a command that answers another input is a working one, and its
        // failure at rest is a finding of the run (at-rest), not bad input.
        std::vector<double> one(in_dim, 0.0);
        for (std::size_t j = 0; j < in_dim; ++j)
            one[j] = j % 2 == 0 ? -1.0 : 1.0;
        ImplStatus again = ImplStatus::ok;
        auto second = std::make_unique<CommandImpl>(cmd, in_dim, out_dim, timeout_seconds, true);
        second->eval(one.data(), out.data(), nullptr, 1, &again);
        if (again == ImplStatus::ok)
            return second->clone();
    }
    if (st == ImplStatus::crashed)
        throw InputError("--impl-cmd " + cmd + ": the command ended without answering (" + impl->last_exit() +
                         "; is it a command that reads lines of " + std::to_string(in_dim) + " doubles?)");
    if (st == ImplStatus::hung)
        throw InputError("--impl-cmd " + cmd + ": no answer within the timeout to the first input line");
    if (st == ImplStatus::malformed)
        throw InputError("--impl-cmd " + cmd + ": its answer to the first input line is not " +
                         std::to_string(out_dim) + " numbers");
    return impl->clone(); // the probe (stderr silenced) ends here; the run gets fresh processes
}

bool same_values(const double* a, const double* b, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
        if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i]))))
            return false;
    return true;
}

} // namespace impactcert::fuzz
