// SPDX-License-Identifier: GPL-3.0-or-later
// sanitizer_canary.cpp -- a negative control for the sanitizer build's flags (built only there):
// each mode commits one error that AddressSanitizer, LeakSanitizer or UndefinedBehaviorSanitizer
// must stop, with the compile options every target of that build gets. If a change of flags (an
// optimisation level, a --param) ever hid one of them, tests/sanitizer_canary_test.sh fails.
// Sizes and indices come from the command line, so that nothing is decided at compile time.
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

int opaque(const char* text) { return std::atoi(text); }

__attribute__((noinline)) int read_at(const int* p, int i) { return p[i]; }

// Allocates and drops the only pointer: reported when the program ends.
__attribute__((noinline)) int leak(int n) {
    char* p = static_cast<char*>(std::malloc(static_cast<std::size_t>(n > 0 ? n : 1) * 1000));
    std::memset(p, 1, static_cast<std::size_t>(n > 0 ? n : 1) * 1000);
    return p[0];
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: sanitizer_canary MODE N (N = 4 commits the error)\n");
        return 2;
    }
    const std::string mode = argv[1];
    const int n = opaque(argv[2]);
    volatile int sink = 0;
    if (mode == "heap-buffer-overflow") {
        std::vector<int> v(static_cast<std::size_t>(n > 0 ? n : 1));
        sink = v.data()[n]; // one past the end
    } else if (mode == "heap-use-after-free") {
        int* p = new int[static_cast<std::size_t>(n > 0 ? n : 1)];
        p[0] = n;
        delete[] p;
        sink = p[n / 4];
    } else if (mode == "stack-buffer-overflow") {
        int a[4] = {1, 2, 3, 4};
        sink = read_at(a, n); // the size is unknown there: ASan's check, not UBSan's object size
    } else if (mode == "memory-leak") {
        sink = leak(n);
    } else if (mode == "signed-integer-overflow") {
        int x = INT_MAX - 3;
        x += n; // INT_MAX + 1
        sink = x;
    } else if (mode == "shift-exponent") {
        sink = 1 << (28 + n); // 1 << 32
    } else if (mode == "none") {
        sink = n;
    } else {
        std::fprintf(stderr, "sanitizer_canary: unknown mode '%s'\n", mode.c_str());
        return 2;
    }
    return sink == INT_MIN ? 1 : 0;
}
