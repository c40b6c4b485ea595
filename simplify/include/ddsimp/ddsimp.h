// ddsimp — data-dependent surface simplification (Frank & Lang, HLRS).
//
// The whole public interface of libddsimp. A surface is an indexed triangle list with named
// per-vertex float fields; `simplify` reduces it with the weight
//     w(v) = alpha * curv(v) + (1 - alpha) * grad(v)
// by edge collapse or vertex removal, keeping the topology of the input. No networking, no VTK.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ddsimp {

// Bumped whenever a change can alter the output bytes for the same input and options
// (the server keys its result cache on it).
inline constexpr int algorithm_version = 37;

// ---------------------------------------------------------------------------------------------
// Surface
// ---------------------------------------------------------------------------------------------

// What a field's values are: it decides how an operation that makes a new vertex sets them, and
// whether the field drives the data term when Options::gradient_fields is empty.
enum class FieldKind {
    Continuous, // a sampled quantity (pressure, velocity): interpolated; drives by default
    Label,      // ids, labels, integer counts: a new vertex takes the values of the edge's end
                // nearer to it (never a mix of two); does not drive by default
    Direction,  // unit vectors such as normals: interpolated, then scaled back to unit length;
                // does not drive by default
};

// One named per-vertex field: `components` floats per vertex, vertex-major
// (values[v * components + c]). A scalar has 1 component, a velocity 3.
struct Field {
    std::string name;
    int components = 1;
    std::vector<float> values;
    FieldKind kind = FieldKind::Continuous;
};

// An indexed triangle surface: 3 floats per vertex, 3 vertex indices per triangle, and any number
// of fields, each with one tuple per vertex.
struct Surface {
    std::vector<float> positions;
    std::vector<uint32_t> triangles;
    std::vector<Field> fields;

    size_t vertex_count() const { return positions.size() / 3; }
    size_t triangle_count() const { return triangles.size() / 3; }
    // The field called `name`, or nullptr.
    const Field* find_field(std::string_view name) const;
};

// ---------------------------------------------------------------------------------------------
// Input checks
// ---------------------------------------------------------------------------------------------

// Thrown for input that cannot be repaired; what() says what is wrong and where
// (e.g. "triangle 12 refers to vertex 4711, but the surface has 434 vertices").
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// What `validate` repaired.
struct RepairReport {
    size_t degenerate_triangles_dropped = 0; // a triangle that names one vertex twice
    size_t duplicate_triangles_dropped = 0;  // same three vertices as an earlier triangle
    size_t unused_vertices = 0;              // referenced by no triangle (not in any output)
    size_t triangles_flipped = 0;            // turned to agree with their neighbours' orientation
};

// Checks a surface and repairs what has one obvious repair, in place:
// - rejected (InputError): no triangles; positions not a multiple of 3 or triangles not a multiple
//   of 3; a non-finite coordinate; an index out of range; a field with components < 1, an empty
//   or repeated name, the wrong number of values, or a non-finite value.
// - repaired: degenerate and duplicate triangles are dropped (the first copy is kept, in order);
//   triangles are flipped where needed so that every edge-connected component is consistently
//   oriented like its first triangle (where the surface is orientable).
RepairReport validate(Surface& surface);

// ---------------------------------------------------------------------------------------------
// Topology
// ---------------------------------------------------------------------------------------------

// Counts that simplification must preserve (see `simplify`).
struct Topology {
    size_t vertices = 0; // referenced by at least one triangle
    size_t triangles = 0;
    size_t edges = 0;
    size_t boundary_edges = 0;          // edges with one triangle
    size_t nonmanifold_edges = 0;       // edges with three or more triangles
    size_t nonmanifold_vertices = 0;    // vertices whose star is not one disk or half-disk
    size_t boundary_loops = 0;          // closed loops of boundary edges
    size_t components = 0;              // edge-connected components of triangles
    long long euler_characteristic = 0; // V - E + F
};

// Topology of a surface whose indices are in range (call `validate` first for foreign input).
Topology analyze_topology(const Surface& surface);

// ---------------------------------------------------------------------------------------------
// Weights
// ---------------------------------------------------------------------------------------------

