// One simplification run: the weights, the passes, the two strategies and the record they write.
// Pipeline: build the half-edge mesh -> classify vertices -> weigh -> per pass: rank again the
// candidates the last pass changed (the order of all candidates is kept between passes), select
// in rank order from the lightest share those whose neighbourhoods no lighter selected one
// touches (an independent set), check them on the untouched surface, apply the ones that pass,
// record them in key order -> repeat until the target. Ranking, checks and application run on
// Options::threads threads; the output does not depend on it.
#pragma once

#include "ddsimp/ddsimp.h"
#include "error_quadric.h"
#include "parallel.h"
#include "pass_order.h"
#include "weights.h"
#include "working_mesh.h"

#include <algorithm>
#include <atomic>

namespace ddsimp {

class Simplifier {
public:
    // `surface` must have passed `validate` and must outlive run(). The set-up calls
    // Options::progress(0) every few milliseconds of work; if that asks to stop, run() records
    // no operation.
    Simplifier(const Surface& surface, const Options& options, const RepairReport& repairs);
    // The record of the run; the points the collapses made (with their data, 3 + the fields'
    // components per point) into `made_points`, for the record's vertices (progressive_record.cpp
    // appends them to the input's once this object and its working memory are gone).
    ProgressiveRecord run(std::vector<float>& made_points);

private:
    static constexpr size_t kMaxValence = 64;
    // A collapse may not make a vertex with more neighbours than this: hubs of many thin
    // triangles are bad for rendering and interpolation alike.
    static constexpr size_t kMaxNewValence = 24;
    // The error quadrics' geometric error weighs at least this much, so that at alpha = 0
    // the quadrics still say where the surface is. A reader sees the data where the reduced
    // surface passes; with the data's error alone, collapses cut creases and move points off
    // the surface for nothing, and the data goes with them. 0.2 is the least weight that keeps
    // the data error at alpha = 0 within the peers' (docs/algorithm.md).
    static constexpr double kMinGeometryWeight = 0.2;

    // What a collapse of the edge `halfedge` (from `keep` to `gone`, both replaced by a new
    // vertex) will do; filled by plan_collapse.
    struct CollapsePlan {
        uint32_t halfedge;
        detail::Vec3 point;
        double along; // position of `point` along the edge, for the data
        double error; // Terms::ErrorQuadrics: the error of both ends at `point`
        // Terms::ErrorQuadrics: what `error` misses: the retraction (retraction_scale) and the
        // error against the present triangles (star_error). At least that much, and exactly that
        // unless `error + retraction` came out within plan_collapse's `taken_within`.
        double retraction;
        uint32_t refused_at; // on a refusal: the half-edge of the triangle that would fold
    };
    // Where a re-triangulation passes the removed vertex: the corners of the new triangle there
    // (indices into the ring) with v's barycentric weights in it; for a boundary ear, its two
    // ends, half each. None (count 0) without the error quadrics.
    struct Cover {
        uint8_t corner[3];
        double weight[3];
        size_t count = 0;
        // A boundary ear (no new triangle: its two ends are joined).
        static Cover ear(size_t ring_size) {
            return {{0, uint8_t(ring_size - 1), 0}, {0.5, 0.5, 0}, 2};
        }
    };
    // What applying a removal needs: the star and its re-triangulation.
    struct Removal {
        uint32_t vertex;
        size_t ring_size;
        bool boundary;
        uint32_t ring[kMaxValence];
        uint32_t star[kMaxValence];       // the star's triangle slots, in ring order
        uint32_t outer_twin[kMaxValence]; // twin of polygon edge i (ring[i] -> ring[i+1])
        uint8_t outer_line[kMaxValence];
        size_t new_count;
        uint8_t triangles[kMaxValence][3];  // new triangles as indices into ring
        int feature_a = -1, feature_b = -1; // a feature line's two ends (indices into ring)
        Cover cover;                        // where the new triangles pass v
        // The triangle slots it rewrites (the record's writes): its star's, on a boundary one
        // fewer than its ring.
        size_t slots() const { return boundary ? ring_size - 1 : ring_size; }
    };
    // A pass's removals that their checks took, each packed into the room its ring needs: a
    // Removal has room for kMaxValence neighbours (1.1 kB), a typical one needs 150 bytes, so the
    // pages a pass writes follow the removals it takes (removal_store.cpp). One slot per selected
    // candidate, added by the selection walk in selection order; checks on any thread fill
    // distinct slots.
    class RemovalStore {
    public:
        RemovalStore() = default;
        RemovalStore(const RemovalStore&) = delete;
        RemovalStore& operator=(const RemovalStore&) = delete;
        ~RemovalStore();
        // Empty, with room for `slots` slots and each slot's largest removal (reserved, not
        // written, until a check stores one).
        void reset(size_t slots);
        // Empty, the pages of the removals stored given back (the room stays reserved).
        void release();
        void add_slot() { at_.push_back(kEmpty); }
        size_t size() const { return at_.size(); }
        // Stores a taken removal in `slot`.
        void put(size_t slot, const Removal& removal);
        // Unpacks the removal of `slot` into `removal` (what apply_removal reads).
        void get(size_t slot, Removal& removal) const;
        // The triangle slots the removal of `slot` rewrites (Removal::slots) and the triangles it
        // makes (Removal::new_count).
        size_t slots_of(size_t slot) const;
        size_t new_count_of(size_t slot) const;

