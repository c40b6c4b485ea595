// Parallel loops on a fixed number of threads (oneTBB), for the engine's stages. Every loop
// writes each index's results to that index's own place, so what a stage computes does not depend
// on how the range is split: the same bytes for any thread count.
// Under ThreadSanitizer the loops run on plain std::threads instead: Debian's oneTBB is not built
// for it, so the sanitizer would not see its synchronisation, while thread start and join it sees.
#pragma once

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_sort.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace ddsimp::detail {

class Parallel {
public:
    // threads == 0: every hardware thread.
    explicit Parallel(int threads)
        : threads_(threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()))),
          arena_(threads_) {}
    int threads() const { return threads_; }

    // f(begin, end) over [0, n) in pieces of at least `grain` indices.
    template <class F> void for_range(size_t n, F&& f, size_t grain = 256) {
        if (threads_ <= 1 || n <= grain) {
            if (n > 0) f(size_t(0), n);
            return;
        }
#if defined(__SANITIZE_THREAD__)
        std::vector<std::thread> pool;
        const size_t chunk = (n + size_t(threads_) - 1) / size_t(threads_);
        for (size_t begin = 0; begin < n; begin += chunk)
            pool.emplace_back([&, begin] { f(begin, std::min(n, begin + chunk)); });
        for (std::thread& t : pool) t.join();
        return;
#endif
        arena_.execute([&] {
            oneapi::tbb::parallel_for(
                oneapi::tbb::blocked_range<size_t>(0, n, grain),
                [&](const oneapi::tbb::blocked_range<size_t>& r) { f(r.begin(), r.end()); });
        });
    }
    // f(i) for every i in [0, n).
    template <class F> void for_each(size_t n, F&& f, size_t grain = 256) {
        for_range(
            n,
            [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) f(i);
            },
            grain);
    }

    // Sorts [begin, end) of distinct values, so that the result is the one order.
    template <class It> void sort(It begin, It end) {
#if defined(__SANITIZE_THREAD__)
        std::sort(begin, end);
        return;
#endif
        if (threads_ <= 1) return std::sort(begin, end);
        arena_.execute([&] { oneapi::tbb::parallel_sort(begin, end); });
    }

    // produce() on the calling thread while every other thread runs consume(), then consume() on
    // the calling thread too: a serial stage and the work it hands out, side by side. consume()
    // returns once produce() is over and nothing is left for it.
    template <class P, class C> void beside(P&& produce, C&& consume) {
        if (threads_ <= 1) {
            produce();
            consume(true);
            return;
        }
#if defined(__SANITIZE_THREAD__)
        std::vector<std::thread> pool;
        for (int i = 1; i < threads_; ++i) pool.emplace_back([&] { consume(false); });
        produce();
        consume(true);
        for (std::thread& t : pool) t.join();
        return;
#endif
        arena_.execute([&] {
            oneapi::tbb::task_group others;
            for (int i = 1; i < threads_; ++i) others.run([&] { consume(false); });
            produce();
            consume(true);
            others.wait();
        });
    }
    // f(begin, end, piece) over [0, n) in pieces(n) pieces, one per thread, numbered in order:
    // for a gather that scans all of its input and keeps what falls in its piece, so that each
    // index sums its terms in input order, or for lists that are joined in piece order.
    size_t pieces(size_t n) const {
        return std::min(n, size_t(threads_));
    }
    template <class F> void for_pieces(size_t n, F&& f) {
        const size_t count = pieces(n);
        for_each(
            count, [&](size_t i) { f(i * n / count, (i + 1) * n / count, i); }, 1);
    }

private:
    int threads_;
    oneapi::tbb::task_arena arena_;
};

} // namespace ddsimp::detail