// Unit-free curvature of every vertex: the absolute angle deficit |2pi - sum(theta)|, or
// |pi - sum(theta)| at a boundary vertex, divided by pi. Computed on the repaired surface (see
// `validate`, which may throw); unreferenced and complex (non-manifold) vertices get 0.
std::vector<float> vertex_curvature(const Surface& surface);

// Unit-free data gradient of every vertex: max over neighbours v_i of
// ||f_i - f||_1 / ||x_i - x||_1, where each field's components are divided by that field's range
// (the largest max - min of its components over the surface) and lengths by the bounding-box
// diagonal. `fields` names the fields that count; empty means default_gradient_fields. Throws
// InputError for an unknown field name. Like vertex_curvature, on the repaired surface; complex
// vertices get 0.
std::vector<float> vertex_gradient(const Surface& surface, const std::vector<std::string>& fields);

// The fields that drive the data term when none are named: those of kind Continuous, in order.
std::vector<std::string> default_gradient_fields(const Surface& surface);

// ---------------------------------------------------------------------------------------------
// Simplification
// ---------------------------------------------------------------------------------------------

enum class Strategy {
    EdgeCollapse,  // collapse the lightest edge into one new point
    VertexRemoval, // remove the lightest vertex and re-triangulate its star; data stays exact
};

enum class Placement {
    LeastError,       // the point of the edge where the error quadrics (see Terms) are least
    Midpoint,         // the middle of the edge
    VolumePreserving, // the point nearest the midpoint that keeps the enclosed volume (Gueziec)
    // In every case, an end pinned by a boundary or feature line (see feature_angle) keeps its
    // position: the new point goes there. Its data: see DataPlacement.
};

// The data an edge collapse gives its new point.
enum class DataPlacement {
    // Each component of a Continuous field that drives the data term (gradient_fields) takes its
    // value of least data error at the new point (the least-squares value of the two ends' error
    // quadrics, see Terms), clamped to the range of the two values it replaces, so that it never
    // overshoots them; other fields are interpolated, and a collapse onto a locked vertex
    // (Options::locked) keeps its data. Once the run is over, those components of the points it
    // made are fitted again over the whole level: the least-squares fit of the level's
    // interpolated data to the input's, both ways (each input vertex against the level, each
    // level vertex against the input), clamped to the range each component spans over the
    // input; the input's own vertices and locked points keep theirs (docs/algorithm.md, "Edge
    // collapse"). Needs the error quadrics (Terms::ErrorQuadrics or Placement::LeastError) and
    // alpha < 1; otherwise as Interpolated.
    LeastError,
    // Interpolated at the new point's position along the edge (Frank & Lang); a Label field
    // takes the nearer end's value, a Direction field is scaled back to unit length.
    Interpolated,
};

// What the two terms of the weight measure.
enum class Terms {
    // The error an operation introduces relative to the input surface and data: curv is the
    // geometric error (area x squared distance to the input triangles' planes, lengths in
    // bounding-box diagonals), grad the data error (area x squared difference to the input's
    // linear interpolation, data in field ranges), both accumulated per vertex as quadrics and
    // evaluated where the operation puts the vertex. The geometric term weighs alpha but at
    // least 0.2, so that at alpha = 0 the surface stays where the data is read from (data alone
    // lets the surface drift off its creases, taking the data with it). An edge weighs the error
    // of its two ends at the new point plus how far its new triangles retract from the ends (the
    // squared distances, priced at an average vertex's area); a removed vertex weighs its error
    // where the new triangles pass it plus, off a boundary, their distance from it, priced the
    // same way (docs/algorithm.md).
    ErrorQuadrics,
    // Frank & Lang's: curv the absolute angle deficit / pi, grad the steepest neighbour's
    // ||df||_1 / ||dx||_1 (see vertex_curvature, vertex_gradient), each divided by its mean over
    // the input; an edge weighs the sum of its ends' weights.
    AngleDeficitGradient,
};

enum class StopReason {
    TargetReached,    // the triangle target was met
    WeightBound,      // the lightest remaining element weighs more than Options::max_weight
    NothingRemovable, // every remaining element would change topology, flip or fold a triangle
                      // or move a corner of a line (see line_tolerance)
    Cancelled,        // the progress callback asked to stop
};

