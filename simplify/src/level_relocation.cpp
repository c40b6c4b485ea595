// A vertex-removal level's vertices moved to the input vertex in their star that the samples fit
// best.
#include "level_relocation.h"

#include "data_flips.h"
#include "working_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace ddsimp::detail {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Above this many data components a point's joint coordinates do not fit the scratch arrays;
// such a level is left as it is.
constexpr size_t kMaxComponents = 61;
constexpr size_t kMaxDims = 3 + kMaxComponents;
// The most samples landed as a star's new centre, the best by the estimate. Landing one costs the
// star's samples, so without a bound a star costs the square of its samples: on coarse levels,
// where each vertex stands for thousands, that is most of a run. The move chosen is in the median
// among the estimate's first five; at 10 % a star has about 30 samples, so the bound binds on
// coarser levels.
constexpr size_t kMaxCandidates = 64;
// A sum of a star's samples in another order differs by far less than this part of it.
constexpr double kOrderMargin = 1e-9;

// The least cosine between a triangle's normals before and after a move: where data weighs, only
// across nearly flat stars, so that the data does not pull the surface away; by the distance
// alone, as far as the run lets any operation turn it. Above 1: no move.
double move_cos(const RefitInput& input) {
    return input.components.empty() ? input.turn_cos : input.flat_cos;
}

// A star's samples: the input vertices on its triangles, the weight of the star's centre at each
// one's landing, and each one's joint coordinates and residual there (dims per sample).
struct StarSamples {
    std::vector<uint32_t> vertex;
    std::vector<double> centre_weight, joint, residual;
    std::vector<uint32_t> by_error; // the samples, the most error at the old centre first

    void clear() {
        vertex.clear(), centre_weight.clear(), joint.clear(), residual.clear(), by_error.clear();
    }
};

// Where a star's centre would go: the input vertex, and the samples' landings there.
struct Move {
    uint32_t to = kNoOwner;
    std::vector<std::pair<uint32_t, Landing>> landed;
};

// The level, its stars, and the samples on each triangle, as the moves change them. A point's
// joint coordinates are its position and its data in one vector, each scaled by the square root
// of its weight, so that a squared difference of two is their weighted squared error.
class LevelRelocation {
public:
    LevelRelocation(const RefitInput& input, const std::vector<uint8_t>& locked,
                    const std::vector<uint8_t>& boundary_line, std::vector<uint32_t>& source,
                    std::vector<Landing>& forward, Surface& level)
        : input_(input), in_(*input.surface), locked_(locked), boundary_line_(boundary_line),
          source_(source), forward_(forward), level_(level), stars_(level),
          dims_(3 + input.components.size()), keep_cos_(move_cos(input)) {
        scale_.push_back(std::sqrt(input.distance_weight));
        for (double w : input.data_weight) scale_.push_back(std::sqrt(w));
        // Each triangle's samples as a list through next_, in input order.
        head_.assign(level.triangle_count(), kNoOwner), next_.assign(forward.size(), kNoOwner);
        for (size_t i = forward.size(); i-- > 0;)
            if (const uint32_t t = forward[i].triangle; t != kNoOwner)
                next_[i] = head_[t], head_[t] = uint32_t(i);
    }

    size_t vertex_count() const { return level_.vertex_count(); }

