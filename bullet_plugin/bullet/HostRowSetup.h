// Contact rows set up on the host, with the same functions as the setup kernel
// (kernels/row_setup.h) plus what the kernel does not handle: anisotropic friction, which
// scales friction directions and rolling axes in each object's frame (SI's
// applyAnisotropicFriction). The gather uses it when an object of the step has anisotropic
// friction, a step solved on the host (StepMode::Host) for every step, and the tests to set rows
// up without a device.
#pragma once

#include "BulletStep.h"
#include "HostSolve.h"
#include "StepProblem.h"

namespace btocl {

// Fills p.rows, empty before (the joints' rows come after), with every contact row in gather
// order ([normal][friction][rolling]) and p.lateralDirs from p.points (the manifolds' objects
// from `bullet`); clears p.rowsOnDevice. A rolling row whose anisotropic axis vanishes is
// left out, as SI leaves it out: the rolling rows, the joints' rows after them, and the
// constraints' and points' references to them, are renumbered.
// With `into`, the rows go straight into that host solve (HostSolve::setRow) instead: p.rows and
// p.rowsOnDevice are left as they were (the joints' rows alone, or none), ready for
// HostSolve::solveRowsSet.
// inParallel: the constraints set up by the host's threads (HostParallel.h) where the step is
// large enough and has no rolling row; the same rows as on one thread.
void setupRowsOnHost(StepProblem& p, const BulletStep& bullet, HostSolve* into = nullptr, bool inParallel = false);

}  // namespace btocl
