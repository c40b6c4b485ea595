// Vertex removal's record, indexed for following its removed vertices (removal_cover.h).
#include "removal_cover.h"

namespace ddsimp::detail {

RemovalCover::RemovalCover(const std::vector<uint32_t>& triangles, size_t vertices,
                           const std::vector<uint32_t>& write_begin,
                           const std::vector<uint32_t>& writes, size_t operations)
    : write_begin_(write_begin), writes_(writes), removed_at_(vertices, kNone),
      next_write_(write_begin[operations] / 4, kNone), operation_(write_begin[operations] / 4) {
    // Each write's predecessor on its slot (kNone: the slot still holds the input's triangle).
    std::vector<uint32_t> last(triangles.size() / 3, kNone), previous(next_write_.size());
    for (uint32_t i = 0; i < operations; ++i)
        for (uint32_t w = write_begin[i]; w < write_begin[i + 1]; w += 4) {
            if (writes[w] >= last.size()) last.resize(writes[w] + 1, kNone);
            previous[w / 4] = last[writes[w]];
            if (previous[w / 4] != kNone) next_write_[previous[w / 4] / 4] = w;
            last[writes[w]] = w, operation_[w / 4] = i;
        }
    // A removal's vertex is in each of its star's old triangles and in none of the new ones.
    for (uint32_t i = 0; i < operations; ++i) {
        const uint32_t* old = nullptr;
        for (uint32_t w = write_begin[i]; w < write_begin[i + 1] && !old; w += 4) {
            const size_t slot = writes[w];
            if (const uint32_t p = previous[w / 4]; p != kNone)
                old = &writes[p + 1];
            else if (3 * slot < triangles.size())
                old = &triangles[3 * slot];
            if (old && old[0] == kNone) old = nullptr; // a retired slot
        }
        if (!old) continue;
        for (int k = 0; k < 3; ++k) {
            bool kept = false;
            for (uint32_t w = write_begin[i]; w < write_begin[i + 1] && !kept; w += 4)
                kept =
                    writes[w + 1] != kNone &&
                    (writes[w + 1] == old[k] || writes[w + 2] == old[k] || writes[w + 3] == old[k]);
            if (!kept) removed_at_[old[k]] = i;
        }
    }
}

} // namespace ddsimp::detail
