// The one check of a reduction's options and the triangle target they set: the library, the
// server and the clients all go through these, so a parameter means the same everywhere.
#include "ddsimp/ddsimp.h"

#include <cmath>
#include <string>

namespace ddsimp {

void check_options(const Options& o) {
    auto fail = [](const std::string& what) { throw InputError("invalid option: " + what); };
    if (!(o.alpha >= 0 && o.alpha <= 1)) fail("alpha must be in [0, 1]");
    if (!(o.keep_fraction >= 0 && o.keep_fraction <= 1)) fail("keep fraction must be in [0, 1]");
    if (std::isnan(o.max_weight)) fail("max weight is NaN");
    if (!(o.feature_angle >= 0 && o.feature_angle <= 180))
        fail("feature angle must be in [0, 180] degrees");
    if (!(o.line_tolerance >= 0 && o.line_tolerance < 180))
        fail("line tolerance must be in [0, 180) degrees");
    if (!(o.max_normal_turn > 0 && o.max_normal_turn < 180))
        fail("max normal turn must be in (0, 180) degrees");
    if (o.threads < 0) fail("threads must be at least 0 (0: every hardware thread)");
}

size_t target_triangles(const Options& o, size_t triangles_in) {
    if (o.target_triangles > 0) return o.target_triangles;
    return size_t(std::floor(o.keep_fraction * double(triangles_in) + 1e-9));
}

} // namespace ddsimp
