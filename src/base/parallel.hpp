// SPDX-License-Identifier: GPL-3.0-or-later
// parallel.hpp -- starting threads without letting a failed start end the process.
//
// std::thread's constructor throws when the system cannot start one more thread (no memory for
// its stack under a cap such as `ulimit -v`, or no threads left), and a vector of joinable
// threads destroyed by that exception calls std::terminate (SIGABRT). Every parallel section
// starts its threads through start_thread and does the shares that did not start, or ran out of
// memory on their thread, itself: a run under a cap gives the same result on fewer threads, or
// std::bad_alloc (exit 3) when the calling thread runs out too.
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

// Runs share(t) once to completion for t = 0 .. jobs - 1: shares 1.. on threads when they start,
// share 0 and every share whose thread did not start on the calling thread. Under an
// address-space cap a thread can start and still find no memory for its own heap (mimalloc gives
// each thread its own segments): a share that ends in std::bad_alloc on a thread is run again on
// the calling thread after the joins (the memory of the other threads' heaps given back). A
// share must therefore be safe to repeat (its results written in place, each reset before it is
// written). Any other exception, and std::bad_alloc on the calling thread (which is not retried:
// exit 3), is rethrown after the joins: that of the lowest share. Where shares take contiguous
// ranges that is the one a single thread meets first; where they are dealt out round-robin, two
// different exceptions in one call could be reported differently (callers keep limits, which
// must be read in order, out of the exceptions).
template <class F> void run_shares(std::size_t jobs, F&& share) {
    std::vector<std::exception_ptr> errors(jobs); // allocated before any thread starts
    std::vector<char> again(jobs, 0);
    std::vector<std::size_t> here;
    here.reserve(jobs);
    std::vector<std::thread> threads;
    threads.reserve(jobs); // the emplace_back below then never reallocates
    here.push_back(0);
    for (std::size_t t = 1; t < jobs; ++t) {
        auto on_thread = [&share, &errors, &again, t] {
            try {
                share(t);
            } catch (const std::bad_alloc&) {
                again[t] = 1;
            } catch (...) {
                errors[t] = std::current_exception();
            }
        };
        if (!start_thread(threads, on_thread))
            here.push_back(t);
    }
    auto on_this_thread = [&](std::size_t t) {
        try {
            share(t);
        } catch (...) {
            errors[t] = std::current_exception();
        }
    };
    for (const std::size_t t : here)
        on_this_thread(t);
    for (auto& th : threads)
        th.join();
    for (std::size_t t = 0; t < jobs; ++t)
        if (again[t])
            on_this_thread(t);
    for (const auto& e : errors)
        if (e)
            std::rethrow_exception(e);
}

} // namespace impactcert
