// The colour map of the page (web/src/colormap.js): matplotlib's viridis at i/16, i = 0..16,
// interpolated linearly in sRGB, so that a .glb is coloured as the page colours the surface.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace ddsimp::protocol {

// The sRGB colour (components in [0, 1]) of t in [0, 1]; t outside is clamped, NaN is grey.
inline std::array<float, 3> viridis_srgb(double t) {
    static constexpr uint32_t kStops[] = {
        0x440154, 0x48186a, 0x472d7b, 0x424086, 0x3b528b, 0x33638d, 0x2c728e, 0x26828e, 0x21918c,
        0x1fa088, 0x28ae80, 0x3fbc73, 0x5ec962, 0x84d44b, 0xaddc30, 0xd8e219, 0xfde725,
    };
    constexpr int kLast = int(std::size(kStops)) - 1;
    if (std::isnan(t)) return {0.5f, 0.5f, 0.5f};
    const double x = std::clamp(t, 0.0, 1.0) * kLast;
    const int i = std::min(kLast - 1, int(std::floor(x)));
    const double f = x - i;
    std::array<float, 3> rgb{};
    for (int c = 0; c < 3; ++c) {
        const int shift = 16 - 8 * c;
        const double a = ((kStops[i] >> shift) & 0xff) / 255.0;
        const double b = ((kStops[i + 1] >> shift) & 0xff) / 255.0;
        rgb[c] = float(a + f * (b - a));
    }
    return rgb;
}

// sRGB to linear, as glTF's COLOR_0 and three.js expect.
inline float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : float(std::pow((c + 0.055) / 1.055, 2.4));
}

} // namespace ddsimp::protocol