    private:
        static constexpr size_t kEmpty = ~size_t(0);
        // Words of a removal's header (vertex; ring size, new triangles, boundary, the feature
        // ends, the cover's count and corners; the cover's three weights).
        static constexpr size_t kHeader = 4 + 6;
        static size_t words_for(size_t ring_size, size_t new_count);
        // The sizes in the header of the removal of `slot`.
        struct Shape {
            size_t ring_size, new_count, cover_count;
            bool boundary;
        };
        Shape shape(size_t slot) const;
        std::vector<size_t> at_; // per slot: where its removal begins in words_, or kEmpty
        uint32_t* words_ = nullptr;
        size_t capacity_ = 0;
        std::atomic<size_t> used_{0};
    };
    // The re-triangulation of a removed vertex's star, with what planning it reads; filled by
    // plan_removal.
    struct RemovalPlan : Removal {
        detail::Vec3 star_normal[kMaxValence]; // of star triangle i (v, ring[i], ring[i+1])
        bool star_faces_along;                 // every star triangle faces its corners' way
        double error = 0; // Terms::ErrorQuadrics: v's error where the new triangles pass it
        // midpoint_change of the new edges tried so far, between ring points below
        // kChangeMemo: the planar triangulation and each fan try many of the same edges.
        static constexpr size_t kChangeMemo = 16;
        mutable double edge_change[kChangeMemo][kChangeMemo];
        mutable uint16_t edge_change_known[kChangeMemo];
    };

    // The share of a pass's candidates, lightest first, that the pass selects from (pass_share):
    // kPassShare while at least kFineBelow of the input's triangles are left, then in proportion
    // to what is left, down to kFinestShare.
    static constexpr double kPassShare = 0.25;
    static constexpr double kFineBelow = 0.5;
    static constexpr double kFinestShare = 0.03;
    // Items of a parallel stage between two progress calls (see checkpoint).
    static constexpr size_t kBlock = 8192;

