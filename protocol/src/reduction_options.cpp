#include "ddsimp/protocol/reduction_options.h"

#include "ddsimp/protocol/content_hash.h"

#include <charconv>
#include <cstdio>

namespace ddsimp::protocol {

double from_wire(float value) {
    char text[32];
    const auto written = std::to_chars(text, text + sizeof text, value);
    double out = value;
    std::from_chars(text, written.ptr, out);
    return out;
}

v1::Strategy to_wire(Strategy s) {
    return s == Strategy::VertexRemoval ? v1::VERTEX_REMOVAL : v1::EDGE_COLLAPSE;
}

Strategy from_wire(v1::Strategy s) {
    return s == v1::VERTEX_REMOVAL  ? Strategy::VertexRemoval
           : s == v1::EDGE_COLLAPSE ? Strategy::EdgeCollapse
                                    : Options{}.strategy;
}

v1::Placement to_wire(Placement p) {
    return p == Placement::VolumePreserving ? v1::VOLUME
           : p == Placement::Midpoint       ? v1::MIDPOINT
                                            : v1::LEAST_ERROR;
}

Placement from_wire(v1::Placement p) {
    return p == v1::VOLUME        ? Placement::VolumePreserving
           : p == v1::MIDPOINT    ? Placement::Midpoint
           : p == v1::LEAST_ERROR ? Placement::LeastError
                                  : Options{}.placement;
}

v1::DataPlacement to_wire(DataPlacement d) {
    return d == DataPlacement::Interpolated ? v1::DATA_INTERPOLATED : v1::DATA_LEAST_ERROR;
}

DataPlacement from_wire(v1::DataPlacement d) {
    return d == v1::DATA_INTERPOLATED  ? DataPlacement::Interpolated
           : d == v1::DATA_LEAST_ERROR ? DataPlacement::LeastError
                                       : Options{}.data_placement;
}

v1::Terms to_wire(Terms t) {
    return t == Terms::AngleDeficitGradient ? v1::ANGLE_DEFICIT_GRADIENT : v1::ERROR_QUADRICS;
}

Terms from_wire(v1::Terms t) {
    return t == v1::ANGLE_DEFICIT_GRADIENT ? Terms::AngleDeficitGradient
           : t == v1::ERROR_QUADRICS       ? Terms::ErrorQuadrics
                                           : Options{}.terms;
}

Options options_from(const v1::Request& r) {
    Options o;
    o.alpha = r.has_alpha_exact() ? r.alpha_exact() : from_wire(r.alpha());
    o.strategy = from_wire(r.strategy());
    o.placement = from_wire(r.placement());
    o.data_placement = from_wire(r.data_placement());
    o.terms = from_wire(r.terms());
    o.gradient_fields.assign(r.gradient_fields().begin(), r.gradient_fields().end());
    // The wire's 0 (a proto3 default) means no feature edges, as the library's 180 does.
    o.feature_angle = r.feature_angle() == 0 ? 180.0 : from_wire(r.feature_angle());
    o.keep_fraction = 0;
    check_options(o);
    return o;
}

void set_options(v1::Request& r, const Options& o) {
    r.set_alpha(float(o.alpha));
    r.set_alpha_exact(o.alpha);
    r.set_strategy(to_wire(o.strategy));
    r.set_placement(to_wire(o.placement));
    r.set_data_placement(to_wire(o.data_placement));
    r.set_terms(to_wire(o.terms));
    r.clear_gradient_fields();
    for (const std::string& f : o.gradient_fields) r.add_gradient_fields(f);
    r.set_feature_angle(o.feature_angle >= 180 ? 0.0f : float(o.feature_angle));
}

Options options_from(const v1::View& v) {
    Options o;
    o.alpha = v.has_alpha_exact() ? v.alpha_exact() : from_wire(v.alpha());
    o.strategy = from_wire(v.strategy());
    o.placement = from_wire(v.placement());
    o.keep_fraction = 0;
    check_options(o);
    return o;
}

void set_alpha(v1::View& view, double alpha) {
    view.set_alpha(float(alpha));
    view.set_alpha_exact(alpha);
}

void set_defaults(v1::ReductionDefaults& d) {
    const Options o;
    d.set_alpha(o.alpha);
    d.set_strategy(to_wire(o.strategy));
    d.set_placement(to_wire(o.placement));
    d.set_data_placement(to_wire(o.data_placement));
    d.set_terms(to_wire(o.terms));
    d.set_feature_angle(o.feature_angle);
}

size_t target_for_keep(float keep, size_t triangles_in) {
    Options o;
    o.keep_fraction = from_wire(keep);
    return target_triangles(o, triangles_in);
}

std::string result_key(const std::string& surface, const Options& o) {
    char numbers[160];
    std::snprintf(numbers, sizeof numbers, "%.17g|%d|%d|%d|%d|%.17g|%.17g|%.17g|%.17g", o.alpha,
                  int(o.strategy), int(o.placement), int(o.data_placement), int(o.terms),
                  o.feature_angle, o.line_tolerance, o.max_normal_turn, o.max_weight);
    std::string text =
        "ddsimp-algorithm/" + std::to_string(algorithm_version) + "|" + surface + "|" + numbers;
    for (const std::string& f : o.gradient_fields) text += '\0' + f;
    return sha256_hex(text);
}

} // namespace ddsimp::protocol
