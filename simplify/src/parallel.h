// Parallel loops on a fixed number of threads (oneTBB), for the engine's stages. Every loop
// writes each index's results to that index's own place, so what a stage computes does not depend
// on how the range is split: the same bytes for any thread count.
// Under ThreadSanitizer the loops run on plain std::threads instead: Debian's oneTBB is not built
// for it, so the sanitizer would not see its synchronisation, while thread start and join it sees.
// While a StageWatch is on (Watching), the loops run in blocks and check it between them.
#pragma once

#include "stage_watch.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
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

    // The watch the loops check while an instance lives (one at a time).
    class Watching {
    public:
        Watching(Parallel& parallel, StageWatch& watch) : parallel_(parallel) {
            parallel_.watch_ = &watch;
        }
        ~Watching() { parallel_.watch_ = nullptr; }
        Watching(const Watching&) = delete;
        Watching& operator=(const Watching&) = delete;

    private:
        Parallel& parallel_;
    };
    // Whether the watch on has been stopped: the loops since have skipped their work.
    bool stopped() const { return watch_ && watch_->skipping(); }
    // Checks the watch on (a stage's serial loop calls it every block of its own); false once
    // stopped.
    bool check() { return !watch_ || watch_->check(); }
    // The part of its stage done (StageWatch::reach).
    void reach(double part) {
        if (watch_) watch_->reach(part);
    }

    // f(begin, end) over [0, n) in pieces of at least `grain` indices. With a watch on that
    // reports: in blocks of kBlockGrains grains per thread, the watch checked after each; none
    // once it is stopped.
    template <class F> void for_range(size_t n, F&& f, size_t grain = 256) {
        if (!watch_ || !watch_->reports()) return run_range(0, n, f, grain);
        const size_t block = grain * kBlockGrains * size_t(threads_);
        for (size_t begin = 0; begin < n && !watch_->skipping(); begin += block) {
            run_range(begin, std::min(n, begin + block), f, grain);
            watch_->check();
        }
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
    // A loop's grain is at most about a millisecond of work: a block, eight per thread, some
    // milliseconds.
    static constexpr size_t kBlockGrains = 8;

    template <class F> void run_range(size_t begin, size_t end, F& f, size_t grain) {
        const size_t n = end - begin;
        if (threads_ <= 1 || n <= grain) {
            if (n > 0) f(begin, end);
            return;
        }
#if defined(__SANITIZE_THREAD__)
        std::vector<std::thread> pool;
        const size_t chunk = (n + size_t(threads_) - 1) / size_t(threads_);
        for (size_t from = begin; from < end; from += chunk)
            pool.emplace_back([&, from] { f(from, std::min(end, from + chunk)); });
        for (std::thread& t : pool) t.join();
        return;
#endif
        arena_.execute([&] {
            oneapi::tbb::parallel_for(
                oneapi::tbb::blocked_range<size_t>(begin, end, grain),
                [&](const oneapi::tbb::blocked_range<size_t>& r) { f(r.begin(), r.end()); });
        });
    }

    int threads_;
    oneapi::tbb::task_arena arena_;
    StageWatch* watch_ = nullptr;
};

} // namespace ddsimp::detail