    // The sample of v's star that lowers the star's error most as its centre, with its landings;
    // to = kNoOwner if none does (or v may not move). Reads the level only.
    Move best_move(uint32_t v) const {
        Move best;
        if (!locked_.empty() && locked_[source_[v]]) return best;
        // A vertex on the boundary moves along it: onto a sample on the boundary's line on one of
        // its two triangles with a boundary edge at it (`rim`).
        std::array<uint32_t, 2> ends{}, rim{kNoOwner, kNoOwner};
        const int fan = fan_ends(v, ends);
        if (fan == 2 && on_line(source_[v]))
            rim = {star_triangle_with(v, ends[0]), star_triangle_with(v, ends[1])};
        else if (fan != 0)
            return best;
        // Each thread keeps its star's arrays from call to call.
        static thread_local Scratch scratch;
        Star& star = scratch.star;
        star_of(v, star);
        star.closed = fan == 0;
        if (!star.smooth(input_.feature_cos)) return best;
        // The samples and their error; with them, the sums that price moving the centre by d
        // with every sample's weights kept: the sum of |w d + r|^2 is A |d|^2 + 2 d.B + C.
        StarSamples& samples = scratch.samples;
        samples.clear();
        std::array<double, kMaxDims> b{}, r;
        double a = 0, c = 0;
        for (size_t i = 0; i < star.triangle.size(); ++i) {
            const uint32_t t = star.triangle[i];
            for (uint32_t s = head_[t]; s != kNoOwner; s = next_[s]) {
                const Landing& l = forward_[s];
                std::array<double, 3> w; // in the star's order: the centre first
                for (size_t k = 0; k < 3; ++k) w[star.order[i][k]] = l.weights[k];
                samples.vertex.push_back(s);
                samples.centre_weight.push_back(w[0]);
                const size_t at = samples.joint.size();
                samples.joint.resize(at + dims_);
                joint(s, &samples.joint[at]);
                const double e =
                    residual(star, i, star.centre_joint.data(), w, &samples.joint[at], r.data());
                samples.residual.insert(samples.residual.end(), r.begin(), r.begin() + long(dims_));
                c += e, a += w[0] * w[0];
                for (size_t k = 0; k < dims_; ++k) b[k] += w[0] * r[k];
            }
        }
        const size_t count = samples.vertex.size();
        if (count == 0) return best;
        { // the samples by their error at the old centre, the most first
            std::vector<std::pair<double, uint32_t>>& errors = scratch.order;
            errors.resize(count);
            for (uint32_t i = 0; i < count; ++i) {
                const double* ru = &samples.residual[i * dims_];
                double e = 0;
                for (size_t k = 0; k < dims_; ++k) e += ru[k] * ru[k];
                errors[i] = {-e, i};
            }
            std::sort(errors.begin(), errors.end());
            samples.by_error.resize(count);
            for (uint32_t i = 0; i < count; ++i) samples.by_error[i] = errors[i].second;
        }
        // A move must lower the error by more than rounding and than differences the data's
        // floats cannot tell apart (as a flip must, data_flips.cpp).
        const double noise = std::max(1e-9 * c, 1e-12 * double(count + 1));
        // Each sample as the centre, estimated with the weights kept (less its own error, plus
        // that of the old centre, which lies where the new one is: |d|^2); the best
        // kMaxCandidates landed properly in the estimates' order, each given up once it is no
        // better than the best so far.
        const double* jv = star.centre_joint.data();
        std::vector<std::pair<double, uint32_t>>& order = scratch.order;
        order.clear();
        for (uint32_t i = 0; i < count; ++i) {
            if (rim[0] != kNoOwner) {
                const uint32_t s = samples.vertex[i], t = forward_[s].triangle;
                if (!on_line(s) || (t != rim[0] && t != rim[1])) continue;
            }
            const double *ju = &samples.joint[i * dims_], *ru = &samples.residual[i * dims_];
            double dd = 0, db = 0, own = 0;
            for (size_t k = 0; k < dims_; ++k) {
                const double d = ju[k] - jv[k], o = samples.centre_weight[i] * d + ru[k];
                dd += d * d, db += d * b[k], own += o * o;
            }
            order.emplace_back(a * dd + 2 * db + c - own + dd, i);
        }
        if (order.size() > kMaxCandidates) {
            std::nth_element(order.begin(), order.begin() + long(kMaxCandidates), order.end());
            order.resize(kMaxCandidates);
        }
        std::sort(order.begin(), order.end());
        double least = c - noise;
        uint32_t chosen = kNoOwner;
        Landings &landings = scratch.landings, &chosen_landings = scratch.chosen_landings;
        for (const auto& [estimate, i] : order) {
            if (!star.keeps(point_of(in_.positions, samples.vertex[i]), keep_cos_)) continue;
            // Landed with the samples of most error first, to give most candidates up soon;
            // what that cannot rule out is summed again in the samples' own order, so that the
            // sums, and the choice, do not depend on the first order.
            if (land_all(star, samples, i, least * (1 + kOrderMargin), samples.by_error,
                         landings) == kInfinity)
                continue;
            const double e = in_sample_order(landings, i, count, least);
            if (e < least) least = e, chosen = i, std::swap(landings, chosen_landings);
        }
        if (chosen != kNoOwner) {
            best.to = samples.vertex[chosen];
            best.landed.emplace_back(source_[star.centre], chosen_landings.at[0]);
            for (uint32_t n = 0; n < count; ++n)
                if (n != chosen)
                    best.landed.emplace_back(samples.vertex[n], chosen_landings.at[1 + n]);
        }
        return best;
    }

