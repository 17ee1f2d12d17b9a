// Serial host reference of the device solve (kernels/solve.cl): the same passes and iterations,
// set after set, group after group, batch after batch, one constraint after another, with the
// same row math (kernels/row_solve.h). The tests compare the device's parallel solve with it.
#pragma once

#include "BatchLayout.h"
#include "SolveSettings.h"
#include "StepProblem.h"

namespace btocl {

// Solves rows set up on the host (p.rows, gather order) in `layout`'s order, walking the step's
// passes as the device does (passScheduleOf, StepPlan.h).
// Leaves p.deltas as DeviceSolver::download does, and p.appliedImpulses for every row (the device
// reads back the normal and friction rows, the first ones). Returns the velocity iterations run.
int solveOnHost(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings);

}  // namespace btocl
