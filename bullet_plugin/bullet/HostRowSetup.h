// Contact rows set up on the host, with the same functions as the setup kernel
// (kernels/row_setup.h) plus what the kernel does not handle: anisotropic friction, which
// scales friction directions and rolling axes in each object's frame (SI's
// applyAnisotropicFriction). The step uses it when an object of the step has anisotropic
// friction; the tests use it to set rows up without a device.
#pragma once

#include "BulletStep.h"
#include "StepProblem.h"

namespace btocl {

// Fills p.rows in gather order ([normal][friction][rolling]) and p.lateralDirs from p.points
// (the manifolds' objects from `bullet`).
// A rolling row whose anisotropic axis vanishes is left out, as SI leaves it out: the rolling
// rows, and the constraints' and points' references to them, are renumbered.
void setupRowsOnHost(StepProblem& p, const BulletStep& bullet);

}  // namespace btocl
