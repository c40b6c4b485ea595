// A reduction's options on the wire: the one place where a Request or a session's View becomes
// ddsimp::Options and back. Unset fields take the library's defaults, floats are read as the
// decimals they were typed as, values are checked by the library's own check_options, and the
// result key is derived from the Options themselves, so the same request gives the same bytes
// from the library, the command line, the client library, the page and a session.
#pragma once

#include "ddsimp/ddsimp.h"
#include "ddsimp/v1/ddsimp.pb.h"

#include <string>

namespace ddsimp::protocol {

// The double a float on the wire stands for: the shortest decimal that reads back as that float
// (0.3f -> 0.3, not 0.30000001192...).
double from_wire(float value);

v1::Strategy to_wire(Strategy strategy);
Strategy from_wire(v1::Strategy strategy); // unspecified: the library's default
v1::Placement to_wire(Placement placement);
Placement from_wire(v1::Placement placement); // unspecified: the library's default
v1::DataPlacement to_wire(DataPlacement data_placement);
DataPlacement from_wire(v1::DataPlacement data_placement); // unspecified: the library's default
v1::Terms to_wire(Terms terms);
Terms from_wire(v1::Terms terms); // unspecified: the library's default

// The options a Request asks for: alpha (alpha_exact if present), strategy, placement, data
// placement, terms, gradient fields, feature angle (0 on the wire: none, 180); everything else the
// library's defaults, keep_fraction 0 (the levels come from the request's keep list). Throws
// InputError (check_options) when a value is out of range.
Options options_from(const v1::Request& request);
// Writes those options into `request` (alpha both as float and exactly).
void set_options(v1::Request& request, const Options& options);

// The options of a session's view: its alpha, strategy and placement; the rest as above.
Options options_from(const v1::View& view);
void set_alpha(v1::View& view, double alpha);

// What the server fills in for a Request's unset options.
void set_defaults(v1::ReductionDefaults& defaults);

// The triangle count a level's keep fraction asks for from `triangles_in` triangles, counted as
// the library counts Options::keep_fraction.
size_t target_for_keep(float keep, size_t triangles_in);

// The key of a result: hex SHA-256 of the surface id, every option that changes the library's
// output, and the library's algorithm version.
std::string result_key(const std::string& surface, const Options& options);

} // namespace ddsimp::protocol
