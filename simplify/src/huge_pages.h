// Large arrays in transparent huge pages. The engine's arrays hold hundreds of megabytes, written
// once and then read at random: in 4 KiB pages the first touch of every page is a fault of its
// own, and the random reads miss the TLB. Arrays of 2 MiB or more start on a 2 MiB boundary and
// their whole 2 MiB pages are marked MADV_HUGEPAGE, so that the kernel backs them with huge pages
// where its settings allow (Linux: transparent_hugepage `madvise` or `always`). An array's last
// part stays in small pages, so that its resident memory is what it touches. Smaller arrays, and
// every array where the system has no such advice, are allocated as usual. assign_on_threads
// fills a large array with its pages first touched on the engine's threads; release_unused and
// clear_and_release give back the pages of scratch arrays that keep their room for a later,
// smaller use.
#pragma once

#include "parallel.h"

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <vector>

namespace ddsimp::detail {

template <class T> struct HugePageAllocator {
    using value_type = T;
    static constexpr size_t kHugePage = size_t(2) << 20;

    HugePageAllocator() = default;
    template <class U> HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    T* allocate(size_t n) {
        const size_t bytes = n * sizeof(T);
        if (!huge(bytes)) return static_cast<T*>(::operator new(bytes));
        void* p = ::operator new (bytes, std::align_val_t{kHugePage});
#ifdef MADV_HUGEPAGE
        madvise(p, bytes & ~(kHugePage - 1), MADV_HUGEPAGE); // only advice: no error to handle
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t n) noexcept {
        if (huge(n * sizeof(T)))
            ::operator delete (p, std::align_val_t{kHugePage});
        else
            ::operator delete(p);
    }
    template <class U> bool operator==(const HugePageAllocator<U>&) const noexcept {
        return true;
    }

private:
    static bool huge(size_t bytes) {
#ifdef MADV_HUGEPAGE
        return bytes >= kHugePage;
#else
        return false;
#endif
    }
};

// A vector whose storage goes to huge pages once it is large (see above).
template <class T> using Array = std::vector<T, HugePageAllocator<T>>;

// Gives the whole pages within [begin, end) back to the system: they read as zeros when written
// again, so only what is in use stays resident.
inline void release_pages(const void* begin, const void* end) {
    constexpr uintptr_t kPage = 4096;
    const uintptr_t first = (reinterpret_cast<uintptr_t>(begin) + kPage - 1) & ~(kPage - 1);
    const uintptr_t last = reinterpret_cast<uintptr_t>(end) & ~(kPage - 1);
    if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
}

// The pages past an array's size given back: an array that shrinks and later grows in place keeps
// only the pages it uses resident.
template <class T> void release_unused(Array<T>& array) {
    release_pages(array.data() + array.size(), array.data() + array.capacity());
}

// Empties a scratch array that keeps its room for the next use, its pages given back meanwhile.
template <class T> void clear_and_release(Array<T>& array) {
    array.clear();
    release_unused(array);
}

// When to give back the pages of scratch arrays whose use shrinks over a run: once a use has
// fallen below half of the use at the last release. The pages written again after releases are
// then at most about twice the first use, where releasing after every use would fault them in
// again each time.
class HalvingRelease {
public:
    bool due(size_t used) {
        if (2 * used >= last_) return false;
        last_ = used;
        return true;
    }

private:
    size_t last_ = SIZE_MAX;
};

// array = n copies of value, its fresh pages first written on the threads: the first write to a
// page is a fault in which the kernel clears it, serial work for one thread otherwise.
template <class T>
void assign_on_threads(Array<T>& array, size_t n, const std::type_identity_t<T>& value,
                       Parallel& parallel) {
    array.clear();
    array.reserve(n);
    constexpr size_t kPage = 4096;
    volatile char* bytes = reinterpret_cast<char*>(array.data()); // not dropped for assign's
    parallel.for_range((n * sizeof(T) + kPage - 1) / kPage,
                       [&](size_t begin, size_t end) {
                           for (size_t page = begin; page < end; ++page) bytes[page * kPage] = 0;
                       },
                       HugePageAllocator<T>::kHugePage / kPage);
    array.assign(n, value);
}

} // namespace ddsimp::detail
