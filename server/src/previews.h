// Previews: a stand-in for a level the server is still computing, made in milliseconds. The
// same level of the nearest ready record of the surface (another alpha) when there is one,
// else a vertex clustering of the surface (meshoptimizer's simplifySloppy), which keeps no
// topology and is never sent as anything but a preview.
#pragma once

#include "ddsimp/ddsimp.h"

#include <cstddef>

namespace ddsimp::server {

// About `target` triangles of `surface` by vertex clustering, every field carried, unused
// vertices dropped.
Surface clustered_preview(const Surface& surface, size_t target);

} // namespace ddsimp::server
