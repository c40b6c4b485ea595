// A check for the tests: after each ranking, whether the order kept between passes is the order
// that ranking every id afresh gives (Simplifier::order_is_afresh). Off unless a test turns it on;
// it then costs a whole ranking per pass.
#pragma once

#include <atomic>
#include <cstddef>

namespace ddsimp::detail {

struct OrderAudit {
    std::atomic<bool> on{false};
    // Rankings audited, and those whose kept order differed from the fresh one.
    std::atomic<size_t> rankings{0}, mismatches{0};
};

// The one audit of the process: the runs of every thread add to its counts.
OrderAudit& order_audit();

} // namespace ddsimp::detail