    // simplifier.cpp: weights, passes, the main loop.
    // Re-classifies v and recomputes its weight (and, for vertex removal, its key's tie-break).
    void refresh_vertex(uint32_t v);
    // Terms::ErrorQuadrics, vertex removal: v's error at the centre of its ring (its neighbours
    // in fan order; on a boundary, of the two boundary neighbours that the removal joins), with
    // their mean data, where a flat re-triangulation passes; off a boundary, at a ring vertex
    // with its data if that is lighter, where a fan from it puts v (infinite for a ring too
    // large).
    double removal_error(uint32_t v, const uint32_t* ring, size_t count) const;
    // Vertex removal: refreshes the removed vertex's ring (see refresh_changed).
    void refresh_around(const uint32_t* changed, size_t count);
    // One vertex of refresh_around: `made` a collapse's new vertex, `apex` one whose kind may
    // have changed (all but the rest of a collapse's ring). Sets neither epoch_ nor out[].
    void refresh_changed(uint32_t v, bool made, bool apex);
    // Whether refresh_changed(v, false, false) does anything.
    bool ring_refreshes(uint32_t v) const;
    // Takes kShared off v's hold; whether it was there (a vertex shared by collapses on several
    // threads is refreshed once, by the one that takes it).
    bool claim_shared(uint32_t v);
    // Reserves the record's per-operation arrays for the most operations a run to `target` takes.
    void reserve_record(size_t target);
    // rank.cpp: the next pass: the number of candidates it selects from into `share`; ranked_
    // holds every candidate, lightest first. False: cancelled.
    bool rank_candidates(size_t& share);
    // The fraction of the candidates the next pass selects from; reads only the surface's size.
    double pass_share() const;
    // Ranks id again: kIsCandidate if it is a candidate now, kKeyed if its key may have changed
    // (computed again, as what it reads changed). Writes only id's own places (its flags and,
    // for an edge, its cached weight).
    static constexpr uint8_t kIsCandidate = 1, kKeyed = 2;
    uint8_t rank_id(uint32_t id);
    // The key of a candidate that rank_id ranked.
    detail::Key key_of(uint32_t id) const;
    // order_audit.cpp: whether ranked_ holds exactly the candidates, with the keys and in the
    // order, that ranking every id afresh gives (the check that order_audit.h turns on).
    bool order_is_afresh() const;
    // The ids marked stale, in id order, into stale_ids_.
    void gather_stale();
    // A ranking sorts its new places in place when they are more than the kept ones over this.
    static constexpr size_t kSortedInPlace = 8;
    // Drops from ranked_ every candidate whose place is kDropped, keeping the order.
    void drop_stale();
    // One pass (see the pipeline above); returns true with `stop` set when the run is over.
    bool run_pass(size_t target, StopReason& stop);
    // Adds the pass to detail::pass_counts(): the candidates its selection walks visited, and
    // its checks that waited or were refused (taken_ holds those taken).
    void count_pass(size_t walked, size_t waited, size_t refused) const;
    // Selection rounds per pass (see run_pass).
    static constexpr int kSelectionRounds = 2;
    // A candidate's neighbourhood: the vertices its operation reads or changes (those it moves or
    // removes and their neighbours, some twice). walk_neighbourhood calls visit(v) on each until
    // it returns false; returns whether it went through all.
    static constexpr size_t kMaxNeighbourhood = 2 * kMaxValence + 2;
    // Where a candidate's neighbourhood starts: an edge's origin a and destination b; a vertex
    // (vertex removal) in both.
    struct Ends {
        uint32_t a, b;
    };
    template <class F> bool walk_neighbourhood(const Ends& ends, F&& visit) const;
    // Edge collapse: the ends of the edge at each place of the pass's share, listed on the
    // threads when the pass begins; the walk reads them in rank order.
    detail::Array<Ends> share_ends_;
    // selection.cpp: one round of a pass's selection, a walk through pending_ (ranks, ascending)
    // in rank order. A candidate whose neighbourhood no candidate selected before it in this
    // round holds (for an edge: whose ends none holds, see ring_shared_) goes into selected_ and
    // holds it (busy_ stamped round_stamp, its holder index `first` + its index in selected_);
    // one that such a candidate blocks goes into blocked_,
    // with the holder index of the one that blocks it in blocked_by_; one next to an operation
    // taken in an earlier round of this pass (stamped from pass_stamp on, its check Taken), or
    // larger than kMaxNeighbourhood, cannot be selected in this pass. False: cancelled.
    // Each selected one gets its plan's place at once, and every kCheckBatch of them are
    // published to the checks running beside the walk (see run_pass).
    bool select(uint32_t pass_stamp, uint32_t round_stamp, size_t first);
    // Edge collapse: two selected edges may share ring vertices, never an end in the other's
    // neighbourhood: each collapse then changes only its own stars, and a shared vertex only
    // loses a neighbour or gets a new one from each. A shared vertex keeps the hold of the first
    // edge selected, with kShared in its holder (such a vertex's out[] and record are set after
    // the pass's collapses, see refresh_rings); the others are listed here (vertex, holder), and
    // after the round's checks (hold_for_taken) a taken one's hold replaces one that was not
    // taken, so that the vertex stays held for the pass.
    static constexpr uint32_t kShared = 0x80000000u;
    std::vector<std::pair<uint32_t, uint32_t>> ring_shared_;
    void hold_for_taken();
    bool shared(uint32_t v) const {
        return options_.strategy == Strategy::EdgeCollapse && (busy_[v].holder & kShared);
    }
    // After the walk selected another one (over: after the walk ended): its plan's place, and
    // the count of selected ones for the checks, with kWalkOver once the walk is over.
    void publish_selected(bool over);
    // Waits until `count` selected ones are published or the walk is over; returns how many of
    // the first `count` there are.
    size_t wait_published(size_t count);
    // A check thread's part of a round (see run_pass): claims batches of the published selected
    // ones and checks them, their plans from plans_[first] or removals_[first] on, until the walk
    // is over and nothing is left or `stopped`; the calling thread reports progress.
    void check_published(size_t first, std::atomic<size_t>& claimed, std::atomic<bool>& stopped,
                         bool calling);
    static constexpr size_t kCheckBatch = 32;
    static constexpr uint64_t kWalkOver = uint64_t(1) << 63;
    std::atomic<uint64_t> published_{0};
    // The candidates that the round's refused or waiting ones blocked into pending_: the others
    // are next to a taken operation now.
    void pend_blocked();
    // The constructor's work, with a watch on parallel_: returns early once it is stopped.
    void set_up(const Surface& surface, const Options& options);
    // Calls Options::progress (on the calling thread); false once it asked to stop.
    bool checkpoint();
    // f(begin, end) over [0, n) on the threads, block by block of kBlock items, with a progress
    // call after each but the last; returns how many items it went through (n unless cancelled).
    template <class F> size_t in_blocks(size_t n, F&& f) {
        for (size_t begin = 0; begin < n; begin += kBlock) {
            const size_t end = std::min(n, begin + kBlock);
            parallel_.for_range(end - begin, [&](size_t b, size_t e) { f(begin + b, begin + e); });
            if (end < n && !checkpoint()) return end;
        }
        return n;
    }
    // The weight of the quadrics' geometric error: alpha, but at least kMinGeometryWeight.
    double geometry_weight() const;
    // Terms::ErrorQuadrics: the price of a squared distance (raw units) by which the surface
    // retracts from a vertex an operation removes or moves, the geometric quadric area of an
    // average vertex now; 0 otherwise. A quadric holds the planes of the triangles a vertex
    // stands for, and a thin spike's or a corner's planes all meet at it: pulling its tip back
    // costs them little when it stands for a small area, though the surface no longer reaches
    // where the tip was. So a plan also prices the distance from the vertex to the new
    // triangles, as if it stood for an average vertex's area.
    double retraction_scale() const;
    // The error quadrics' geometric error of point p against the present triangle g / 3 (raw
    // units: area x squared distance to its plane).
    double star_error(uint32_t g, const detail::Vec3& p) const;