    // Moves v to `move`'s input vertex, its samples to their landings there.
    void apply(uint32_t v, Move& move) {
        const uint32_t u = move.to;
        std::copy_n(&in_.positions[3 * size_t(u)], 3, &level_.positions[3 * size_t(v)]);
        for (size_t f = 0; f < level_.fields.size(); ++f) {
            const size_t nc = size_t(level_.fields[f].components);
            std::copy_n(&in_.fields[f].values[nc * u], nc, &level_.fields[f].values[nc * v]);
        }
        forward_[u] = Landing{};
        source_[v] = u;
        for (uint32_t p = stars_.begin[v]; p < stars_.begin[v + 1]; ++p)
            head_[stars_.triangle[p]] = kNoOwner;
        // Back to front, so that each triangle's list is in input order.
        std::sort(move.landed.begin(), move.landed.end(),
                  [](const auto& x, const auto& y) { return x.first > y.first; });
        for (const auto& [s, at] : move.landed) {
            forward_[s] = at;
            next_[s] = head_[at.triangle], head_[at.triangle] = s;
        }
    }

    // v and its ring: the vertices whose stars a move of v changes.
    template <class F> void for_each_near(uint32_t v, F&& visit) const {
        visit(v);
        for (uint32_t p = stars_.begin[v]; p < stars_.begin[v + 1]; ++p)
            for (uint32_t k : corners(stars_.triangle[p]))
                if (k != v) visit(k);
    }

private:
    using Corners = std::array<uint32_t, 3>;

    // A star's triangles with their corners' points, the centre's first, and their normals.
    struct Star {
        uint32_t centre;
        std::vector<uint32_t> triangle;
        std::vector<std::array<Vec3, 3>> points;   // the centre's point first, then in order
        std::vector<std::array<uint8_t, 3>> order; // the triangle's corners in points' order
        std::vector<Vec3> normal;
        double area = 0;                  // twice the star's
        bool closed = false;              // a closed fan (the centre not on a boundary)
        std::vector<double> centre_joint; // the centre's joint coordinates
        std::vector<double> ring_joint;   // per triangle, its other two corners'
        // The plane of the star's mean normal (two unit vectors in it), and in it each
        // triangle's other two corners.
        Vec3 e1{}, e2{};
        std::vector<std::array<double, 4>> ring_2d;

        void clear() {
            triangle.clear(), points.clear(), order.clear(), normal.clear();
            centre_joint.clear(), ring_joint.clear(), ring_2d.clear();
            area = 0;
        }

        std::array<double, 2> project(const Vec3& p) const { return {dot(p, e1), dot(p, e2)}; }
        // Whether the star has no feature edge: each two triangles that share an edge at the
        // centre have normals within `feature_cos`. A corner or a crease stays where it is.
        bool smooth(double feature_cos) const {
            for (size_t i = 0; i < triangle.size(); ++i)
                for (size_t j = 0; j < triangle.size(); ++j)
                    if (points[i][2] == points[j][1] &&
                        dot(normal[i], normal[j]) < feature_cos * norm(normal[i]) * norm(normal[j]))
                        return false;
            return true;
        }
        // Whether moving the centre to x keeps each triangle's normal within `flat_cos` of its
        // own, and makes no sliver.
        bool keeps(const Vec3& x, double flat_cos) const {
            for (size_t i = 0; i < triangle.size(); ++i) {
                const Vec3 after = cross(sub(points[i][1], x), sub(points[i][2], x));
                const double la = norm(after);
                if (!(la > 1e-6 * area) || dot(after, normal[i]) < flat_cos * la * norm(normal[i]))
                    return false;
            }
            return true;
        }
    };
    // The star with its centre moved to x, seen in its plane: per triangle the edges from the
    // centre, projected. A triangle's projection lies in the wedge between them, and the
    // projection brings no two points nearer, so a point outside a wedge is at least its distance
    // from the wedge's edges away from that triangle. Where the wedges of a closed fan each turn
    // counter-clockwise by less than a half turn and go round once, they do not overlap: a point
    // over one triangle is at least its distance from that wedge's edges away from every other.
    struct CentredStar {
        struct Wedge {
            double ax, ay, bx, by; // the edges from the centre
            double inv_a, inv_b;   // their inverse squared lengths
            bool open;             // counter-clockwise, by less than a half turn
        };
        Vec3 x{};
        std::array<double, 2> cx{};
        std::vector<Wedge> wedge;
        std::vector<std::array<double, 2>> cross; // per wedge, a point's cross products
        bool apart = false;                       // no two wedges overlap

