// Large arrays in transparent huge pages. The engine's arrays hold hundreds of megabytes, written
// once and then read at random: in 4 KiB pages the first touch of every page is a fault of its
// own, and the random reads miss the TLB. Arrays of 2 MiB or more start on a 2 MiB boundary and
// their whole 2 MiB pages are marked MADV_HUGEPAGE, so that the kernel backs them with huge pages
// where its settings allow (Linux: transparent_hugepage `madvise` or `always`). An array's last
// part stays in small pages, so that its resident memory is what it touches. Smaller arrays, and
// every array where the system has no such advice, are allocated as usual.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <new>
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

} // namespace ddsimp::detail
