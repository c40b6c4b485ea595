// The error of a level (ProgressiveRecord::error_after): none for the input, never falling as
// the level coarsens, equal at every operation to the definition evaluated the slow way from the
// public API (edge collapse: explicit distances to the input triangles' planes and interpolation
// on them; vertex removal: removed vertices followed to the triangles that cover them, and never
// nearer to the level than the error says), and 0 where nothing is lost (flat, linear data).
#include "test_surfaces.h"

namespace ddsimp::test {
namespace {

struct TermsConfig {
    Config config;
    Terms terms;
};

std::vector<TermsConfig> terms_configs() {
    std::vector<TermsConfig> out;
    for (const Config& c : all_configs())
        for (Terms t : {Terms::ErrorQuadrics, Terms::AngleDeficitGradient}) out.push_back({c, t});
    return out;
}

std::string terms_config_name(const ::testing::TestParamInfo<TermsConfig>& info) {
    return std::string(info.param.config.name) +
           (info.param.terms == Terms::ErrorQuadrics ? "Quadrics" : "Paper");
}

class LevelErrors : public ::testing::TestWithParam<TermsConfig> {
protected:
    Options record_options() const {
        Options o = options_for(GetParam().config);
        o.terms = GetParam().terms;
        o.keep_fraction = 0.0; // every operation until nothing more is removable
        return o;
    }
};

INSTANTIATE_TEST_SUITE_P(All, LevelErrors, ::testing::ValuesIn(terms_configs()), terms_config_name);

// A height field with a boundary: z = 0.08 sin(5x) cos(4y) over the unit square.
Surface bumpy_grid(int n) {
    Surface s = grid(n, n);
    for (size_t v = 0; v < s.vertex_count(); ++v)
        s.positions[3 * v + 2] =
            float(0.08 * std::sin(5 * s.positions[3 * v]) * std::cos(4 * s.positions[3 * v + 1]));
    return s;
}

// LevelError's definition for edge collapse, the slow way. Every input triangle and every
// boundary edge is a plane; a vertex stands for a weighted set of them (an input vertex: its
// triangles and boundary edges once each; a collapse: the union of its ends' sets, weights
// added). Also the positions and data of vertex removal's measure.
class BruteForce {
public:
    using Region = std::map<size_t, double>; // plane -> weight

    BruteForce(const ProgressiveRecord& rec, const std::vector<std::string>& fields)
        : v_(rec.vertices()), input_(rec.indexed_triangles(0)) {
        std::set<uint32_t> used(input_.begin(), input_.end());
        Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t v : used)
            for (int k = 0; k < 3; ++k)
                lo[k] = std::min(lo[k], position(v_, v)[k]),
                hi[k] = std::max(hi[k], position(v_, v)[k]);
        diagonal_ = norm(hi - lo);
        for (size_t f = 0; f < v_.fields.size(); ++f) {
            const Field& field = v_.fields[f];
            if (!fields.empty() &&
                std::find(fields.begin(), fields.end(), field.name) == fields.end())
                continue;
            double range = 0;
            for (int c = 0; c < field.components; ++c) {
                double a = INFINITY, b = -INFINITY;
                for (uint32_t v : used)
                    a = std::min(a, double(field.values[v * field.components + c])),
                    b = std::max(b, double(field.values[v * field.components + c]));
                range = std::max(range, b - a);
            }
            if (range > 0)
                for (int c = 0; c < field.components; ++c) components_.push_back({f, c, range});
        }
        // Planes: the triangles, then the boundary edges (used by one triangle).
        std::map<std::pair<uint32_t, uint32_t>, int> uses;
        for (size_t i = 0; i < input_.size(); ++i)
            ++uses[std::minmax(input_[i], input_[i % 3 == 2 ? i - 2 : i + 1])];
        for (size_t t = 0; 3 * t < input_.size(); ++t) {
            const Vec3 a = at(input_[3 * t]), b = at(input_[3 * t + 1]), c = at(input_[3 * t + 2]);
            const Vec3 n = cross(b - a, c - a);
            planes_.push_back({0.5 * norm(n), (1 / norm(n)) * n, a, t});
            for (uint32_t corner : {input_[3 * t], input_[3 * t + 1], input_[3 * t + 2]})
                region_[corner][t] += 1;
        }
        for (size_t i = 0; i < input_.size(); ++i) {
            const uint32_t a = input_[i], b = input_[i % 3 == 2 ? i - 2 : i + 1];
            if (uses[std::minmax(a, b)] != 1) continue;
            const size_t t = i / 3;
            const Vec3 edge = at(b) - at(a);
            const Vec3 across = cross(edge, planes_[t].unit);
            const size_t plane = planes_.size();
            planes_.push_back({dot(edge, edge), (1 / norm(across)) * across, at(a), kNotATriangle});
            region_[a][plane] += 1;
            region_[b][plane] += 1;
        }
    }