        void centre_at(const Star& star, const Vec3& at) {
            x = at, cx = star.project(at);
            const size_t n = star.triangle.size();
            wedge.resize(n), cross.resize(n);
            apart = star.closed;
            for (size_t i = 0; i < n; ++i) {
                const std::array<double, 4>& ring = star.ring_2d[i];
                Wedge& g = wedge[i];
                g.ax = ring[0] - cx[0], g.ay = ring[1] - cx[1];
                g.bx = ring[2] - cx[0], g.by = ring[3] - cx[1];
                const double la = g.ax * g.ax + g.ay * g.ay, lb = g.bx * g.bx + g.by * g.by;
                g.open = g.ax * g.by - g.ay * g.bx > 0 && la > 0 && lb > 0;
                g.inv_a = g.open ? 1 / la : 0, g.inv_b = g.open ? 1 / lb : 0;
                apart = apart && g.open;
            }
            // Round once: no wedge but the first holds the first's leading edge.
            for (size_t i = 1; i < n && apart; ++i) {
                const Wedge &g = wedge[i], &first = wedge[0];
                apart = !(g.ax * first.ay - g.ay * first.ax >= 0 &&
                          first.ax * g.by - first.ay * g.bx > 0);
            }
        }

        // The squared distance of a point (qx, qy from the centre, cross products ca and cb
        // with the wedge's edges) from wedge g's edges.
        static double edge_distance(const Wedge& g, double qx, double qy, double ca, double cb) {
            const double qq = qx * qx + qy * qy;
            const double da = g.ax * qx + g.ay * qy > 0 ? ca * ca * g.inv_a : qq;
            const double db = g.bx * qx + g.by * qy > 0 ? cb * cb * g.inv_b : qq;
            return std::min(da, db);
        }

        // The triangle of the star nearest p, and p's closest point on it, as the measure finds
        // it: the first triangle whose wedge holds p's projection, unless another is nearer (the
        // first of the nearest, if none holds it).
        std::pair<size_t, ClosestPoint> closest(const Star& star, const Vec3& p) {
            const std::array<double, 2> q = star.project(p);
            const double qx = q[0] - cx[0], qy = q[1] - cx[1];
            const size_t n = wedge.size();
            auto cross_with = [&](size_t i) {
                const Wedge& g = wedge[i];
                cross[i] = {g.ax * qy - g.ay * qx, qx * g.by - qy * g.bx};
            };
            size_t on = n;
            for (size_t i = 0; i < n; ++i) {
                cross_with(i);
                if (cross[i][0] >= 0 && cross[i][1] >= 0) {
                    on = i;
                    break;
                }
            }
            const bool over = on < n;
            if (!over) on = 0;
            ClosestPoint at = closest_on_triangle(p, x, star.points[on][1], star.points[on][2]);
            double nearest = dot(sub(at.point, p), sub(at.point, p));
            const double margin = 1 + kOrderMargin; // a bound within rounding rules nothing out
            if (over && apart &&
                edge_distance(wedge[on], qx, qy, cross[on][0], cross[on][1]) > nearest * margin)
                return {on, at};
            for (size_t i = 0; i < n; ++i) {
                if (i == on) continue;
                const Wedge& g = wedge[i];
                if (over && i > on) cross_with(i); // the search stopped before it
                const double ca = cross[i][0], cb = cross[i][1];
                if (g.open && !(ca >= 0 && cb >= 0) &&
                    edge_distance(g, qx, qy, ca, cb) > nearest * margin)
                    continue;
                const ClosestPoint c =
                    closest_on_triangle(p, x, star.points[i][1], star.points[i][2]);
                const double d = dot(sub(c.point, p), sub(c.point, p));
                if (d < nearest) nearest = d, on = i, at = c;
            }
            return {on, at};
        }
    };
    // A candidate's landings: per landed point its error and where it landed, the centre's input
    // vertex in slot 0 and the star's sample n in slot 1 + n.
    struct Landings {
        std::vector<double> error;
        std::vector<Landing> at;
    };
    struct Scratch {
        Star star;
        StarSamples samples;
        Landings landings, chosen_landings;
        std::vector<std::pair<double, uint32_t>> order;
    };