struct Options {
    // w = alpha * curvature + (1 - alpha) * gradient, alpha in [0, 1]; what the terms measure
    // and how they are made unit-free: see Terms.
    double alpha = 0.5;
    Terms terms = Terms::ErrorQuadrics;
    Strategy strategy = Strategy::EdgeCollapse;
    Placement placement = Placement::LeastError;
    DataPlacement data_placement = DataPlacement::LeastError;

    // Target: the first that is set wins: target_triangles, then keep_fraction.
    size_t target_triangles = 0; // stop at or below this many triangles (0: not set)
    double keep_fraction = 0.1;  // or this fraction of the repaired input's triangles
    // Also stop when the lightest element's weight exceeds this (the "error bound" target; with
    // Terms::ErrorQuadrics a weight is an area in squared diagonals times a squared relative
    // error).
    double max_weight = std::numeric_limits<double>::infinity();

    // Fields that drive the gradient (data) term; empty means default_gradient_fields.
    std::vector<std::string> gradient_fields;
    // An edge whose two triangles' normals differ by more than this (degrees) is a feature edge;
    // 180 disables features.
    // Off by default: isosurfaces of sampled data are full of sharp-looking dihedrals between
    // slivers, which would pin most vertices. Turn it on for CAD-like parts (e.g. 45).
    double feature_angle = 180.0;
    // A boundary or feature vertex is removed only where its line continues within this angle
    // (degrees) of straight, or where it lies within half the input's mean edge length of the
    // segment between its two line neighbours and the input's line turned the other way at one
    // of them (a zigzag of the sampling; a polygon's corners stay). Once nothing else is
    // removable before the target, the angle doubles, at most to 80 degrees, as often as that
    // makes more removable. 0 keeps every vertex where its line turns (no zigzag, never
    // widens); a right angle stays unless it is such a zigzag.
    double line_tolerance = 20.0;
    // Largest allowed turn (degrees) of any remaining triangle's normal in one operation; larger
    // turns are refused as folds. (Independently, no operation may leave a triangle facing away
    // from the input surface's normal at its corners, so turns cannot add up to a flip; once
    // nothing else is removable, edge collapse asks this of the corners' normals together.)
    double max_normal_turn = 60.0;

    // Locked vertices: empty means none, else one entry per input vertex; a non-zero entry
    // keeps that vertex in the output with its position and data unchanged (like a corner of a
    // line, it is never removed or moved; a free neighbour may still collapse into it). For
    // pieces of a larger surface whose shared borders must stay as they are (ddsimp-mpi).
    // Whatever this says, the vertices of the input's folds (two neighbouring triangles more
    // than 175 degrees apart, docs/algorithm.md) are kept the same way.
    std::vector<std::uint8_t> locked;

    // Threads for the engine's stages (keys, selection, checks, application); 0 means every
    // hardware thread. The output bytes do not depend on it.
    int threads = 0;
    // Called with the fraction of the work done (non-decreasing, in [0, 1]) at least every few
    // thousand items of a stage's work, in the set-up (fraction 0), the passes and, in simplify,
    // the level's fit: every few tens of milliseconds on one core, at most a few tenths of a
    // second on a million triangles (the set-up's serial steps, the first ranking's sort). Always
    // on the thread that called simplify or ProgressiveRecord::build, never concurrently; return
    // false to cancel: the run stops at its next call (StopReason::Cancelled) and does not call
    // it again. The input's repair is finished first, so that a cancelled run still has it.
    std::function<bool(double)> progress;
};

// Throws InputError with a message that names the option if `options` is out of range (alpha
// outside [0, 1], a negative thread count, ...). simplify and ProgressiveRecord::build call it;
// callers that take options from users (command lines, the server) call it first.
void check_options(const Options& options);

// The triangle count `options` asks for from a surface of `triangles_in` (repaired) triangles:
// target_triangles if set, else floor(keep_fraction x triangles_in).
size_t target_triangles(const Options& options, size_t triangles_in);

// What a simplification did.
struct Result {
    // The reduced surface, every field carried, unused vertices dropped. Cancelled: the level the
    // run had reached, as recorded (not fitted, see ProgressiveRecord::after_as_recorded).
    Surface surface;
    size_t triangles_in = 0;
    size_t triangles_out = 0;
    size_t operations = 0;
    StopReason stop = StopReason::TargetReached;
    bool target_reached = false;
    RepairReport repairs;
};

