#include "polygons.h"

#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolygon.h>

#include <array>
#include <cmath>

namespace ddsimp::io {

namespace {

using Vec = std::array<double, 3>;

Vec point(const std::vector<float>& positions, uint32_t v) {
    return {positions[3 * size_t(v)], positions[3 * size_t(v) + 1], positions[3 * size_t(v) + 2]};
}
Vec sub(const Vec& a, const Vec& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The face's area vector (Newell's method): its direction is the face's normal for any simple
// polygon, convex or not.
Vec newell_normal(const std::vector<float>& positions, const uint32_t* corners, size_t n) {
    Vec normal{0, 0, 0};
    for (size_t i = 0; i < n; ++i) {
        const Vec a = point(positions, corners[i]), b = point(positions, corners[(i + 1) % n]);
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    return normal;
}

double facing(const std::vector<float>& positions, uint32_t a, uint32_t b, uint32_t c,
              const Vec& normal) {
    const Vec pa = point(positions, a);
    return dot(cross(sub(point(positions, b), pa), sub(point(positions, c), pa)), normal);
}

void push(std::vector<uint32_t>& triangles, uint32_t a, uint32_t b, uint32_t c) {
    triangles.push_back(a), triangles.push_back(b), triangles.push_back(c);
}

} // namespace

void PolygonSplitter::split(const std::vector<float>& positions, const uint32_t* corners, size_t n,
                            std::vector<uint32_t>& triangles) {
    if (n < 3) {
        ++dropped_;
        return;
    }
    if (n == 3) {
        push(triangles, corners[0], corners[1], corners[2]);
        return;
    }
    made_ += n - 2;
    if (n == 4) {
        ++quads_;
    } else {
        ++polygons_;
        if (fewest_corners_ == 0 || n < fewest_corners_) fewest_corners_ = n;
        if (n > most_corners_) most_corners_ = n;
    }
    auto fan = [&] {
        for (size_t k = 1; k + 1 < n; ++k) push(triangles, corners[0], corners[k], corners[k + 1]);
    };
    for (size_t i = 0; i < n; ++i) // an index out of range is for the validation to report
        if (3 * size_t(corners[i]) + 2 >= positions.size()) return fan();
    const Vec normal = newell_normal(positions, corners, n);
    if (n == 4) {
        const uint32_t a = corners[0], b = corners[1], c = corners[2], d = corners[3];
        const bool ac_keeps =
            facing(positions, a, b, c, normal) > 0 && facing(positions, a, c, d, normal) > 0;
        const bool bd_keeps =
            facing(positions, b, c, d, normal) > 0 && facing(positions, b, d, a, normal) > 0;
        const Vec ac = sub(point(positions, c), point(positions, a));
        const Vec bd = sub(point(positions, d), point(positions, b));
        if (bd_keeps && (!ac_keeps || dot(bd, bd) < dot(ac, ac)))
            push(triangles, b, c, d), push(triangles, b, d, a);
        else // also a degenerate quad, where neither diagonal keeps both halves facing
            push(triangles, a, b, c), push(triangles, a, c, d);
        return;
    }
    vtkNew<vtkPolygon> polygon;
    polygon->GetPoints()->SetNumberOfPoints(vtkIdType(n));
    polygon->GetPointIds()->SetNumberOfIds(vtkIdType(n));
    for (size_t i = 0; i < n; ++i) {
        const Vec p = point(positions, corners[i]);
        polygon->GetPoints()->SetPoint(vtkIdType(i), p.data());
        polygon->GetPointIds()->SetId(vtkIdType(i), vtkIdType(i));
    }
    vtkNew<vtkIdList> local;
    if (polygon->Triangulate(local) && local->GetNumberOfIds() == vtkIdType(3 * (n - 2))) {
        for (vtkIdType i = 0; i < local->GetNumberOfIds(); i += 3) {
            uint32_t t[3];
            for (int k = 0; k < 3; ++k) t[k] = corners[local->GetId(i + k)];
            if (facing(positions, t[0], t[1], t[2], normal) < 0) std::swap(t[1], t[2]);
            push(triangles, t[0], t[1], t[2]);
        }
        return;
    }
    fan();
}

std::string PolygonSplitter::note() const {
    std::string note;
    if (quads_ + polygons_ > 0) {
        std::string faces;
        if (quads_ > 0) faces = std::to_string(quads_) + (quads_ == 1 ? " quad" : " quads");
        if (polygons_ > 0) {
            if (!faces.empty()) faces += " and ";
            faces +=
                std::to_string(polygons_) + (polygons_ == 1 ? " polygon" : " polygons") + " (" +
                std::to_string(fewest_corners_) +
                (most_corners_ > fewest_corners_ ? " to " + std::to_string(most_corners_) : "") +
                " corners)";
        }
        note = faces + " triangulated into " + std::to_string(made_) + " triangles";
    }
    if (dropped_ > 0) {
        if (!note.empty()) note += "; ";
        note += std::to_string(dropped_) + (dropped_ == 1 ? " face" : " faces") +
                " with fewer than 3 corners dropped";
    }
    return note;
}

} // namespace ddsimp::io