    // edge_collapse.cpp
    // a = origin of h, b = its destination (the callers have them).
    bool kinds_allow_collapse(uint32_t h, uint32_t a, uint32_t b) const;
    // kinds_allow_collapse, and not known to fail: plan_collapse refused it and nothing it reads
    // has changed since.
    bool collapsible(uint32_t h, uint32_t a, uint32_t b) const;
    // The weight of collapsing h, the first part of its key (edge_length the second).
    float collapse_weight(uint32_t h) const;
    // Fetches the records and quadrics of an edge's ends a and b, which its key reads (a prefetch
    // changes no result).
    void prefetch_key(uint32_t a, uint32_t b) const;
    // In a loop over edges edge_at(i) for i < end, at i: fetches what planning and applying
    // the collapses a few steps ahead read first, their half-edges, then their ends' records,
    // quadrics and first triangles (a prefetch changes no result).
    template <class EdgeAt> void prefetch_ahead(size_t i, size_t end, EdgeAt&& edge_at) const {
        constexpr size_t kAhead = 4;
        if (i + 2 * kAhead < end) __builtin_prefetch(&mesh_.origin[edge_at(i + 2 * kAhead)]);
        if (i + kAhead < end) {
            const uint32_t h = edge_at(i + kAhead), a = mesh_.origin[h], b = mesh_.dest(h);
            prefetch_key(a, b);
            __builtin_prefetch(&mesh_.out[a]), __builtin_prefetch(&mesh_.out[b]);
            __builtin_prefetch(&mesh_.twin[h]);
        }
    }
    float edge_length(uint32_t h) const; // the key's tie-break
    // A plan whose full key (error + retraction) is at most `taken_within` is taken whatever its
    // exact retraction (see taken_within()): the walk stops measuring the retraction once it knows
    // that.
    bool plan_collapse(uint32_t h, CollapsePlan& plan, double taken_within) const;
    // What place() is for: a collapse's plan, or its key (see place).
    enum class Pricing : uint8_t { Plan, Key };
    void place(uint32_t h, CollapsePlan& plan, Pricing pricing = Pricing::Plan) const;
    detail::Vec3 near_surface(const detail::SegmentSlope& slope, double t, uint32_t a, uint32_t b,
                              const detail::Vec3& axis, double length, const detail::Vec3& d) const;
    // With `star`, also adds star_error(g, p) there (from the normal the check computes anyway).
    bool keeps_facing(uint32_t g, const detail::Vec3& p, const detail::Vec3& ref,
                      double* star = nullptr) const;
    detail::Vec3 ref_of(uint32_t a, uint32_t b) const;
    // What the rest of a pass needs of an applied collapse: the new vertex, the edge's apexes
    // that another collapse shares and, for such an apex whose out[] the collapse removed, the
    // half-edge from which to set it again.
    struct Apexes {
        uint32_t made;
        uint32_t apex[2];  // the shared apexes (else kNone)
        uint32_t entry[2]; // the half-edge from which a shared apex's out[] is set, or kNone
        bool ring;         // whether the rest of the ring holds a shared vertex to refresh
    };
    // Applies a checked collapse as the record's operation `index`: its own stars, the new
    // vertex's record and those of its ring (see run_pass: the operations applied together
    // touch disjoint stars); the ring vertices another collapse shares wait for refresh_rings.
    Apexes apply_collapse(const CollapsePlan& plan, size_t index);
    // After a pass's collapses: their apexes' out[] and their rings' records (see select).
    void refresh_rings(const Apexes* collapses, size_t count);
    // Empties the arrays a pass fills (sized by its share, which shrinks as the surface
    // coarsens), their pages given back: those of a large pass would stay resident otherwise.
    // Done once the share is half that of the last release (pass_release_).
    void release_pass_arrays();
    detail::HalvingRelease pass_release_;
    detail::Array<Apexes> apexes_;
    // What checking a selected candidate on the untouched surface found.
    enum class Check : uint8_t { Refused, Waits, Taken };
    // `weight`: the candidate's key weight.
    Check check_collapse(uint32_t h, float weight, CollapsePlan& plan);
    // With `rekey`, marks the edges at v stale with their keys to be computed again; without,
    // only those that have no place in the order (see refresh_changed).
    void mark_edges_at(uint32_t v, bool rekey);
    // The id of half-edge h's edge: the lower of its two half-edges.
    uint32_t edge_id(uint32_t h) const {
        const uint32_t t = mesh_.twin[h];
        return t != detail::kNone && t < h ? t : h;
    }
    // v's star changed: if a standing refusal reads v (refusal_near_), marks the refused edges of
    // its star, v an end or an apex of each.
    void forgive_around(uint32_t v);

