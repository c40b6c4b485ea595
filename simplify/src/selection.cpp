// A pass's selection: among the pass's candidates, in rank order, every one whose neighbourhood
// no candidate selected before it touches (an independent set, the same for any thread count;
// edge collapses may share ring vertices, see ring_shared_). The walk goes through the
// candidates one by one and stops at the first vertex that is not free. It is bound by memory
// latency, so it fetches the candidates ahead, and a second round walks only the candidates that a
// refused or waiting one blocked: one that a taken operation blocked cannot be selected in this
// pass.
#include "simplifier.h"

namespace ddsimp {

using detail::kNone;

template <class F> bool Simplifier::walk_neighbourhood(const Ends& ends, F&& visit) const {
    // A walk around one star: each step visits the next neighbour (on a boundary, last the one
    // that closes the fan) and loads the half-edge after it.
    struct Star {
        uint32_t h, start, last = kNone;
        bool over = false;
    };
    auto step = [&](Star& s) {
        if (s.h == kNone || (s.h == s.start && s.last != kNone)) {
            s.over = true;
            const uint32_t closing = detail::prev(s.last); // on a boundary, the fan's other side
            return mesh_.twin[closing] != kNone || visit(mesh_.origin[closing]);
        }
        if (!visit(mesh_.dest(s.h))) return false;
        s.last = s.h;
        s.h = mesh_.twin[detail::prev(s.h)];
        return true;
    };
    if (options_.strategy == Strategy::VertexRemoval) {
        Star s{mesh_.out[ends.a], mesh_.out[ends.a]};
        if (!visit(ends.a)) return false;
        while (!s.over)
            if (!step(s)) return false;
        return true;
    }
    // An edge's two stars step by step side by side: each step waits on its own star's last
    // load only. The order of the visits does not change what is selected (see select).
    const auto [a, b] = ends;
    Star sa{mesh_.out[a], mesh_.out[a]}, sb{mesh_.out[b], mesh_.out[b]};
    if (!visit(a) || !visit(b)) return false;
    while (!sa.over || !sb.over) {
        if (!sa.over && !step(sa)) return false;
        if (!sb.over && !step(sb)) return false;
    }
    return true;
}

bool Simplifier::select(uint32_t pass_stamp, uint32_t round_stamp, size_t first) {
    selected_.clear();
    blocked_.clear();
    blocked_by_.clear();
    uint32_t near[kMaxNeighbourhood];
    const size_t count = pending_.size();
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    // The walk's loads depend on one another (the candidate's edge, its ends, their records),
    // each a miss in a large surface; so the candidates ahead are fetched a stage at a time, each
    // stage reading what the one before fetched.
    constexpr size_t kAhead = 8;
    auto id_at = [&](size_t j) { return ranked_[pending_[j]].id; };
    auto ends_at = [&](size_t j) { return share_ends_[pending_[j]]; };
    // Held by an operation taken in an earlier round of this pass (their checks are done).
    auto taken = [&](const Hold& hold) {
        return hold.stamp >= pass_stamp && hold.stamp != round_stamp &&
               checked_[hold.holder & ~kShared] == Check::Taken;
    };
    struct Over { // the checks beside the walk learn that it is over, however it ends
        Simplifier& s;
        ~Over() { s.publish_selected(true); }
    } over{*this};
    for (size_t j = 0; j < count; ++j) {
        if (j > 0 && j % kBlock == 0 && !checkpoint()) return false;
        if (j + 2 * kAhead < count) {
            if (collapse)
                __builtin_prefetch(&share_ends_[pending_[j + 2 * kAhead]]);
            else
                __builtin_prefetch(&mesh_.out[id_at(j + 2 * kAhead)]);
        }
        if (j + kAhead < count) {
            if (collapse) {
                const auto [a, b] = ends_at(j + kAhead);
                __builtin_prefetch(&busy_[a]), __builtin_prefetch(&busy_[b]);
                __builtin_prefetch(&mesh_.out[a]), __builtin_prefetch(&mesh_.out[b]);
            } else {
                __builtin_prefetch(&busy_[id_at(j + kAhead)]);
            }
        }
        if (j + kAhead / 2 < count) { // the first triangle of each star
            auto fetch_star = [&](uint32_t v) {
                const uint32_t h = mesh_.out[v];
                __builtin_prefetch(&mesh_.origin[h]), __builtin_prefetch(&mesh_.twin[h]);
            };
            if (collapse) {
                const auto [a, b] = ends_at(j + kAhead / 2);
                fetch_star(a), fetch_star(b);
            } else {
                fetch_star(id_at(j + kAhead / 2));
            }
        }
        const uint32_t rank = pending_[j];
        const Ends ends = collapse ? share_ends_[rank] : Ends{id_at(j), id_at(j)};
        // An edge's far end first: what holds either end shows before the walk reaches it.
        // Which vertex shows a candidate blocked or out does not change what is selected: nor
        // does which holder it records as its blocker, since one that a taken operation blocks
        // too is out in the next round anyway.
        if (collapse) {
            const Hold& far = busy_[ends.b];
            if (taken(far)) continue;
            if (far.stamp == round_stamp) {
                blocked_.push_back(rank), blocked_by_.push_back(far.holder & ~kShared);
                continue;
            }
        }
        size_t n = 0;
        uint32_t blocker = kNone;
        // An edge's ring vertices may be shared (see ring_shared_): only its ends are looked at.
        auto ring_vertex = [&](uint32_t v) { return collapse && v != ends.a && v != ends.b; };
        const bool free = walk_neighbourhood(ends, [&](uint32_t v) {
            if (n == kMaxNeighbourhood) return false;
            if (!ring_vertex(v)) {
                const Hold& hold = busy_[v];
                if (taken(hold)) return false;
                if (hold.stamp == round_stamp) return blocker = hold.holder & ~kShared, false;
            }
            near[n++] = v;
            return true;
        });
        if (free) {
            const uint32_t holder = uint32_t(first + selected_.size());
            for (size_t i = 0; i < n; ++i) {
                Hold& hold = busy_[near[i]];
                if (ring_vertex(near[i])) {
                    if (taken(hold)) { // next to a taken operation: it stays so
                        hold.holder |= kShared;
                        continue;
                    }
                    if (hold.stamp == round_stamp) {
                        if ((hold.holder & ~kShared) != holder) {
                            hold.holder |= kShared;
                            ring_shared_.push_back({near[i], holder});
                        }
                        continue;
                    }
                }
                hold = {round_stamp, holder};
            }
            selected_.push_back(rank);
            publish_selected(false);
        } else if (blocker != kNone) {
            blocked_.push_back(rank);
            blocked_by_.push_back(blocker);
        }
    }
    return true;
}

void Simplifier::hold_for_taken() {
    for (const auto& [v, holder] : ring_shared_)
        if (checked_[holder] == Check::Taken &&
            checked_[busy_[v].holder & ~kShared] != Check::Taken)
            busy_[v].holder = holder | kShared;
    ring_shared_.clear();
}

void Simplifier::pend_blocked() {
    pending_.clear();
    for (size_t j = 0; j < blocked_.size(); ++j)
        if (checked_[blocked_by_[j]] != Check::Taken) pending_.push_back(blocked_[j]);
}

} // namespace ddsimp