    Corners corners(uint32_t t) const {
        const uint32_t* k = &level_.triangles[3 * size_t(t)];
        return {k[0], k[1], k[2]};
    }
    int corner_of(uint32_t t, uint32_t v) const {
        const Corners k = corners(t);
        return k[0] == v ? 0 : k[1] == v ? 1 : 2;
    }
    Vec3 point(uint32_t v) const { return point_of(level_.positions, v); }

    bool on_line(uint32_t i) const { return !boundary_line_.empty() && boundary_line_[i]; }

    // v's star as a fan, each neighbour on one or two of its triangles: how many are on one (0: a
    // closed fan, v interior; 2: v on a boundary it passes once, those two its neighbours along
    // it, into `ends`), or -1 if it is neither.
    int fan_ends(uint32_t v, std::array<uint32_t, 2>& ends) const {
        std::vector<uint32_t> ring;
        for (uint32_t p = stars_.begin[v]; p < stars_.begin[v + 1]; ++p)
            for (uint32_t k : corners(stars_.triangle[p]))
                if (k != v) ring.push_back(k);
        if (ring.empty()) return -1;
        std::sort(ring.begin(), ring.end());
        int once = 0;
        for (size_t i = 0; i < ring.size();) {
            size_t j = i;
            while (j < ring.size() && ring[j] == ring[i]) ++j;
            if (j - i > 2 || (j - i == 1 && once == 2)) return -1;
            if (j - i == 1) ends[size_t(once++)] = ring[i];
            i = j;
        }
        return once == 1 ? -1 : once;
    }

    // The triangle of v's star with corner k (on a boundary fan's end, there is one).
    uint32_t star_triangle_with(uint32_t v, uint32_t k) const {
        for (uint32_t p = stars_.begin[v]; p < stars_.begin[v + 1]; ++p) {
            const Corners c = corners(stars_.triangle[p]);
            if (c[0] == k || c[1] == k || c[2] == k) return stars_.triangle[p];
        }
        return kNoOwner;
    }

    // Input vertex i's joint coordinates.
    void joint(uint32_t i, double* out) const {
        const Vec3 p = point_of(in_.positions, i);
        for (size_t k = 0; k < 3; ++k) out[k] = scale_[0] * p[k];
        for (size_t j = 0; j < input_.components.size(); ++j) {
            const auto [field, component] = input_.components[j];
            const Field& f = in_.fields[field];
            out[3 + j] = scale_[1 + j] * double(f.values[size_t(f.components) * i + component]);
        }
    }

    // The residual of a sample with joint coordinates `own` landed on the star's triangle i with
    // weights w (in the star's order) and the centre's joint coordinates `centre`: the joint
    // coordinates there less its own, into r. Returns its squared length, the sample's error.
    double residual(const Star& star, size_t i, const double* centre,
                    const std::array<double, 3>& w, const double* own, double* r) const {
        const double *j1 = &star.ring_joint[(2 * i) * dims_],
                     *j2 = &star.ring_joint[(2 * i + 1) * dims_];
        double e = 0;
        for (size_t d = 0; d < dims_; ++d) {
            r[d] = w[0] * centre[d] + w[1] * j1[d] + w[2] * j2[d] - own[d];
            e += r[d] * r[d];
        }
        return e;
    }

