// The layout that the global split and the local batching produce and the solve consumes:
// constraints ordered by set, then group (cell), then batch. See kernels/btocl_shared.h.
#pragma once

#include "btocl_shared.h"

#include <array>
#include <vector>

namespace btocl {

// Host copy of the layout (the device keeps the same arrays in buffers).
struct BatchLayout {
    std::vector<int> solveOrder;    // constraint indices, by set, group, batch
    std::vector<int> batchEnd;      // batch ends of group g at batchEnd[g.offset + k]
    std::vector<btoclGroup> groups; // groups of set s: [setGroupStart[s], setGroupStart[s+1])
    std::array<int, BTOCL_NUM_SETS + 2> setGroupStart{};  // set 4 = overflow
    float cellSize = 0;
    int numOverflowConstraints = 0;
    // The serial path's layout: each group is one run that one work-item walks in order, not a
    // sequence of batches of independent constraints.
    bool serialRuns = false;
};

// The dynamic body on one side (0 = A, 1 = B) of a constraint, or -1: only dynamic bodies lock.
inline int dynamicBodyOf(const btoclConstraint& c, int side) {
    if (side == 0) return c.dynamicA ? c.bodyA : -1;
    return c.dynamicB ? c.bodyB : -1;
}

}  // namespace btocl
