// The layout that the global split and the local batching produce and the solve consumes:
// constraints ordered by set, then group (cell), then batch. See kernels/btocl_shared.h.
#pragma once

#include "btocl_shared.h"
#include "split_grid.h"

#include <array>
#include <string>
#include <vector>

namespace btocl {

struct SplitParams {
    float cellSize = 0;       // 0 = from the dynamic bodies' extents
    int batchIterations = 4;  // locking rounds per streamed chunk
    int workGroupSize = 64;
    // World distance by which a contact point may lie outside its body's AABB (Bullet's contact
    // breaking threshold is 0.02; points of a manifold may also sit on the other body's surface).
    float contactMargin = 0.05f;
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

// The O(bodies) part of the split, done on the host by both paths: the cell edge the bodies ask for
// and which dynamic bodies are too big for it (their constraints go to the overflow group).
// Rule: with params.cellSize > 0 that is the cell; a dynamic body is too big when its contact span,
// extent * 1.1 + contactMargin, exceeds it. Otherwise a dynamic body is too big when its extent
// exceeds 4x the median dynamic extent, and the cell is the largest contact span of the others.
struct SplitBodiesPlan {
    float baseCellSize = 0;                  // before the grid's cap on cells per axis
    std::vector<unsigned char> overflowBody; // per body: 1 = its constraints go to the overflow group
};
SplitBodiesPlan planSplitBodies(const std::vector<SplitBody>& bodies, const SplitParams& params);

// The sort key of one constraint (btoclSplitKeyOfCell, or grid.overflowKey).
int splitKeyOfConstraint(const btoclConstraint& c, const btoclSplitGrid& grid,
                         const std::vector<unsigned char>& overflowBody);

// The grid of this step (bounding box of the constraints' positions, cell cap), as the device makes it.
btoclSplitGrid makeSplitGridHost(const std::vector<btoclConstraint>& constraints, float baseCellSize);

// Global split only: groups by key, each group's constraints in increasing index order, no batches
// yet (numBatches 0, batchEnd sized but unset). Throws btOpenCLSolverError on a body index out of range.
BatchLayout splitHost(const std::vector<btoclConstraint>& constraints, const std::vector<SplitBody>& bodies,
                      const SplitParams& params);

// Serial host reference: 2x2 checkerboard grid split, then greedy colouring of each group
// (each constraint goes to the first batch where neither of its dynamic bodies is taken).
// The oracle of the tests (the quality yardstick of the device batches).
BatchLayout buildBatchesHost(const std::vector<btoclConstraint>& constraints,
                             const std::vector<SplitBody>& bodies, const SplitParams& params);

// The serial twin of the device's local batching (kernels/batch.cl), same split: each group is
// streamed through a window of `windowSize` constraints; each batch takes params.batchIterations
// rounds in which every pending constraint offers its priority (btoclBatchPriority) to its dynamic
// bodies, and the ones that won all their bodies are scheduled and lock them. The device output must
// equal it bitwise.
BatchLayout buildBatchesHostStreamed(const std::vector<btoclConstraint>& constraints,
                                     const std::vector<SplitBody>& bodies, const SplitParams& params,
                                     int windowSize);

// Bits of a window position, as the priorities of the locking rounds use them (batch_priority.h).
int batchWindowBits(int windowSize);

// Batches of one group by greedy colouring (the quality yardstick), for a list of constraint indices.
int greedyBatchCount(const std::vector<btoclConstraint>& constraints, const int* indices, int count);

// Checks the invariants of DESIGN §5 on a layout: every constraint exactly once; no dynamic body
// in two groups of one set; no dynamic body twice in one batch. Returns "" or the first failure.
std::string validateBatchLayout(const BatchLayout& layout, const std::vector<btoclConstraint>& constraints);

}  // namespace btocl