    // vertex_removal.cpp
    bool removable(uint32_t v) const;
    detail::Key removal_key(uint32_t v) const;
    // A vertex's key from the mesh, before the first pass (refresh_vertex keeps it afterwards):
    // shortest_[v] and, with the error quadrics, weight_[v].
    void key_removal(uint32_t v);
    bool plan_removal(uint32_t v, RemovalPlan& plan) const;
    // Terms::ErrorQuadrics: how far the new edge between ring[p] and ring[q] leaves the star's
    // surface and data at its midpoint (squared, weighted and normalised as the quadrics are).
    // xyh: the ring in the plane of the star's mean normal, v at the origin, with each point's
    // height above that plane.
    double midpoint_change(const RemovalPlan& plan, const double (*xyh)[3], uint8_t p,
                           uint8_t q) const {
        const uint8_t lo = std::min(p, q), hi = std::max(p, q);
        if (hi < RemovalPlan::kChangeMemo && (plan.edge_change_known[lo] >> hi & 1))
            return plan.edge_change[lo][hi];
        return new_midpoint_change(plan, xyh, lo, hi);
    }
    // midpoint_change of an edge not yet in the plan's memo (lo < hi), kept there.
    double new_midpoint_change(const RemovalPlan& plan, const double (*xyh)[3], uint8_t lo,
                               uint8_t hi) const;
    // Terms::ErrorQuadrics: the squared change a re-triangulation makes to the star's surface
    // and data, integrated over the new triangles (zero on the ring's own edges).
    double triangulation_change(const RemovalPlan& plan, const double (*xyh)[3],
                                const uint8_t (*triangles)[3], size_t count) const;
    bool triangulate(const RemovalPlan& plan, const double (*xyh)[3], const uint8_t* polygon,
                     size_t n, const uint64_t* adjacent, RemovalPlan& out) const;
    bool planar_triangulation(RemovalPlan& plan, const double (*xyh)[3], const uint64_t* adjacent,
                              const detail::Vec3& axis) const;
    // The fan from one ring vertex (the half-edge collapse into it) of least error, the
    // best-shaped among equals; with the error quadrics, a fan must be lighter than `beat` (an
    // alternative's error) to matter, so heavier ones are not priced in full.
    bool fan_triangulation(RemovalPlan& plan, const uint64_t* adjacent, const double (*xyh)[3],
                           double beat = INFINITY) const;
    // Terms::ErrorQuadrics: the error of v's quadric at the point of `triangles` (indices into
    // plan.ring) that lies on v's projection axis (xyh as for midpoint_change), with
    // the data interpolated there; the nearest triangle's nearest point if none holds it. Inside
    // the surface, plus the retraction from v to that point (see retraction_scale). Where that
    // point is into `cover`. count >= 1: a boundary ear, which makes no triangle, is planned
    // without one (plan_removal).
    double triangulation_error(const RemovalPlan& plan, const uint8_t (*triangles)[3], size_t count,
                               const double (*xyh)[3], Cover& cover) const;
    // Applies a planned removal as the record's operation `index`, its writes from `write_at`.
    void apply_removal(const Removal& plan, size_t index, size_t write_at);
    // Taken: removals_ holds what applying it needs in `slot`.
    Check check_removal(uint32_t v, size_t slot);