    void star_of(uint32_t v, Star& star) const {
        star.clear();
        star.centre = v;
        Vec3 axis{0, 0, 0};
        star.centre_joint.resize(dims_);
        joint(source_[v], star.centre_joint.data());
        for (uint32_t p = stars_.begin[v]; p < stars_.begin[v + 1]; ++p) {
            const uint32_t t = stars_.triangle[p];
            const int c = corner_of(t, v);
            const Corners k = corners(t);
            // The centre first, the triangle's orientation kept.
            const uint32_t n1 = k[size_t((c + 1) % 3)], n2 = k[size_t((c + 2) % 3)];
            star.triangle.push_back(t);
            star.points.push_back({point(v), point(n1), point(n2)});
            std::array<uint8_t, 3> o{};
            o[size_t(c)] = 0, o[size_t((c + 1) % 3)] = 1, o[size_t((c + 2) % 3)] = 2;
            star.order.push_back(o);
            const Vec3 n = cross(sub(point(n1), point(v)), sub(point(n2), point(v)));
            star.normal.push_back(n);
            star.area += norm(n);
            axis = add(axis, n);
            for (uint32_t k : {n1, n2}) {
                star.ring_joint.resize(star.ring_joint.size() + dims_);
                joint(source_[k], &star.ring_joint[star.ring_joint.size() - dims_]);
            }
        }
        // The plane across the mean normal.
        const double length = norm(axis);
        const auto across = plane_across(length > 0 ? scale(axis, 1 / length) : Vec3{0, 0, 1});
        star.e1 = across[0], star.e2 = across[1];
        for (const auto& p : star.points) {
            const auto a = star.project(p[1]), b = star.project(p[2]);
            star.ring_2d.push_back({a[0], a[1], b[0], b[1]});
        }
    }

    // The star's samples but sample `to`, and the centre's input vertex, each landed at its
    // closest point on the star with the centre at sample `to` (CentredStar::closest), the
    // samples in `order`, into `landings`: their total error in that order, or infinity once it
    // reaches `bound`.
    double land_all(const Star& star, const StarSamples& samples, uint32_t to, double bound,
                    const std::vector<uint32_t>& order, Landings& landings) const {
        const Vec3 x = point_of(in_.positions, samples.vertex[to]);
        const double* centre = &samples.joint[to * dims_];
        landings.error.resize(samples.vertex.size() + 1);
        landings.at.resize(samples.vertex.size() + 1);
        std::array<double, kMaxDims> r;
        static thread_local CentredStar centred;
        centred.centre_at(star, x);
        auto land = [&](uint32_t s, const double* own, size_t slot) {
            const auto [on, closest] = centred.closest(star, point_of(in_.positions, s));
            landings.error[slot] = residual(star, on, centre, closest.weights, own, r.data());
            Landing& at = landings.at[slot];
            at.triangle = star.triangle[on];
            for (size_t k = 0; k < 3; ++k) at.weights[k] = closest.weights[star.order[on][k]];
            return landings.error[slot];
        };
        double total = land(source_[star.centre], star.centre_joint.data(), 0);
        for (const uint32_t i : order)
            if (i != to) {
                if (total >= bound) return kInfinity;
                total += land(samples.vertex[i], &samples.joint[i * dims_], 1 + i);
            }
        return total;
    }

    // The total error of land_all's landings summed as land_all sums them in the samples' own
    // order: the centre's input vertex first, infinity once the sum reaches `bound`.
    static double in_sample_order(const Landings& landings, uint32_t to, size_t count,
                                  double bound) {
        double total = landings.error[0];
        for (uint32_t n = 0; n < count; ++n)
            if (n != to) {
                if (total >= bound) return kInfinity;
                total += landings.error[1 + n];
            }
        return total;
    }

    const RefitInput& input_;
    const Surface& in_;
    const std::vector<uint8_t>& locked_;
    const std::vector<uint8_t>& boundary_line_;
    std::vector<uint32_t>& source_;
    std::vector<Landing>& forward_;
    Surface& level_;
    const Stars stars_;
    const size_t dims_;
    const double keep_cos_;     // move_cos(input_)
    std::vector<double> scale_; // the square root of the distance's weight, then each datum's
    std::vector<uint32_t> head_, next_;
};

} // namespace

