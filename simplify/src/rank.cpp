// A pass's ranking: the pool of candidates brought up to date (the dead out, the born merged in,
// in id order), every candidate's key, and the lightest share of them sorted. Each step runs in
// pieces of the pool on the threads, each piece writing only its own places, and the pieces are
// joined in order: the same pool and the same order on any number of threads.
#include "simplifier.h"

#include <algorithm>
#include <cstring>

namespace ddsimp {

using detail::kNone;
using detail::VertexKind;

namespace {

// Pieces of n items worth a thread each (one piece per kMinPiece items at most).
constexpr size_t kMinPiece = 4096;
size_t pieces_of(const detail::Parallel& parallel, size_t n) {
    return std::max<size_t>(1, parallel.pieces(n / kMinPiece));
}

} // namespace

uint8_t Simplifier::rank_member(Member& m) {
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    const uint32_t id = m.id;
    const uint32_t a = collapse ? mesh_.origin[id] : id;
    if (collapse) {
        const uint32_t t = mesh_.twin[id];
        if (a == kNone || (t != kNone && t < id)) return listed_[id] = 0, kDeadMember;
    } else if (mesh_.kind[id] == VertexKind::Dead) {
        return listed_[id] = 0, kDeadMember;
    }
    const uint32_t b = collapse ? mesh_.dest(id) : kNone;
    if (collapse ? !collapsible(id, a, b) : !removable(id)) return kLiveMember;
    // A key is computed again only if an end's star changed since (nothing else it reads can
    // change), so a pass costs a sweep, not a key per candidate.
    const uint32_t changed = std::max(rekey_[a], collapse ? rekey_[b] : uint32_t(0));
    if (m.keyed == kNever || changed > m.keyed) {
        m.key = collapse ? collapse_key(id) : removal_key(id), m.keyed = pass_;
        if (collapse) raised_[id] = 0;
    }
    return std::isinf(m.key.weight) ? kLiveMember : kCandidate;
}

size_t Simplifier::drop_dead(detail::Array<Member>& members, detail::Array<uint8_t>& status,
                             detail::LightestShare& lightest) {
    // Each piece moves its own to its front, then the pieces are moved together in order.
    const size_t n = members.size(), pieces = pieces_of(parallel_, n);
    std::vector<detail::LightestShare> shares(pieces);
    std::vector<size_t> kept(pieces);
    parallel_.for_each(
        pieces,
        [&](size_t p) {
            const size_t begin = p * n / pieces, end = (p + 1) * n / pieces;
            size_t k = begin;
            for (size_t i = begin; i < end; ++i) {
                if (status[i] == kDeadMember) continue;
                if (status[i] == kCandidate) shares[p].add(members[i].key);
                status[k] = status[i];
                members[k++] = members[i];
            }
            kept[p] = k - begin;
        },
        1);
    size_t total = 0;
    for (size_t p = 0; p < pieces; ++p) {
        const size_t begin = p * n / pieces;
        if (total != begin) {
            std::memmove(&members[total], &members[begin], kept[p] * sizeof(Member));
            std::memmove(&status[total], &status[begin], kept[p]);
        }
        total += kept[p];
        lightest.add(shares[p]);
    }
    members.resize(total);
    status.resize(total);
    return total;
}

void Simplifier::merge_born() {
    // In pieces of the merged pool: where each begins in the pool and in the born is found by a
    // binary search (a merge path), and each is merged from its back, in place: a member only
    // moves up. The piece before a piece overwrites the first members of its pool part (as many
    // as born come before it), so those are set aside first.
    const size_t old = pool_.size(), born = born_members_.size(), n = old + born;
    if (born == 0) return;
    pool_.resize(n), status_.resize(n);
    const size_t pieces = pieces_of(parallel_, n);
    // Born among the first o members of the merged pool.
    auto born_before = [&](size_t o) {
        size_t low = o > old ? o - old : 0, high = std::min(o, born);
        while (low < high) { // the least j with no born j that goes before pool member o - j - 1
            const size_t j = (low + high) / 2;
            if (born_members_[j].id < pool_[o - j - 1].id)
                low = j + 1;
            else
                high = j;
        }
        return low;
    };
    std::vector<size_t> first_born(pieces + 1), aside_at(pieces + 1, 0);
    for (size_t p = 0; p <= pieces; ++p) first_born[p] = born_before(p * n / pieces);
    for (size_t p = 1; p < pieces; ++p) aside_at[p + 1] = aside_at[p] + first_born[p];
    aside_.resize(aside_at[pieces]), aside_status_.resize(aside_at[pieces]);
    for (size_t p = 1; p < pieces; ++p) {
        const size_t from = p * n / pieces - first_born[p];
        std::copy_n(&pool_[from], first_born[p], &aside_[aside_at[p]]);
        std::copy_n(&status_[from], first_born[p], &aside_status_[aside_at[p]]);
    }
    parallel_.for_each(
        pieces,
        [&](size_t p) {
            const size_t begin = p * n / pieces;
            const size_t j0 = first_born[p], i0 = begin - j0;
            size_t k = (p + 1) * n / pieces, j = first_born[p + 1], i = k - j;
            // Pool member x of this piece, and its status: set aside below `begin`.
            auto member = [&](size_t x) -> const Member& {
                return x < begin ? aside_[aside_at[p] + x - i0] : pool_[x];
            };
            auto status = [&](size_t x) {
                return x < begin ? aside_status_[aside_at[p] + x - i0] : status_[x];
            };
            while (k > begin) {
                --k;
                if (j > j0 && (i == i0 || born_members_[j - 1].id > member(i - 1).id)) {
                    --j;
                    pool_[k] = born_members_[j], status_[k] = born_status_[j];
                } else {
                    --i;
                    status_[k] = status(i), pool_[k] = member(i);
                }
            }
        },
        1);
}

void Simplifier::collect_lightest(const detail::LightestShare& lightest) {
    // Counted per piece, then each piece written after the ones before it.
    const size_t n = pool_.size(), pieces = pieces_of(parallel_, n);
    auto kept = [&](size_t i) { return status_[i] == kCandidate && lightest.keeps(pool_[i].key); };
    std::vector<size_t> at(pieces + 1, 0);
    parallel_.for_each(
        pieces,
        [&](size_t p) {
            size_t count = 0;
            for (size_t i = p * n / pieces; i < (p + 1) * n / pieces; ++i) count += kept(i);
            at[p + 1] = count;
        },
        1);
    for (size_t p = 0; p < pieces; ++p) at[p + 1] += at[p];
    order_.resize(at[pieces]);
    parallel_.for_each(
        pieces,
        [&](size_t p) {
            size_t k = at[p];
            for (size_t i = p * n / pieces; i < (p + 1) * n / pieces; ++i)
                if (kept(i))
                    order_[k++] = detail::Candidate::make(pool_[i].key, uint32_t(i), pool_[i].id);
        },
        1);
}

double Simplifier::pass_share() const {
    // The last operations set a coarse level's error, so they are ranked more finely; the share
    // reads only the surface, never the target, so a run stays a prefix of any longer one. Only
    // a pass with candidates asks, so the input has triangles.
    const double left = double(mesh_.live_triangles) / double(record_.triangles_in_);
    return std::clamp(kPassShare * left / kFineBelow, kFinestShare, kPassShare);
}

bool Simplifier::rank_candidates(size_t& share) {
    // Every member of the pool, and every one born since the last pass, side by side: whether it
    // is live, and whether it is a candidate, with its key. Each writes only its own member and
    // id.
    status_.resize(pool_.size());
    const size_t swept = in_blocks(pool_.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) status_[i] = rank_member(pool_[i]);
    });
    if (swept < pool_.size()) return false;
    parallel_.sort(born_.begin(), born_.end());
    born_members_.resize(born_.size()), born_status_.resize(born_.size());
    const size_t born = in_blocks(born_.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            born_members_[i] = {born_[i], kNever, {}};
            born_status_[i] = rank_member(born_members_[i]);
        }
    });
    if (born < born_.size()) return false;
    born_.clear();
    // The pool without the dead, merged with the born in id order; its candidates counted by
    // key, then the lightest share of them collected in id order and sorted.
    detail::LightestShare lightest;
    drop_dead(pool_, status_, lightest);
    drop_dead(born_members_, born_status_, lightest);
    merge_born();
    share = lightest.total() == 0
                ? 0
                : std::max<size_t>(1, size_t(std::ceil(pass_share() * double(lightest.total()))));
    lightest.bound(share);
    collect_lightest(lightest);
    detail::sort_candidates(order_, scratch_, parallel_);
    return true;
}

} // namespace ddsimp