    size_t components() const { return components_.size(); }
    Region& region(uint32_t v) { return region_[v]; }

    // Position in diagonals; data of vertex v in field ranges.
    Vec3 at(uint32_t v) const { return (1 / diagonal_) * position(v_, v); }
    std::vector<double> data(uint32_t v) const {
        std::vector<double> s;
        for (const auto& c : components_) {
            const Field& f = v_.fields[c.field];
            s.push_back(f.values[v * f.components + c.component] / c.range);
        }
        return s;
    }

    // {geometric, data} RMS error of a region at position p (diagonals) with data s (ranges).
    std::pair<double, double> error(const Region& region, const Vec3& p,
                                    const std::vector<double>& s) const {
        double g = 0, gw = 0, d = 0, dw = 0;
        for (const auto& [index, weight] : region) {
            const Plane& plane = planes_[index];
            const double distance = dot(plane.unit, p - plane.point);
            g += weight * plane.weight * distance * distance;
            gw += weight * plane.weight;
            if (plane.triangle == kNotATriangle || components_.empty()) continue;
            // p projected into the triangle's plane, in barycentric coordinates (extended
            // outside the triangle): r = u e1 + v e2 in the least-squares sense.
            const uint32_t* c = &input_[3 * plane.triangle];
            const Vec3 e1 = at(c[1]) - at(c[0]), e2 = at(c[2]) - at(c[0]), r = p - at(c[0]);
            const double a11 = dot(e1, e1), a12 = dot(e1, e2), a22 = dot(e2, e2);
            const double det = a11 * a22 - a12 * a12;
            const double u = (dot(r, e1) * a22 - dot(r, e2) * a12) / det;
            const double v = (dot(r, e2) * a11 - dot(r, e1) * a12) / det;
            const std::vector<double> s0 = data(c[0]), s1 = data(c[1]), s2 = data(c[2]);
            for (size_t j = 0; j < s.size(); ++j) {
                const double interpolated = s0[j] + u * (s1[j] - s0[j]) + v * (s2[j] - s0[j]);
                d += weight * plane.weight * (s[j] - interpolated) * (s[j] - interpolated);
            }
            dw += weight * plane.weight * double(s.size());
        }
        return {gw > 0 ? std::sqrt(g / gw) : 0.0, dw > 0 ? std::sqrt(d / dw) : 0.0};
    }

private:
    static constexpr size_t kNotATriangle = SIZE_MAX;
    struct Plane {
        double weight; // a triangle's area, or a boundary edge's squared length
        Vec3 unit;     // normal
        Vec3 point;    // a point on it
        size_t triangle;
    };
    struct Component {
        size_t field;
        int component;
        double range;
    };
    const Surface& v_;
    std::vector<uint32_t> input_;
    double diagonal_ = 0;
    std::vector<Component> components_;
    std::vector<Plane> planes_;
    std::map<uint32_t, Region> region_;
};

std::set<uint32_t> vertices_of(const std::vector<uint32_t>& triangles) {
    return {triangles.begin(), triangles.end()};
}

// Triangles as sorted corner triples.
std::set<std::array<uint32_t, 3>> triangle_set(const std::vector<uint32_t>& triangles) {
    std::set<std::array<uint32_t, 3>> out;
    for (size_t t = 0; t < triangles.size(); t += 3) {
        std::array<uint32_t, 3> c{triangles[t], triangles[t + 1], triangles[t + 2]};
        std::sort(c.begin(), c.end());
        out.insert(c);
    }
    return out;
}

// The point of segment ab closest to p.
Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const double t = std::clamp(dot(p - a, b - a) / dot(b - a, b - a), 0.0, 1.0);
    return a + t * (b - a);
}

