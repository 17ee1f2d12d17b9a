// Serial host references of the global split and the local batching: the oracles that the tests
// hold the device's split.cl and batch.cl to. Not part of the library that users link.
#pragma once

#include "BatchLayout.h"
#include "SplitPlan.h"
#include "split_grid.h"

#include <vector>

namespace btocl {

// The sort key of one constraint (btoclSplitKeyOfCell, or grid.overflowKey).
int splitKeyOfConstraint(const btoclConstraint& c, const btoclSplitGrid& grid,
                         const std::vector<unsigned char>& overflowBody);

// The grid of this step (bounding box of the constraints' positions, cell cap), as the device makes it.
btoclSplitGrid makeSplitGridHost(const std::vector<btoclConstraint>& constraints, float baseCellSize);

// Global split only: groups by key, each group's constraints in increasing index order, no batches
// yet (numBatches 0, batchEnd sized but unset). Throws btOpenCLSolverError on a body index out of range.
BatchLayout splitHost(const std::vector<btoclConstraint>& constraints, const std::vector<SplitBody>& bodies,
                      const SplitParams& params);

// 2x2 checkerboard grid split, then greedy colouring of each group (each constraint goes to the
// first batch where neither of its dynamic bodies is taken): the quality yardstick of the device
// batches.
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

// Batches of one group by greedy colouring (the quality yardstick), for a list of constraint indices.
int greedyBatchCount(const std::vector<btoclConstraint>& constraints, const int* indices, int count);

}  // namespace btocl