// A human-readable reason ("target reached", "nothing more removable without changing
// topology", ...).
const char* describe(StopReason reason);

// Validates (and repairs, see `validate`) a copy of `input`, then simplifies it. Keeps the Euler
// characteristic, boundary loops and components of the repaired input; never adds a non-manifold
// edge. Deterministic: the same input and options give the same bytes. Throws InputError for
// invalid input or options.
Result simplify(const Surface& input, const Options& options);

// How far a level of a ProgressiveRecord is from the repaired input (docs/algorithm.md, "The
// error of a level"): the geometry in bounding-box diagonals, the data in field ranges, RMS over
// the data components that drive the weight (Options::gradient_fields).
// - Edge collapse: for every vertex a collapse made, the area-weighted RMS distance from it to the
//   planes of the input triangles (and boundary edges) it stands for, and the RMS difference
//   between its data and the input data's linear interpolation on those triangles (the error
//   quadric's meaning): a typical deviation over the region the vertex replaced.
// - Vertex removal: for every removed input vertex, its distance to the nearest point of the
//   level's triangle that covers it, and the difference between its data and the level's
//   interpolation there: a bound on how far the input's vertices are from the level.
// A level's numbers are the largest over its operations, so they never fall as the level
// coarsens. Neither is a Hausdorff distance. The same whatever Options::terms ordered the
// operations.
struct LevelError {
    float geometric = 0;        // in bounding-box diagonals of the input
    float data = 0;             // in field ranges (0 when data_components is 0)
    size_t data_components = 0; // the data components measured (0: no data error measured)
};

namespace detail {
class StageWatch; // the progress of a level's fit (simplify/src/stage_watch.h)
}

// The ordered operations of one run for (surface, options), from which every coarser level is
// extracted without re-running: `level(n)` equals `simplify` with target_triangles = n exactly,
// as long as that run would stop for its target and not earlier.
class ProgressiveRecord {
public:
    // Runs until `options`'s target (usually set low, e.g. keep_fraction = 0) or until nothing
    // more is removable.
    static ProgressiveRecord build(const Surface& input, const Options& options);

    // The surface after the first `operations` operations (0 = the repaired input). With edge
    // collapse's least-error data (DataPlacement::LeastError) the points the run made move onto
    // the input where its samples fit better, and its data is fitted over the level.
    // With vertex removal and the error quadrics, its vertices may move to other input vertices
    // (with their data) where the input fits better: its data and, as the quadrics weigh it, its
    // surface (at alpha = 1, or with no data, the surface alone). With either, where the surface
    // is nearly flat, its edges are flipped where the input fits better (edge collapse: not at
    // alpha = 1).
    Surface after(size_t operations) const;
    // The same, calling `progress` with the fraction of the fit done as Options::progress is
    // called (on the calling thread, every few milliseconds of work); nothing once it returns
    // false: the fit stops at once.
    std::optional<Surface> after(size_t operations,
                                 const std::function<bool(double)>& progress) const;
    // The same level with each vertex's position and data as vertices() carries them, never
    // fitted, nor its edges flipped, nor its vertices moved: what a refinement stream (vertices()
    // and indexed_triangles) shows, level after level. As many vertices as after(), in the same
    // order; each of after()'s is this level's vertex (a point the run made perhaps moved) or one
    // of the input vertices it replaced.
    Surface after_as_recorded(size_t operations) const;
    // The surface at the first operation that leaves at most `triangles` triangles (or the
    // coarsest recorded if none does).
    Surface level(size_t triangles) const;
    // Operations needed to get to at most `triangles` triangles (or all of them).
    size_t operations_for(size_t triangles) const;

    // Every vertex the record knows: the input's, then one per collapse (edge collapse only),
    // with every field. Vertex ids are stable across levels, so a renderer can refine a level
    // into a finer one by sending only what changed (see indexed_triangles). A point's data is
    // the one its collapse gave it, the same in every level: after() fits least-error data to
    // each level anew.
    const Surface& vertices() const { return vertices_; }
    // The triangles after `operations` operations, in the ids of vertices(), in slot order.
    std::vector<uint32_t> indexed_triangles(size_t operations) const;

