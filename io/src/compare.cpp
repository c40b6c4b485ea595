#include "ddsimp/io/compare.h"

#include "ddsimp/io/triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddsimp::tools {

namespace {

// Squared errors gathered over one direction's samples.
struct Accumulator {
    double sum_squares = 0;
    double max = 0;
    size_t count = 0;
    void add(double error) {
        sum_squares += error * error;
        max = std::max(max, error);
        ++count;
    }
    ErrorStats stats(double scale) const {
        return {count ? std::sqrt(sum_squares / double(count)) / scale : 0.0, max / scale};
    }
};

TwoWayError combine(const Accumulator& forward, const Accumulator& backward, double scale) {
    Accumulator both = forward;
    both.sum_squares += backward.sum_squares;
    both.max = std::max(both.max, backward.max);
    both.count += backward.count;
    return {forward.stats(scale), backward.stats(scale), both.stats(scale)};
}

void check_surface(const Surface& s, const char* which) {
    if (s.triangle_count() == 0)
        throw InputError(std::string("the ") + which + " surface has no triangles");
    if (s.positions.size() % 3 != 0 || s.triangles.size() % 3 != 0)
        throw InputError(std::string("the ") + which + " surface is malformed");
    for (uint32_t v : s.triangles)
        if (v >= s.vertex_count())
            throw InputError(std::string("the ") + which + " surface refers to vertex " +
                             std::to_string(v) + " of " + std::to_string(s.vertex_count()));
}

double bounding_box_diagonal(const Surface& s) {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (uint32_t v : s.triangles)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(s.positions[3 * v + a]));
            hi[a] = std::max(hi[a], double(s.positions[3 * v + a]));
        }
    return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

double field_range(const Surface& s, const Field& f) {
    double sum = 0;
    for (int c = 0; c < f.components; ++c) {
        double lo = INFINITY, hi = -INFINITY;
        for (uint32_t v : s.triangles) {
            const double x = f.values[size_t(v) * f.components + c];
            lo = std::min(lo, x), hi = std::max(hi, x);
        }
        sum += (hi - lo) * (hi - lo);
    }
    const double range = std::sqrt(sum);
    return range > 0 ? range : 1.0;
}

std::vector<uint8_t> used_vertices(const Surface& s) {
    std::vector<uint8_t> used(s.vertex_count(), 0);
    for (uint32_t v : s.triangles) used[v] = 1;
    return used;
}

// One direction: every used vertex of `from` against the surface `to`.
void measure(const Surface& from, const Surface& to, const std::vector<const Field*>& from_fields,
             const std::vector<const Field*>& to_fields, Accumulator& distance,
             std::vector<Accumulator>& data) {
    const TriangleBvh bvh(to.positions, to.triangles);
    const std::vector<uint8_t> used = used_vertices(from);
    uint32_t hint = UINT32_MAX;
    for (size_t v = 0; v < from.vertex_count(); ++v) {
        if (!used[v]) continue;
        const double q[3] = {from.positions[3 * v], from.positions[3 * v + 1],
                             from.positions[3 * v + 2]};
        // Consecutive vertices are usually close, so the last answer is a good first guess.
        const ClosestPoint hit = bvh.closest(q, hint);
        hint = hit.triangle;
        distance.add(std::sqrt(hit.distance_squared));
        const uint32_t* corners = &to.triangles[3 * size_t(hit.triangle)];
        for (size_t f = 0; f < from_fields.size(); ++f) {
            const Field& a = *from_fields[f];
            const Field& b = *to_fields[f];
            const size_t k = size_t(a.components);
            double squares = 0;
            for (size_t c = 0; c < k; ++c) {
                double interpolated = 0;
                for (int i = 0; i < 3; ++i)
                    interpolated += hit.barycentric[i] * b.values[corners[i] * k + c];
                const double d = a.values[v * k + c] - interpolated;
                squares += d * d;
            }
            data[f].add(std::sqrt(squares));
        }
    }
}

} // namespace

CompareReport compare_surfaces(const Surface& original, const Surface& reduced,
                               const std::vector<std::string>& fields) {
    check_surface(original, "original");
    check_surface(reduced, "reduced");

    std::vector<const Field*> original_fields, reduced_fields;
    auto pair_up = [&](const std::string& name, bool required) {
        const Field* a = original.find_field(name);
        const Field* b = reduced.find_field(name);
        if (a == nullptr || b == nullptr) {
            if (!required) return;
            throw InputError("no field '" + name + "' in the " + (a ? "reduced" : "original") +
                             " surface");
        }
        if (a->components != b->components) {
            if (!required) return; // not asked for by name: compare what can be compared
            throw InputError("field '" + name + "' has " + std::to_string(a->components) +
                             " components in the original but " + std::to_string(b->components) +
                             " in the reduced surface");
        }
        if (a->values.size() != original.vertex_count() * size_t(a->components) ||
            b->values.size() != reduced.vertex_count() * size_t(b->components))
            throw InputError("field '" + name + "' does not have one value per vertex");
        original_fields.push_back(a);
        reduced_fields.push_back(b);
    };
    if (fields.empty())
        for (const Field& f : original.fields) pair_up(f.name, false);
    else
        for (const std::string& name : fields) pair_up(name, true);

    CompareReport report;
    report.diagonal = bounding_box_diagonal(original);
    const double diagonal = report.diagonal > 0 ? report.diagonal : 1.0;

    Accumulator distance_forward, distance_backward;
    std::vector<Accumulator> data_forward(original_fields.size());
    std::vector<Accumulator> data_backward(original_fields.size());
    measure(original, reduced, original_fields, reduced_fields, distance_forward, data_forward);
    measure(reduced, original, reduced_fields, original_fields, distance_backward, data_backward);

    report.original_samples = distance_forward.count;
    report.reduced_samples = distance_backward.count;
    report.distance = combine(distance_forward, distance_backward, diagonal);
    for (size_t f = 0; f < original_fields.size(); ++f) {
        FieldError error;
        error.name = original_fields[f]->name;
        error.components = original_fields[f]->components;
        error.range = field_range(original, *original_fields[f]);
        error.error = combine(data_forward[f], data_backward[f], error.range);
        report.fields.push_back(std::move(error));
    }
    return report;
}

} // namespace ddsimp::tools
