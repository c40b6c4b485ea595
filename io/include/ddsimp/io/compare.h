// How far a reduced surface is from its original, in geometry and in data.
#pragma once

#include "ddsimp/ddsimp.h"

#include <string>
#include <vector>

namespace ddsimp::tools {

// RMS and maximum of one error over a set of sample points.
struct ErrorStats {
    double rms = 0;
    double max = 0;
};

// An error measured both ways: at the original's vertices against the reduced surface, at the
// reduced surface's vertices against the original, and over both sets of samples together
// (symmetric: RMS over all samples, max of the two maxima = the Hausdorff distance).
struct TwoWayError {
    ErrorStats original_to_reduced;
    ErrorStats reduced_to_original;
    ErrorStats symmetric;
};

struct FieldError {
    std::string name;
    int components = 1;
    // The scale errors are divided by: max - min of a scalar over the original; for a vector the
    // diagonal of its components' bounding box (sqrt of the sum of squared component ranges).
    // 1 if the field is constant (errors are then absolute).
    double range = 1;
    TwoWayError error;
};

struct CompareReport {
    double diagonal = 0;         // the original's bounding-box diagonal
    size_t original_samples = 0; // vertices of the original used by a triangle
    size_t reduced_samples = 0;
    TwoWayError distance; // distance to the closest point, divided by `diagonal`
    std::vector<FieldError> fields;
};

// Samples every vertex (used by a triangle) of each surface and finds the closest point on the
// other one. Geometric error: that distance. Data error: the vertex's field value minus the other
// surface's field interpolated barycentrically at the closest point (L2 norm for vectors),
// divided by the field's range. `fields` names the fields to compare (each must exist in both
// with the same components); empty means every field of the original that the reduced one also
// has with the same number of components.
// Throws ddsimp::InputError for a missing or mismatched field or an empty surface.
// Cost: O((V + V') log T) with a BVH per surface, single-threaded.
CompareReport compare_surfaces(const Surface& original, const Surface& reduced,
                               const std::vector<std::string>& fields);

} // namespace ddsimp::tools
