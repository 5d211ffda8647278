// SPDX-License-Identifier: GPL-3.0-or-later
// allocation.cpp -- the global operator new and delete of the three programs, over malloc.
//
// The programs link mimalloc or jemalloc (CMakeLists.txt, IMPACTCERT_ALLOCATOR), which replace
// malloc and free. mimalloc would replace operator new as well: Debian builds it as C, where a
// failed `new` cannot throw and calls abort(). A memory cap (ulimit -v, a batch system's limit)
// must give std::bad_alloc, which run_program reports in one line with exit 3, never a signal.
// These definitions, in the program itself, take precedence over every shared library's: they
// take their memory from malloc (the linked allocator's) and follow the standard's loop, the
// new-handler, then std::bad_alloc. Not linked in sanitizer builds (AddressSanitizer brings its
// own).
#include <cstdlib>
#include <new>

namespace {

void* allocate(std::size_t size) {
    if (size == 0)
        size = 1;
    for (;;) {
        if (void* p = std::malloc(size))
            return p;
        const std::new_handler handler = std::get_new_handler();
        if (!handler)
            throw std::bad_alloc();
        handler();
    }
}

void* allocate_aligned(std::size_t size, std::align_val_t alignment) {
    const std::size_t a = static_cast<std::size_t>(alignment);
    if (size == 0)
        size = 1;
    for (;;) {
        void* p = nullptr;
        if (posix_memalign(&p, a < sizeof(void*) ? sizeof(void*) : a, size) == 0)
            return p;
        const std::new_handler handler = std::get_new_handler();
        if (!handler)
            throw std::bad_alloc();
        handler();
    }
}

template <class F> void* without_exception(F f) noexcept {
    try {
        return f();
    } catch (...) {
        return nullptr;
    }
}

} // namespace

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void* operator new(std::size_t size, std::align_val_t alignment) { return allocate_aligned(size, alignment); }
void* operator new[](std::size_t size, std::align_val_t alignment) { return allocate_aligned(size, alignment); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    return without_exception([&] { return allocate(size); });
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    return without_exception([&] { return allocate(size); });
}
void* operator new(std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    return without_exception([&] { return allocate_aligned(size, alignment); });
}
void* operator new[](std::size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    return without_exception([&] { return allocate_aligned(size, alignment); });
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
