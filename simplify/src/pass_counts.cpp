#include "pass_counts.h"

namespace ddsimp::detail {

PassCounts& pass_counts() {
    static PassCounts counts;
    return counts;
}

} // namespace ddsimp::detail
