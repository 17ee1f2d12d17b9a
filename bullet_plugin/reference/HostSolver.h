// Serial host reference of kernels/solve.cl: the same iterations, passes, sets, groups and
// batches, one constraint after another. The tests compare the device solve with it.
#pragma once

#include "BatchLayout.h"
#include "SolveSettings.h"
#include "StepProblem.h"

namespace btocl {

// Runs the split-impulse and velocity iterations on p.rows and p.deltas in place.
// Returns the number of velocity iterations run.
int solveOnHost(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings);

}  // namespace btocl
