// The global split on the host (docs/architecture.md, "The global split"): the same grid, keys
// and stable sort as the device's (kernels/split.cl), bit for bit. A CPU device runs on the host's
// own cores, where the device's split is a dozen launches that cost more than the split's work;
// a GPU splits on the device. The tests hold the device's split to this one.
#pragma once

#include "BatchLayout.h"
#include "SplitPlan.h"
#include "split_grid.h"

#include <utility>
#include <vector>

namespace btocl {

// The sort key of one constraint (btoclSplitKeyOfCell, or grid.overflowKey).
int splitKeyOfConstraint(const btoclConstraint& c, const btoclSplitGrid& grid,
                         const std::vector<unsigned char>& overflowBody);

// The grid of this step (bounding box of the constraints' positions, cell cap), as the device makes it.
btoclSplitGrid makeSplitGridHost(const btoclConstraint* constraints, size_t n, float baseCellSize);

// The split into `layout`, its arrays reused: groups by key, each group's constraints in
// increasing index order. With serialRuns each group is one run (numBatches 1, batchEnd at its
// first place), as the device writes it for the serial path; else no batches yet (numBatches 0,
// batchEnd sized but unset). Throws btOpenCLSolverError on a body index out of range.
void splitHostInto(const btoclConstraint* constraints, size_t n, const std::vector<SplitBody>& bodies,
                   const SplitParams& params, bool serialRuns, BatchLayout& layout);

// The same, into a new layout, without runs.
BatchLayout splitHost(const std::vector<btoclConstraint>& constraints, const std::vector<SplitBody>& bodies,
                      const SplitParams& params);

// Where cells (cell, weight), in linear cell index order (rows of cells), are cut into `parts`
// runs of about equal weight, each cell going to the part its middle falls in: part p takes the
// cells in [cuts[p - 1], cuts[p]) (partOfCell). Threads that each take one part of every set then
// keep to one region of the scene, and a body, whose constraints lie in neighbouring cells,
// mostly stays on one thread's core from set to set.
std::vector<int> cutCells(std::vector<std::pair<int, long long>> cells, int parts);
// A split's cell groups of every set, each weighed by its constraints, cut so (cutCells).
std::vector<int> cellCuts(const BatchLayout& split, int parts);
// The part of `cell` (cutCells).
int partOfCell(const std::vector<int>& cuts, int cell);

}  // namespace btocl