// Checks error_after(i) against the brute force after every operation of `rec`.
void expect_brute_force_errors(const ProgressiveRecord& rec, const std::vector<std::string>& fields,
                               Strategy strategy) {
    BruteForce brute(rec, fields);
    ASSERT_EQ(rec.error_after(0).data_components, brute.components());
    double geometric = 0, data = 0;
    auto count = [&](const std::pair<double, double>& e) {
        geometric = std::max(geometric, e.first), data = std::max(data, e.second);
    };
    std::map<uint32_t, std::array<uint32_t, 3>> cover; // vertex removal: removed vertex -> triangle
    std::vector<uint32_t> now = rec.indexed_triangles(0);
    for (size_t i = 0; i < rec.operations(); ++i) {
        const std::vector<uint32_t> next = rec.indexed_triangles(i + 1);
        const std::set<uint32_t> before = vertices_of(now), after = vertices_of(next);
        std::vector<uint32_t> gone, made;
        std::set_difference(before.begin(), before.end(), after.begin(), after.end(),
                            std::back_inserter(gone));
        std::set_difference(after.begin(), after.end(), before.begin(), before.end(),
                            std::back_inserter(made));
        if (strategy == Strategy::EdgeCollapse) {
            ASSERT_EQ(gone.size(), 2u) << "operation " << i;
            ASSERT_EQ(made.size(), 1u) << "operation " << i;
            BruteForce::Region& region = brute.region(made[0]);
            for (uint32_t g : gone)
                for (const auto& [plane, w] : brute.region(g)) region[plane] += w;
            count(brute.error(region, brute.at(made[0]), brute.data(made[0])));
        } else {
            ASSERT_EQ(gone.size(), 1u) << "operation " << i;
            ASSERT_TRUE(made.empty()) << "operation " << i;
            const auto old_set = triangle_set(now), new_set = triangle_set(next);
            std::vector<std::array<uint32_t, 3>> fresh, vanished;
            std::set_difference(new_set.begin(), new_set.end(), old_set.begin(), old_set.end(),
                                std::back_inserter(fresh));
            std::set_difference(old_set.begin(), old_set.end(), new_set.begin(), new_set.end(),
                                std::back_inserter(vanished));
            ASSERT_FALSE(fresh.empty()) << "operation " << i;
            // The removed vertex, and those whose covering triangle vanished, are covered by
            // the nearest new triangle and measured against its nearest point.
            std::vector<uint32_t> points{gone[0]};
            for (const auto& [p, t] : cover)
                if (std::binary_search(vanished.begin(), vanished.end(), t)) points.push_back(p);
            for (uint32_t p : points) {
                const Vec3 x = brute.at(p);
                double best = INFINITY;
                std::vector<double> s;
                for (const auto& c : fresh) {
                    const Vec3 a = brute.at(c[0]), b = brute.at(c[1]), d = brute.at(c[2]);
                    const Vec3 n = cross(b - a, d - a);
                    Vec3 q = x - (dot(x - a, n) / dot(n, n)) * n;
                    const bool inside = dot(cross(b - a, q - a), n) >= 0 &&
                                        dot(cross(d - b, q - b), n) >= 0 &&
                                        dot(cross(a - d, q - d), n) >= 0;
                    if (!inside) {
                        q = closest_on_segment(x, a, b);
                        for (const Vec3& e :
                             {closest_on_segment(x, b, d), closest_on_segment(x, d, a)})
                            if (norm(e - x) < norm(q - x)) q = e;
                    }
                    // Equally near (within rounding): the lower sorted corner ids (LevelError's
                    // definition).
                    const double distance = norm(q - x);
                    const bool tie = std::abs(distance - best) <= 1e-12;
                    if (tie ? !(c < cover[p]) : !(distance < best)) continue;
                    best = distance, cover[p] = c;
                    // The data there: barycentric weights from sub-triangle areas.
                    const double area = norm(n);
                    const double wa = norm(cross(b - q, d - q)) / area,
                                 wb = norm(cross(d - q, a - q)) / area, wd = 1 - wa - wb;
                    const auto sa = brute.data(c[0]), sb = brute.data(c[1]), sd = brute.data(c[2]),
                               sp = brute.data(p);
                    double squares = 0;
                    for (size_t j = 0; j < sp.size(); ++j) {
                        const double diff = sp[j] - (wa * sa[j] + wb * sb[j] + wd * sd[j]);
                        squares += diff * diff;
                    }
                    s = {sp.empty() ? 0.0 : std::sqrt(squares / double(sp.size()))};
                }
                count({best, s[0]});
            }
            // Independently of which triangle covers what: no input vertex is farther from the
            // level than the error says (the distance to the nearest of all its triangles).
            double farthest = 0;
            for (const auto& [p, t] : cover) {
                double nearest = INFINITY;
                for (const auto& c : new_set) {
                    const Vec3 x = brute.at(p), a = brute.at(c[0]), b = brute.at(c[1]),
                               d = brute.at(c[2]);
                    const Vec3 n = cross(b - a, d - a);
                    const Vec3 q = x - (dot(x - a, n) / dot(n, n)) * n;
                    double distance = std::min({norm(closest_on_segment(x, a, b) - x),
                                                norm(closest_on_segment(x, b, d) - x),
                                                norm(closest_on_segment(x, d, a) - x)});
                    if (dot(cross(b - a, q - a), n) >= 0 && dot(cross(d - b, q - b), n) >= 0 &&
                        dot(cross(a - d, q - d), n) >= 0)
                        distance = norm(q - x);
                    nearest = std::min(nearest, distance);
                }
                farthest = std::max(farthest, nearest);
            }
            ASSERT_GE(rec.error_after(i + 1).geometric, farthest - 1e-6) << "operation " << i;
        }
        const LevelError e = rec.error_after(i + 1);
        ASSERT_NEAR(e.geometric, geometric, 2e-6 + 1e-4 * geometric) << "operation " << i;
        ASSERT_NEAR(e.data, data, 2e-6 + 1e-4 * data) << "operation " << i;
        now = next;
    }
}

