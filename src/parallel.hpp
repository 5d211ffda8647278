// parallel.hpp -- starting threads without letting a failed start end the process.
//
// std::thread's constructor throws when the system cannot start one more thread (no memory for
// its stack under a cap such as `ulimit -v`, or no threads left), and a vector of joinable
// threads destroyed by that exception calls std::terminate (SIGABRT). Every parallel section
// starts its threads through start_thread and does the shares that did not start itself, so a
// run under a cap gives the same result on fewer threads, or std::bad_alloc (exit 3).
#pragma once

#include <cstddef>
#include <exception>
#include <new>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace impactcert {

// Appends a thread running f, or returns false (nothing started, `threads` unchanged).
template <class F> bool start_thread(std::vector<std::thread>& threads, F&& f) noexcept {
    try {
        threads.emplace_back(std::forward<F>(f));
        return true;
    } catch (...) {
        return false;
    }
}

// A thread that the run cannot do without (a watcher enforcing a time limit): started, or
// std::bad_alloc when the system cannot start it (exit 3, out of memory), never std::terminate.
template <class F> std::thread start_required_thread(F&& f) {
    try {
        return std::thread(std::forward<F>(f));
    } catch (const std::system_error&) {
        throw std::bad_alloc();
    }
}

// Runs share(t) for t = 0 .. jobs - 1: shares 1.. on threads when they start, share 0 and every
// share whose thread did not start on the calling thread, then joins them all. Shares on the
// threads must not throw (they keep their exception for the caller to read after the join); an
// exception of a share run here is rethrown once every thread is joined.
template <class F> void run_shares(std::size_t jobs, F&& share) {
    std::vector<std::thread> threads;
    std::vector<std::size_t> here{0};
    for (std::size_t t = 1; t < jobs; ++t)
        if (!start_thread(threads, [&share, t] { share(t); }))
            here.push_back(t);
    std::exception_ptr error;
    for (const std::size_t t : here) {
        try {
            share(t);
        } catch (...) {
            if (!error)
                error = std::current_exception();
        }
    }
    for (auto& th : threads)
        th.join();
    if (error)
        std::rethrow_exception(error);
}

} // namespace impactcert
