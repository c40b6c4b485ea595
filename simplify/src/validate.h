// The input checks of `validate` (ddsimp.h) for callers that must not copy a surface that needs
// no repair: the repairs only ever change the triangles.
#pragma once

#include "ddsimp/ddsimp.h"
#include "parallel.h"

#include <cstdint>
#include <vector>

namespace ddsimp::detail {

// Checks `surface` as `validate` does (throws InputError) and fills `report`, on `parallel`'s
// threads (the same result for any number). Returns true with the repaired triangles in
// `repaired` if a repair changes them; false otherwise (`repaired` then holds nothing useful).
bool repair_triangles(const Surface& surface, std::vector<uint32_t>& repaired, RepairReport& report,
                      Parallel& parallel);

// `input` itself when it needs no repair, otherwise `repaired`, filled with its repaired copy.
const Surface& validated(const Surface& input, Surface& repaired, RepairReport& report,
                         Parallel& parallel);

} // namespace ddsimp::detail
