// Progress and cancellation for the stages outside the passes: the set-up and a level's fit.
// While a watch is on (Parallel::Watching), the stage's parallel loops run in blocks of a few
// milliseconds of work; after each block, on the thread that started the stage, the watch calls
// Options::progress with the fraction the stage has reached. Once that returns false the watch is
// stopped: the loops skip what is left, and the stage, which checks stopped() after each loop
// whose results it goes on to read, gives up. A watch that only reports (`skips` false) lets the
// loops finish: for a stage whose result a cancelled run still needs.
#pragma once

#include <algorithm>
#include <atomic>
#include <functional>
#include <thread>

namespace ddsimp::detail {

class StageWatch {
public:
    // Reports the stage's fractions as from + part (to - from); `progress` may be empty (then the
    // watch never stops).
    StageWatch(const std::function<bool(double)>& progress, double from, double to,
               bool skips = true)
        : progress_(progress), from_(from), to_(to), skips_(skips),
          caller_(std::this_thread::get_id()) {}

    // The part of the stage done, in [0, 1]; never lowers what was reached.
    void reach(double part) { part_ = std::max(part_, std::clamp(part, 0.0, 1.0)); }

    // Between blocks: on the stage's own thread, reports progress. False once stopped.
    bool check() {
        if (stopped()) return false;
        if (!progress_ || std::this_thread::get_id() != caller_) return true;
        if (!progress_(from_ + part_ * (to_ - from_))) stopped_.store(true);
        return !stopped();
    }
    bool stopped() const { return stopped_.load(std::memory_order_relaxed); }
    // Whether there is anything to report to: without a callback the loops run whole.
    bool reports() const { return bool(progress_); }
    // Whether the loops skip their work: stopped, and not only reporting.
    bool skipping() const { return skips_ && stopped(); }

private:
    const std::function<bool(double)>& progress_;
    double from_, to_, part_ = 0;
    bool skips_;
    std::thread::id caller_;
    std::atomic<bool> stopped_{false};
};

} // namespace ddsimp::detail
