// verify_bench.cpp -- wall time of `impactcert verify` as a process, with its baselines measured
// in the same run: the cost of starting any process (/bin/true) and of starting impactcert
// itself (--version). Also the in-process time of verify() alone.
//
// Usage: impactcert_verify_bench PATH/TO/impactcert [RUNS]
#include "law_json.hpp"
#include "obligations.hpp"
#include "paper_law.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <spawn.h>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

struct Stats {
    double median_ms, p90_ms, min_ms;
};

Stats stats_of(std::vector<double> ms) {
    std::sort(ms.begin(), ms.end());
    return {ms[ms.size() / 2], ms[ms.size() * 9 / 10], ms.front()};
}

// Exit statuses a run may end with (verify of a law with a refuted claim exits 1).
int g_max_status = 0;

double run_once(const std::vector<std::string>& argv) {
    std::vector<char*> args;
    for (const auto& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    const auto start = Clock::now();
    pid_t pid;
    if (posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ) != 0) {
        std::fprintf(stderr, "cannot start %s\n", args[0]);
        std::exit(2);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    const auto stop = Clock::now();
    posix_spawn_file_actions_destroy(&actions);
    if (!WIFEXITED(status) || WEXITSTATUS(status) > g_max_status) {
        std::fprintf(stderr, "%s exited with status %d\n", args[0], WEXITSTATUS(status));
        std::exit(2);
    }
    return std::chrono::duration<double, std::milli>(stop - start).count();
}

Stats time_process(const std::vector<std::string>& argv, int runs) {
    std::vector<double> ms;
    run_once(argv); // warm the page cache
    for (int i = 0; i < runs; ++i)
        ms.push_back(run_once(argv));
    return stats_of(ms);
}

void print(const char* what, const Stats& s) {
    std::printf("  %-50s median %7.3f ms   p90 %7.3f ms   min %7.3f ms\n", what, s.median_ms, s.p90_ms, s.min_ms);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s PATH/TO/impactcert [RUNS]\n", argv[0]);
        return 2;
    }
    const std::string cli = argv[1];
    const int runs = argc > 2 ? std::max(5, std::atoi(argv[2])) : 200;
    const std::string law_file = std::string(IMPACTCERT_SOURCE_DIR) + "/proofs/newton3/law.json";

    std::printf("impactcert verify benchmark (%d runs each, wall time per process)\n", runs);
    std::printf("baselines:\n");
    const Stats floor = time_process({"/bin/true"}, runs);
    print("/bin/true (starting any process)", floor);
    print("impactcert --version (starting impactcert)", time_process({cli, "--version"}, runs));
    std::printf("measured:\n");
    const Stats embedded = time_process({cli, "verify"}, runs);
    print("impactcert verify (embedded paper law)", embedded);
    print("impactcert verify --law proofs/newton3/law.json", time_process({cli, "verify", "--law", law_file}, runs));
    print("impactcert verify --json", time_process({cli, "verify", "--json"}, runs));

    std::vector<double> in_process;
    const impactcert::Model model(impactcert::paper_law());
    std::size_t pairs_checked = 0;
    for (int i = 0; i < runs; ++i) {
        const auto start = Clock::now();
        const auto report = impactcert::verify(model);
        in_process.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
        pairs_checked = report.at("nonexpansive").checks;
    }
    print("verify() in process (12 obligations)", stats_of(in_process));
    std::printf("  (nonexpansive: %zu exact checks over 36 ordered cone pairs)\n", pairs_checked);

    const bool ok = embedded.median_ms < 10.0;
    std::printf("target: impactcert verify under 10 ms per process: %s (median %.3f ms, %.3f ms above /bin/true)\n",
                ok ? "met" : "MISSED", embedded.median_ms, embedded.median_ms - floor.median_ms);

    // Derived laws: `derive sequential -o F` then `verify --law F`, two processes per run.
    std::printf("\nderive sequential + verify (two processes per run; verify may exit 1: the verdicts are data)\n");
    g_max_status = 1;
    struct Chain {
        const char* what;
        const char* masses;
        const char* restitution;
        int runs;
        double target_ms;
    };
    const Chain chains[] = {
        {"3 balls, masses 1,2,1, e = 1", "1,2,1", "1", 50, 50.0},
        {"3 balls, masses 1,1,1, e = 1 (the paper's law)", "1,1,1", "1", 50, 50.0},
        {"4 balls, masses 1,2,3,4, e = 1/2", "1,2,3,4", "1/2", 3, 5000.0},
        {"5 balls, masses 2,1,3,1,2, e = 9/10", "2,1,3,1,2", "9/10", 1, 60000.0},
    };
    const std::string out = "/tmp/impactcert-bench-derived.json";
    for (const auto& chain : chains) {
        std::vector<double> ms;
        for (int i = 0; i < chain.runs; ++i) {
            const double d = run_once({cli, "derive", "sequential", "--masses", chain.masses, "--restitution",
                                       chain.restitution, "-o", out});
            const double v = run_once({cli, "verify", "--law", out});
            ms.push_back(d + v);
        }
        const Stats st = stats_of(ms);
        std::printf("  %-50s median %10.1f ms   target %.0f ms: %s\n", chain.what, st.median_ms, chain.target_ms,
                    st.median_ms < chain.target_ms ? "met" : "MISSED");
    }
    std::remove(out.c_str());
    return 0;
}