    Options options_;
    detail::Parallel parallel_;
    detail::WorkingMesh mesh_;
    detail::GradientTerms gradient_;
    // Per vertex: the paper's weight (Terms::AngleDeficitGradient); with the error quadrics,
    // vertex removal's key: its error where a re-triangulation would pass (removal_error), an
    // estimate that step_removal replaces by its planned re-triangulation's error when that is
    // heavier than it and than the pass's share (until v's star changes); unused by edge
    // collapse with the error quadrics (empty).
    detail::Array<float> weight_;
    // Terms::ErrorQuadrics, or Placement::LeastError: the accumulated error per vertex slot.
    detail::ErrorQuadrics quadrics_;
    bool quadric_terms_ = false, least_error_ = false;
    // DataPlacement::LeastError with data in the quadrics: a collapse's new point takes its data
    // of least error (ErrorQuadrics::least_data).
    bool least_data() const {
        return options_.data_placement == DataPlacement::LeastError && quadrics_.components > 0;
    }
    double curvature_scale_ = 0, gradient_scale_ = 0; // 1 / mean of each term over the input
    size_t operations_ = 0;
    // The candidates are the ids (edge collapse: every live edge under its lower half-edge id;
    // vertex removal: every live vertex) that can be operated on with a finite key. ranked_ holds
    // them all, lightest first (see pass_order.h), from pass to pass: a ranking visits only the
    // ids marked in stale_ where something their status or key reads changed (an operation's
    // stars, a refusal, a plan that waits) and replaces the places of those whose status or key
    // changed. A refused id is marked again when a vertex its refusal reads changes (see fail_).
    // kKeyStale: its key (edge collapse's, its weight cached in edge_weight_) must be
    // computed again, as an end moved or changed kind; it stays until the key is computed, which
    // waits until the id is a candidate again. placed_[id]: whether id has a place in
    // ranked_ (kPlaced), one with a key that a plan raised since (kMoved), or one the ranking
    // drops (kDropped; a removed half-edge stays so).
    detail::Array<detail::Candidate> ranked_;
    static constexpr uint8_t kStale = 1, kKeyStale = 2;
    detail::Array<uint8_t> stale_, placed_;
    static constexpr uint8_t kUnplaced = 0, kPlaced = 1, kMoved = 2, kDropped = 3;
    detail::Array<float> edge_weight_;
    // Operations side by side may mark the same id: a mark never clears what another set (both
    // flags are stored outright, kStale added to an id without it).
    void mark_stale(uint32_t id) {
        std::atomic_ref<uint8_t> marks(stale_[id]);
        if (!(marks.load(std::memory_order_relaxed) & kStale))
            marks.fetch_or(kStale, std::memory_order_relaxed), mark_block(id);
    }
    void mark_rekey(uint32_t id) {
        std::atomic_ref<uint8_t>(stale_[id]).store(kStale | kKeyStale, std::memory_order_relaxed);
        mark_block(id);
    }
    // Which blocks of 64 ids hold a kStale mark (bit b of word w: block 64 w + b), so that a
    // ranking lists the stale ids by reading those blocks only: some runs make thousands of
    // passes of a few operations each.
    static constexpr uint32_t kStaleBlockShift = 6;
    detail::Array<uint64_t> stale_blocks_;
    void mark_block(uint32_t id) {
        const uint32_t block = id >> kStaleBlockShift;
        std::atomic_ref<uint64_t> word(stale_blocks_[block / 64]);
        const uint64_t bit = uint64_t(1) << (block % 64);
        if (!(word.load(std::memory_order_relaxed) & bit))
            word.fetch_or(bit, std::memory_order_relaxed);
    }
    // rank_candidates' scratch: the stale ids, which of them get new places, the new places
    // sorted, and the sort's scratch space.
    detail::Array<uint32_t> stale_ids_;
    detail::Array<uint8_t> fresh_status_;
    detail::Array<detail::Candidate> fresh_, scratch_;
    detail::HalvingRelease scratch_release_;
    // The first ranking visits every id (all are stale) without listing them: a list of every id
    // would be the largest array of the run.
    bool all_stale_ = true;
    // busy_[v]: the stamp of the selection round that last reserved v and the holder index (into
    // checked_ and the plans) of the candidate that holds it. Each round has its own stamp
    // (stamp_ counts them), so nothing needs clearing between rounds or passes, and what a taken
    // operation holds stays held for the rest of its pass.
    struct Hold {
        uint32_t stamp, holder;
    };
    detail::Array<Hold> busy_;
    uint32_t stamp_ = 0;
    // A pass's candidates still in its selection, those a round selected (ranks in ranked_,
    // ascending), those it blocked with the holder index of one that blocked each (see select),
    // and what each of the pass's selected ones' check found and its plan, in selection order
    // over the rounds (what a taken one's operation needs when applied).
    detail::Array<uint32_t> pending_, selected_, blocked_, blocked_by_;
    detail::Array<Check> checked_;
    detail::Array<CollapsePlan> plans_;
    RemovalStore removals_;
    // The operations a pass takes: (rank in ranked_, index into plans_ or removals_), sorted by
    // rank; then where each removal's writes go in the record.
    detail::Array<std::pair<uint32_t, uint32_t>> taken_;
    std::vector<uint32_t> write_at_;
    size_t target_ = 0;      // of the run (for the progress fraction only)
    bool cancelled_ = false; // Options::progress asked to stop
    uint32_t pass_ = 0;
    // Refusals are remembered: fail_[id] is the pass in which the plan refused the edge (per
    // half-edge) or vertex; epoch_[v] is the pass in which v's star last changed. A refusal
    // stands while no vertex the checks read has changed since (in that pass or later): the ends
    // and apexes of an edge, the vertex itself for a removal. A ranking that finds an edge's
    // refusal standing sets refusal_near_ at those four vertices, and a change of one's star marks
    // the refused edges of that star (forgive_around): a refused id is visited again only when
    // its refusal may be forgiven, not in every ranking (late in a run most edges of some surfaces
    // are refused, and passes take few operations). A refused vertex (vertex removal) is marked
    // by the change of its star anyway (refresh_around).
    detail::Array<uint32_t> fail_, epoch_;
    detail::Array<uint8_t> refusal_near_;
    // Vertex removal: the length of each vertex's shortest edge (its key's tie-break).
    detail::Array<float> shortest_;
    // Where the triangle that made the last refusal of an edge is (kNoFold: another check
    // refused it), for plan_collapse to test it first: bit 6 says in which end's star (set: the
    // half-edge's destination), bits 0-5 how many steps counter-clockwise from that end's out[]
    // its outgoing half-edge is. One byte, not a half-edge id: it is only a hint, so a star that
    // changed since costs time, not results.
    static constexpr uint8_t kNoFold = 0xff;
    detail::Array<uint8_t> fail_at_;
    uint8_t fold_hint(uint32_t h, uint32_t g) const;         // g: the folding half-edge, or kNone
    uint32_t fold_from_hint(uint32_t h, uint8_t hint) const; // kNone if it names none
    // Once nothing else is removable: a new or moved triangle is checked against the sum of its
    // corners' reference normals instead of each (see run_pass, keeps_facing, faces_the_surface).
    bool relaxed_facing_ = false;
    // The line tolerance in force (degrees): Options::line_tolerance until nothing else is
    // removable even with the facing relaxed; then, each time, doubled up to kWidestLine (see
    // widen_lines).
    static constexpr double kWidestLine = 80.0;
    double line_tolerance_ = 0;
    // Widens the line tolerance one step and re-classifies the corners that it makes line
    // vertices, their candidates marked for ranking; false if it cannot widen.
    bool widen_lines();
    // Marks every refused candidate for ranking again, its refusal forgotten.
    void forgive_refusals();
    // Whether a vertex removal's new triangle with normal n faces the way of the surface at its
    // corners, whose reference normals are ra, rb, rc: at each, or, once relaxed, on their sum.
    bool faces_the_surface(const detail::Vec3& n, const detail::Vec3& ra, const detail::Vec3& rb,
                           const detail::Vec3& rc) const {
        return relaxed_facing_ ? detail::dot(n, detail::add(ra, detail::add(rb, rc))) > 0
                               : detail::WorkingMesh::faces_along_normals(n, ra, rb, rc);
    }
    // The heaviest key of the pass's share. A planned collapse whose retraction (see
    // retraction_scale), or a planned removal whose error, makes it heavier than this and than
    // its own key waits for the next pass, which ranks it with the heavier key.
    float share_limit_ = 0;
    // Whether a candidate `id` keyed `key` whose plan weighs `planned` waits for the next pass,
    // which ranks it with that weight: heavier than its key and than the share (once, see
    // raised_), or always when heavier than Options::max_weight. Marks it raised if so.
    bool waits(uint32_t id, float key, float planned);
    // The heaviest plan of candidate `id` keyed `key` that does not wait (waits reads it).
    double taken_within(uint32_t id, float key) const;
    // raised_[id]: the candidate (half-edge or vertex) waited for a heavier plan since its key
    // was last computed, so it waits only once: the retraction's price grows a little as the
    // surface coarsens, and a plan made again later would be heavier again.
    detail::Array<uint8_t> raised_;
    size_t vertices_in_use_ = 0; // by the input's triangles
    // The validated input: it must outlive run(), which copies its vertices into the record.
    const Surface& input_;
    // Internal vertex ids are the input's in locality order, and a collapse reuses a slot:
    // id_[v] is the record's id of the vertex in slot v (its input id, or input vertices + i for
    // the point collapse i made), rank_ the internal id of each input vertex.
    std::vector<uint32_t> id_, rank_;
    std::vector<float> made_; // per collapse: the new point and its data (stride values)
    ProgressiveRecord record_;
};

} // namespace ddsimp