    size_t operations() const { return triangles_after_.size(); }
    size_t triangles_in() const { return triangles_in_; }
    // Triangle count after operation i.
    size_t triangles_after(size_t i) const { return triangles_after_[i]; }
    StopReason stop() const { return stop_; }
    const RepairReport& repairs() const { return repairs_; }
    // The error of the level after `operations` operations (0 = the repaired input: no error);
    // see LevelError. Costs 8 bytes per operation.
    LevelError error_after(size_t operations) const;

private:
    friend class Simplifier;
    friend Result simplify(const Surface& input, const Options& options);
    // build without the level errors (simplify needs only the last level).
    static ProgressiveRecord run(const Surface& input, const Options& options, bool measure);
    // After the run, once the simplifier's memory is gone: the input's triangles, and the
    // vertices, the input's and then the points the run made (`made`: per collapse, the point
    // and its data in field order); frees `made`.
    void take_input(const Surface& input, std::vector<float>& made);
    // level_error.cpp: fills level_error_ from the record (after the run).
    void measure_errors(const std::vector<std::string>& gradient_fields);
    Strategy strategy_ = Strategy::EdgeCollapse;
    Surface vertices_; // input vertices, then the points made by collapses (no triangles)
    std::vector<uint32_t> base_triangles_;  // the repaired input's triangles
    std::vector<uint32_t> triangles_after_; // per operation
    size_t triangles_in_ = 0;
    StopReason stop_ = StopReason::NothingRemovable;
    RepairReport repairs_;
    // Edge collapse: operation i replaces vertices collapse_[2i] and collapse_[2i+1] by the new
    // vertex input_vertices + i.
    std::vector<uint32_t> collapse_;
    size_t input_vertices_ = 0;
    // Edge collapse with DataPlacement::LeastError: the data components (field, component) that
    // after() fits to the input over the whole level (data_refit.h). With that, or vertex
    // removal with the error quadrics: which input vertices are locked (empty: none), whose data
    // and that of the points placed on them stay and which vertex removal's moves never move
    // (level_relocation.h), and (vertex removal) which input vertices are on the boundary where
    // it runs on, to which its moves may take a boundary vertex; the components a flip of the
    // level's edges or a move weighs (data_flips.h), the weight of each one's squared difference
    // and of a squared distance, the least cosine between the normals it flips or moves across
    // (and across which a move by the distance alone turns a triangle: the run's normal turn),
    // that across an edge that is no feature edge (a vertex on a feature edge is not moved), and
    // the input's bounding-box diagonal (vertex removal's scale of a tie between two distances).
    std::vector<std::pair<uint32_t, uint32_t>> refit_components_;
    std::vector<uint8_t> locked_input_;
    std::vector<uint8_t> boundary_line_input_;
    std::vector<double> refit_data_weight_;
    double refit_distance_weight_ = 0, refit_flat_cos_ = 2, refit_turn_cos_ = 2,
           refit_feature_cos_ = -2, refit_diagonal_ = 0;
    int threads_ = 0; // Options::threads, for the fit
    // Edge collapse: per vertex id up to the first `operations` collapses, the id it went into.
    std::vector<uint32_t> collapse_map(size_t operations) const;
    // after() and after_as_recorded(); nothing if `progress` stopped the fit.
    std::optional<Surface> level_after(size_t operations, bool fit_data,
                                       const std::function<bool(double)>& progress = {}) const;
    // Fits `level`'s data (after(operations), `index`: vertex id -> its vertex in `level`; edge
    // collapse) or moves its vertices (vertex removal), and flips its edges where the data fits
    // better (both strategies). False if `watch` stopped it.
    bool refit(size_t operations, const std::vector<uint32_t>& index, Surface& level,
               detail::StageWatch& watch) const;
    // Vertex removal: operation i rewrites the triangle slots writes_[write_begin_[i] ..
    // write_begin_[i+1]); a write is {slot, a, b, c}, a == kDead retires the slot.
    std::vector<uint32_t> write_begin_;
    std::vector<uint32_t> writes_;
    // Per operation: the geometric and the data error after it (running maxima); empty when not
    // measured.
    std::vector<float> level_error_;
    size_t error_components_ = 0;
};

} // namespace ddsimp
