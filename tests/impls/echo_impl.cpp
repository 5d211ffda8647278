// SPDX-License-Identifier: GPL-3.0-or-later
// echo_impl.cpp -- the cheapest possible --impl-cmd program: answers every line with itself
// (the identity map, so it is wrong for any real law). scripts/bench measures the throughput
// of the --impl-cmd protocol with it. It flushes its output whenever its input is drained,
// which is what "flush after each line" requires without a system call per line.
#include <unistd.h>

#include <cstddef>

int main() {
    static char buf[1 << 16];
    for (;;) {
        const ssize_t n = read(STDIN_FILENO, buf, sizeof buf);
        if (n <= 0)
            return 0;
        for (ssize_t done = 0; done < n;) {
            const ssize_t w = write(STDOUT_FILENO, buf + done, static_cast<std::size_t>(n - done));
            if (w <= 0)
                return 1;
            done += w;
        }
    }
}