TEST_P(LevelErrors, NoneBeforeAnyOperationNeverFallingAfter) {
    const Surface in = with_test_fields(icosphere(3));
    const ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
    ASSERT_GT(rec.operations(), 100u);
    const LevelError zero = rec.error_after(0);
    EXPECT_EQ(zero.geometric, 0.0f);
    EXPECT_EQ(zero.data, 0.0f);
    EXPECT_EQ(zero.data_components, 4u); // pressure and the 3 components of velocity
    LevelError last = zero;
    for (size_t i = 1; i <= rec.operations(); ++i) {
        const LevelError e = rec.error_after(i);
        ASSERT_GE(e.geometric, last.geometric) << "operation " << i;
        ASSERT_GE(e.data, last.data) << "operation " << i;
        last = e;
    }
    // A sphere coarsened to a handful of triangles is off by a good fraction of its size.
    EXPECT_GT(last.geometric, 0.01f);
    EXPECT_GT(last.data, 0.01f);
    // Past the end: the last level's.
    EXPECT_EQ(rec.error_after(rec.operations() + 5).geometric, last.geometric);
}

TEST_P(LevelErrors, EqualTheDefinitionEvaluatedTheSlowWay) {
    for (const Surface& in : {with_test_fields(icosphere(2)), with_test_fields(bumpy_grid(12))}) {
        const ProgressiveRecord rec = ProgressiveRecord::build(in, record_options());
        ASSERT_GT(rec.operations(), 50u);
        expect_brute_force_errors(rec, {}, GetParam().config.strategy);
    }
}

TEST_P(LevelErrors, OnlyTheFieldsThatDriveTheWeightCount) {
    Options o = record_options();
    o.gradient_fields = {"pressure"};
    const ProgressiveRecord rec = ProgressiveRecord::build(with_test_fields(bumpy_grid(10)), o);
    EXPECT_EQ(rec.error_after(0).data_components, 1u);
    expect_brute_force_errors(rec, o.gradient_fields, GetParam().config.strategy);
}

// A flat plane with linear data loses nothing at any level; with data that is not linear, only
// the data error grows.
TEST_P(LevelErrors, FlatAndLinearLosesNothing) {
    Surface linear = grid(16, 16);
    add_field(linear, "ramp", 1,
              [](const Vec3& p) { return std::vector<double>{2 * p[0] + 3 * p[1]}; });
    Surface wavy = grid(16, 16);
    add_field(wavy, "wave", 1, [](const Vec3& p) {
        return std::vector<double>{std::sin(6 * p[0]) * std::cos(5 * p[1])};
    });
    const ProgressiveRecord flat = ProgressiveRecord::build(linear, record_options());
    const ProgressiveRecord waves = ProgressiveRecord::build(wavy, record_options());
    ASSERT_LT(flat.triangles_after(flat.operations() - 1), 100u);
    ASSERT_LT(waves.triangles_after(waves.operations() - 1), 100u);
    const LevelError a = flat.error_after(flat.operations());
    const LevelError b = waves.error_after(waves.operations());
    EXPECT_LE(a.geometric, 1e-6f);
    EXPECT_LE(a.data, 1e-6f);
    EXPECT_LE(b.geometric, 1e-6f);
    EXPECT_GT(b.data, 0.01f);
}

TEST(LevelErrorsWithoutData, MeasureGeometryOnly) {
    Surface constant = icosphere(2);
    add_field(constant, "constant", 1, [](const Vec3&) { return std::vector<double>{4.0}; });
    Options o;
    o.keep_fraction = 0.0;
    for (const Surface& in : {icosphere(2), constant}) {
        const ProgressiveRecord rec = ProgressiveRecord::build(in, o);
        const LevelError e = rec.error_after(rec.operations());
        EXPECT_EQ(e.data_components, 0u);
        EXPECT_EQ(e.data, 0.0f);
        EXPECT_GT(e.geometric, 0.01f);
    }
}

} // namespace
} // namespace ddsimp::test
