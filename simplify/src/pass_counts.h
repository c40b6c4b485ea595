// What the passes of the runs in this process did, for the benchmarks: how many passes, how many
// candidates the selection walks visited, and how the checks of the selected ones came out. Each
// run adds its counts once per pass, from the calling thread; concurrent runs add to the same
// counts.
#pragma once

#include <atomic>
#include <cstddef>

namespace ddsimp::detail {

struct PassCounts {
    std::atomic<size_t> passes{0};
    std::atomic<size_t> walked{0};  // candidates the selection walks visited (every round)
    std::atomic<size_t> taken{0};   // checked and taken
    std::atomic<size_t> waited{0};  // checked, and heavier than the pass takes (Simplifier::waits)
    std::atomic<size_t> refused{0}; // checked, and refused (topology, folds)

    void reset() {
        for (auto* count : {&passes, &walked, &taken, &waited, &refused})
            count->store(0, std::memory_order_relaxed);
    }
};

PassCounts& pass_counts();

} // namespace ddsimp::detail
