// Serial host references of the local batching (the split's is the library's, HostSplit.h): the
// oracles that the tests hold the device's batch.cl to. Not part of the library that users link.
#pragma once

#include "BatchLayout.h"
#include "HostSplit.h"
#include "SplitPlan.h"

#include <vector>

namespace btocl {

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