std::vector<uint32_t>
relocate_level_vertices(const RefitInput& input, const std::vector<uint8_t>& locked,
                        const std::vector<uint8_t>& boundary_line, std::vector<uint32_t>& source,
                        std::vector<Landing>& forward, Surface& level, Parallel& parallel,
                        const std::vector<uint32_t>& from) {
    std::vector<uint32_t> moved_ones;
    if (!(move_cos(input) <= 1) || level.triangle_count() < 2 ||
        input.components.size() > kMaxComponents)
        return moved_ones;
    LevelRelocation relocation(input, locked, boundary_line, source, forward, level);
    const size_t nv = relocation.vertex_count();
    std::vector<uint32_t> sweep = from;
    std::vector<uint8_t> in_sweep(nv, 0);
    std::vector<uint32_t> waiting(nv, 0); // per vertex: its neighbours before it in the sweep
    // Every move lowers the samples' error, so the sweeps would end; most of what they gain is
    // gained in the first three, and each costs about as much as the one before.
    constexpr uint32_t kMaxSweeps = 3;
    for (uint32_t round = 1; round <= kMaxSweeps && !sweep.empty() && !parallel.stopped();
         ++round) {
        // The sweep takes its vertices in order, each finding its best move as the moves before
        // it left the level. A vertex's move depends only on the moves of its neighbours before
        // it: so each step finds and makes, on the threads, the moves of the vertices whose
        // neighbours before them are all done. No two of them are neighbours, so no move changes
        // a star another reads.
        for (uint32_t v : sweep) in_sweep[v] = 1;
        parallel.for_each(sweep.size(), [&](size_t i) {
            const uint32_t v = sweep[i];
            relocation.for_each_near(v, [&](uint32_t k) { waiting[v] += k < v && in_sweep[k]; });
        });
        std::vector<uint32_t> ready, near;
        for (uint32_t v : sweep)
            if (waiting[v] == 0) ready.push_back(v);
        std::vector<uint8_t> moved;
        while (!ready.empty() && !parallel.stopped()) {
            moved.assign(ready.size(), 0);
            parallel.for_each(
                ready.size(),
                [&](size_t i) {
                    Move move = relocation.best_move(ready[i]);
                    if (move.to == kNoOwner) return;
                    relocation.apply(ready[i], move);
                    moved[i] = 1;
                },
                16);
            std::vector<uint32_t> next;
            for (size_t i = 0; i < ready.size(); ++i) {
                const uint32_t v = ready[i];
                in_sweep[v] = 0;
                relocation.for_each_near(v, [&](uint32_t k) {
                    if (k > v && in_sweep[k] && --waiting[k] == 0) next.push_back(k);
                    if (moved[i]) near.push_back(k);
                });
                if (moved[i]) moved_ones.push_back(v);
            }
            std::sort(next.begin(), next.end());
            ready.swap(next);
        }
        std::sort(near.begin(), near.end());
        near.erase(std::unique(near.begin(), near.end()), near.end());
        sweep.swap(near);
    }
    std::sort(moved_ones.begin(), moved_ones.end());
    moved_ones.erase(std::unique(moved_ones.begin(), moved_ones.end()), moved_ones.end());
    return moved_ones;
}

void settle_level(const RefitInput& input, const std::vector<uint8_t>& locked,
                  const std::vector<uint8_t>& boundary_line, std::vector<uint32_t>& source,
                  std::vector<Landing>& forward, Surface& level, Parallel& parallel) {
    std::vector<uint32_t> changed(level.vertex_count());
    std::iota(changed.begin(), changed.end(), 0u);
    // Every move and every flip lowers the samples' error, so the turns would end; most levels
    // settle in three to six turns, the later ones changing a few vertices. The bound caps a level
    // whose turns keep making room for more.
    constexpr int kMaxTurns = 8;
    for (int turn = 0; turn < kMaxTurns && !changed.empty(); ++turn) {
        const std::vector<uint32_t> moved = relocate_level_vertices(
            input, locked, boundary_line, source, forward, level, parallel, changed);
        if (parallel.stopped() || (turn > 0 && moved.empty())) return;
        // Most of the work is in the first turn, less in each after it.
        parallel.reach((turn + 0.5) / (turn + 2));
        changed =
            flip_edges_for_data(input, forward, level, parallel, turn == 0 ? nullptr : &moved);
        parallel.reach((turn + 1.0) / (turn + 2));
    }
}

} // namespace ddsimp::detail
