// A pass's ranking. ranked_ keeps every candidate, lightest first, from pass to pass; a ranking
// visits only the ids marked stale since the last one and ranks each again: the places of those
// that are no candidates now or whose keys changed are dropped, and the new candidates and new
// keys are sorted and merged in. Each step runs in pieces on the threads, each piece writing only
// its own places, and the pieces are joined in order: the same order on any number of threads.
#include "order_audit.h"
#include "simplifier.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <type_traits>

namespace ddsimp {

using detail::kNone;
using detail::VertexKind;

namespace {

// Pieces of n items worth a thread each (one piece per kMinPiece items at most).
constexpr size_t kMinPiece = 4096;
size_t pieces_of(const detail::Parallel& parallel, size_t n) {
    return std::max<size_t>(1, parallel.pieces(n / kMinPiece));
}

// Where piece p of n items in `pieces` begins.
size_t piece_begin(size_t p, size_t n, size_t pieces) {
    return p * n / pieces;
}

// A list that pieces fill on their threads, in piece order: count(p) says how many items piece p
// lists, resize(total) makes room for all, write(p, at) writes piece p's from `at` on.
template <class Count, class Resize, class Write>
void list_in_pieces(detail::Parallel& parallel, size_t pieces, Count&& count, Resize&& resize,
                    Write&& write) {
    std::vector<size_t> at(pieces + 1, 0);
    parallel.for_each(
        pieces, [&](size_t p) { at[p + 1] = count(p); }, 1);
    for (size_t p = 0; p < pieces; ++p) at[p + 1] += at[p];
    resize(at[pieces]);
    parallel.for_each(
        pieces, [&](size_t p) { write(p, at[p]); }, 1);
}

} // namespace

uint8_t Simplifier::rank_id(uint32_t id) {
    const uint8_t marks = stale_[id];
    stale_[id] = 0;
    if (options_.strategy == Strategy::VertexRemoval) {
        // Marked when its star changed, so its key may have: it is placed again.
        if (mesh_.kind[id] == VertexKind::Dead) return kKeyed;
        // A refused vertex is marked again when its star changes (refresh_around).
        if (!removable(id)) return kKeyed;
        return std::isinf(removal_key(id).weight) ? kKeyed : kKeyed | kIsCandidate;
    }
    const uint32_t a = mesh_.origin[id], t = mesh_.twin[id];
    if (a == kNone || (t != kNone && t < id)) return 0; // no live edge's id (a merge marks it)
    if (!collapsible(id, a, mesh_.dest(id))) {
        // A refusal that stands is marked again when a vertex it reads changes (forgive_around),
        // or, where one of them is complex (a star of several fans, which forgive_around does not
        // walk; there are few), visited again by every ranking.
        stale_[id] = marks & kKeyStale;
        if (fail_[id] == 0) return 0;
        const uint32_t reads[4] = {a, mesh_.dest(id), mesh_.origin[detail::prev(id)],
                                   t != kNone ? mesh_.origin[detail::prev(t)] : a};
        if (std::any_of(reads, reads + 4,
                        [&](uint32_t v) { return mesh_.kind[v] == VertexKind::Complex; })) {
            stale_[id] |= kStale, mark_block(id);
            return 0;
        }
        for (const uint32_t v : reads)
            std::atomic_ref<uint8_t>(refusal_near_[v]).store(1, std::memory_order_relaxed);
        return 0;
    }
    uint8_t ranked = 0;
    if (marks & kKeyStale) {
        edge_weight_[id] = collapse_weight(id), raised_[id] = 0;
        ranked = kKeyed;
    }
    return std::isinf(edge_weight_[id]) ? ranked : ranked | kIsCandidate;
}

detail::Key Simplifier::key_of(uint32_t id) const {
    if (options_.strategy == Strategy::VertexRemoval) return removal_key(id);
    return {edge_weight_[id], edge_length(id)}; // an end that moved marked it kKeyStale
}

void Simplifier::gather_stale() {
    // Two scans of the marked blocks' flags, a word at a time (most are clear): each piece counts
    // its stale ids, then writes them after the pieces before it and clears its blocks' marks.
    static_assert(kStale == 1, "the scan reads kStale as the low bit of each byte");
    const size_t n = stale_.size(), words = stale_blocks_.size();
    const size_t pieces = std::min(pieces_of(parallel_, n), words);
    constexpr size_t kIdsPerBlock = size_t(1) << kStaleBlockShift;
    // `clear`: the blocks' marks go once read.
    auto scan = [&](size_t p, bool clear, auto&& stale) {
        for (size_t w = piece_begin(p, words, pieces); w < piece_begin(p + 1, words, pieces); ++w) {
            for (uint64_t blocks = stale_blocks_[w]; blocks != 0; blocks &= blocks - 1) {
                const size_t begin = (64 * w + size_t(std::countr_zero(blocks))) * kIdsPerBlock;
                const size_t end = std::min(begin + kIdsPerBlock, n);
                size_t i = begin;
                constexpr uint64_t kLowBits = 0x0101010101010101u; // kStale of each of 8 ids
                for (; i + sizeof(uint64_t) <= end; i += sizeof(uint64_t)) {
                    uint64_t word;
                    std::memcpy(&word, &stale_[i], sizeof word);
                    for (word &= kLowBits; word != 0; word &= word - 1)
                        stale(uint32_t(i + size_t(std::countr_zero(word)) / 8));
                }
                for (; i < end; ++i)
                    if (stale_[i] & kStale) stale(uint32_t(i));
            }
            if (clear) stale_blocks_[w] = 0;
        }
    };
    list_in_pieces(
        parallel_, pieces,
        [&](size_t p) {
            size_t count = 0;
            scan(p, false, [&](uint32_t) { ++count; });
            return count;
        },
        [&](size_t total) { stale_ids_.resize(total); },
        [&](size_t p, size_t k) { scan(p, true, [&](uint32_t id) { stale_ids_[k++] = id; }); });
}

void Simplifier::drop_stale() {
    // Each piece moves its own to its front, then the pieces are moved together in order.
    const size_t n = ranked_.size(), pieces = pieces_of(parallel_, n);
    std::vector<size_t> kept(pieces);
    parallel_.for_each(
        pieces,
        [&](size_t p) {
            constexpr size_t kAhead = 16; // the flags are scattered: fetch them ahead
            const size_t begin = piece_begin(p, n, pieces), end = piece_begin(p + 1, n, pieces);
            size_t k = begin;
            for (size_t i = begin; i < end; ++i) {
                if (i + kAhead < end) __builtin_prefetch(&placed_[ranked_[i + kAhead].id]);
                if (placed_[ranked_[i].id] != kDropped) ranked_[k++] = ranked_[i];
            }
            kept[p] = k - begin;
        },
        1);
    size_t total = 0;
    for (size_t p = 0; p < pieces; ++p) {
        const size_t begin = piece_begin(p, n, pieces);
        if (total != begin)
            std::memmove(&ranked_[total], &ranked_[begin], kept[p] * sizeof(detail::Candidate));
        total += kept[p];
    }
    ranked_.resize(total);
}

double Simplifier::pass_share() const {
    // The last operations set a coarse level's error, so they are ranked more finely; the share
    // reads only the surface, never the target, so a run stays a prefix of any longer one. Only
    // a pass with candidates asks, so the input has triangles.
    const double left = double(mesh_.live_triangles) / double(record_.triangles_in_);
    return std::clamp(kPassShare * left / kFineBelow, kFinestShare, kPassShare);
}

bool Simplifier::rank_candidates(size_t& share) {
    // The stale ids (the first time: every id), each ranked again: whether its place in the order
    // goes, and whether it gets a new one.
    const bool all = all_stale_;
    all_stale_ = false;
    if (!all) gather_stale();
    const size_t count = all ? stale_.size() : stale_ids_.size();
    const uint32_t* const ids = stale_ids_.data(); // by value: kept in registers in the loops
    auto id_at = [all, ids](size_t i) { return all ? uint32_t(i) : ids[i]; };
    detail::assign_on_threads(fresh_status_, count, 0, parallel_);
    // An edge's key reads its ends' records and quadrics, scattered over the surface: fetched a
    // few ids ahead (a prefetch changes no result).
    constexpr size_t kKeyAhead = 8;
    const bool collapse = options_.strategy == Strategy::EdgeCollapse;
    // The loop made once for every id (the first ranking, in id order, where half the ids are an
    // edge's upper half-edge, no edge's id, whose key is not fetched) and once for the listed.
    auto visit = [&](size_t begin, size_t end, auto id_of, auto every) {
        for (size_t i = begin; i < end; ++i) {
            if (collapse && i + 2 * kKeyAhead < end) {
                const uint32_t ahead = id_of(i + 2 * kKeyAhead);
                __builtin_prefetch(&mesh_.origin[ahead]), __builtin_prefetch(&edge_weight_[ahead]);
                __builtin_prefetch(&fail_[ahead]), __builtin_prefetch(&placed_[ahead]);
            }
            if (collapse && i + kKeyAhead < end) {
                const uint32_t ahead = id_of(i + kKeyAhead), a = mesh_.origin[ahead];
                const bool upper = every && mesh_.twin[ahead] < ahead; // kNone is not below
                if ((stale_[ahead] & kKeyStale) && a != kNone && !upper)
                    prefetch_key(a, mesh_.dest(ahead));
            }
            const uint32_t id = id_of(i);
            const uint8_t rank = rank_id(id);
            const uint8_t placed = placed_[id];
            const bool moved = placed == kMoved || (rank & kKeyed);
            const bool candidate = rank & kIsCandidate;
            if (placed != kUnplaced && (moved || !candidate)) placed_[id] = kDropped;
            fresh_status_[i] = candidate && (placed == kUnplaced || moved);
        }
    };
    const size_t ranked = in_blocks(count, [&](size_t begin, size_t end) {
        if (all)
            visit(
                begin, end, [](size_t i) { return uint32_t(i); }, std::true_type{});
        else
            visit(
                begin, end, [ids](size_t i) { return ids[i]; }, std::false_type{});
    });
    if (ranked < count) return false;
    // Some places go after nearly every pass (the collapsed edges' own, at least; a removed
    // half-edge's are marked kDropped by its collapse, with no visit): no count of them is kept.
    drop_stale();
    // The new places in id order (counted per piece, then each piece written after the ones
    // before it), sorted and merged in.
    const size_t pieces = pieces_of(parallel_, count);
    list_in_pieces(
        parallel_, pieces,
        [&](size_t p) {
            size_t placed = 0;
            for (size_t i = piece_begin(p, count, pieces); i < piece_begin(p + 1, count, pieces);
                 ++i)
                placed += fresh_status_[i];
            return placed;
        },
        [&](size_t total) { detail::assign_on_threads(fresh_, total, {}, parallel_); },
        [&](size_t p, size_t k) {
            const size_t end = piece_begin(p + 1, count, pieces);
            for (size_t i = piece_begin(p, count, pieces); i < end; ++i) {
                if (collapse && i + kKeyAhead < end && fresh_status_[i + kKeyAhead]) {
                    const uint32_t ahead = id_at(i + kKeyAhead);
                    __builtin_prefetch(mesh_.position_of(mesh_.origin[ahead]));
                    __builtin_prefetch(mesh_.position_of(mesh_.dest(ahead)));
                }
                const uint32_t id = id_at(i);
                if (fresh_status_[i]) {
                    fresh_[k++] = detail::Candidate::make(key_of(id), id);
                    placed_[id] = kPlaced;
                } else if (placed_[id] == kDropped) {
                    placed_[id] = kUnplaced;
                }
            }
        });
    // Many at once (the first ranking: all of them) are sorted in place, which needs no second
    // array of their size; fewer by the counting passes, in a scratch space of their size.
    if (fresh_.size() > ranked_.size() / kSortedInPlace)
        detail::sort_candidates_in_place(fresh_, parallel_);
    else
        detail::sort_candidates(fresh_, scratch_, parallel_);
    if (ranked_.empty()) // the first ranking: no merge, and no second array of every candidate
        ranked_.swap(fresh_);
    else
        detail::merge_candidates(ranked_, fresh_);
    if (detail::OrderAudit& audit = detail::order_audit();
        audit.on.load(std::memory_order_relaxed)) {
        audit.rankings.fetch_add(1, std::memory_order_relaxed);
        if (!order_is_afresh()) audit.mismatches.fetch_add(1, std::memory_order_relaxed);
    }
    // The candidates grow fewer as the surface coarsens: the order keeps its room (a merge never
    // moves it) but not the pages past its end. The rankings grow smaller too: their scratch
    // keeps its room for the next one, its pages given back once a ranking visits half as many
    // ids as at the last release.
    detail::release_unused(ranked_);
    if (scratch_release_.due(count)) {
        using detail::clear_and_release;
        clear_and_release(fresh_status_), clear_and_release(fresh_);
        clear_and_release(stale_ids_), clear_and_release(scratch_);
    }
    share = ranked_.empty()
                ? 0
                : std::max<size_t>(1, size_t(std::ceil(pass_share() * double(ranked_.size()))));
    return true;
}

} // namespace ddsimp
