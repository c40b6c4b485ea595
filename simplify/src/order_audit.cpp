// The kept order against a ranking of every id afresh (order_audit.h).
#include "order_audit.h"

#include "simplifier.h"

#include <algorithm>
#include <cmath>

namespace ddsimp {

namespace detail {

OrderAudit& order_audit() {
    static OrderAudit audit;
    return audit;
}

} // namespace detail

bool Simplifier::order_is_afresh() const {
    // Every id's status and key as the first ranking would find them now. A key that a plan
    // raised (raised_) cannot be made afresh: it is the weight the plan found.
    std::vector<detail::Candidate> afresh;
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    for (uint32_t id = 0; id < stale_.size(); ++id) {
        detail::Key key;
        if (collapse) {
            const uint32_t a = mesh_.origin[id], t = mesh_.twin[id];
            if (a == detail::kNone || (t != detail::kNone && t < id) ||
                !collapsible(id, a, mesh_.dest(id)))
                continue;
            key = {raised_[id] ? edge_weight_[id] : collapse_weight(id), edge_length(id)};
        } else {
            if (!removable(id)) continue; // a dead vertex is not removable
            key = removal_key(id);
        }
        if (!std::isinf(key.weight)) afresh.push_back(detail::Candidate::make(key, id));
    }
    std::sort(afresh.begin(), afresh.end());
    return std::equal(afresh.begin(), afresh.end(), ranked_.begin(), ranked_.end());
}

} // namespace ddsimp
