// The layout that the global split and the local batching produce and the solve consumes:
// constraints ordered by set, then group (cell), then batch. See kernels/btOclShared.h.
#pragma once

#include "btOclShared.h"

#include <array>
#include <string>
#include <vector>

namespace btocl {

struct SplitParams {
    float cellSize = 0;       // 0 = from the dynamic bodies' extents
    int batchIterations = 4;  // locking rounds per streamed chunk
    int workGroupSize = 64;
};

// Per body, what the split needs: the largest edge of its AABB (0 for static/kinematic bodies).
struct SplitBody {
    float extent = 0;
    bool dynamic = false;
};

// Host copy of the layout (the device keeps the same arrays in buffers).
struct BatchLayout {
    std::vector<int> solveOrder;    // constraint indices, by set, group, batch
    std::vector<int> batchEnd;      // batch ends of group g at batchEnd[g.offset + k]
    std::vector<btoclGroup> groups; // groups of set s: [setGroupStart[s], setGroupStart[s+1])
    std::array<int, BTOCL_NUM_SETS + 2> setGroupStart{};  // set 4 = overflow
    float cellSize = 0;
    int numOverflowConstraints = 0;
};

// Serial host reference: 2x2 checkerboard grid split, then greedy colouring of each group
// (each constraint goes to the first batch where neither of its dynamic bodies is taken).
// The oracle of the tests, and the fallback before the device path lands.
BatchLayout buildBatchesHost(const std::vector<btoclConstraint>& constraints,
                             const std::vector<SplitBody>& bodies, const SplitParams& params);

// Checks the invariants of DESIGN §5 on a layout: every constraint exactly once; no dynamic body
// in two groups of one set; no dynamic body twice in one batch. Returns "" or the first failure.
std::string validateBatchLayout(const BatchLayout& layout, const std::vector<btoclConstraint>& constraints);

}  // namespace btocl
