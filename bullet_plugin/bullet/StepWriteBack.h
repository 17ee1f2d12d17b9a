// The end of a step (SI's solveGroupCacheFriendlyFinish): what the solve found, written to
// Bullet's bodies and manifold points. The only place a step changes the world besides the
// bodies' companion ids.
#pragma once

#include "BulletStep.h"
#include "StepProblem.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>

namespace btocl {

// Velocities (and push transforms) of the bodies, applied impulses of the points (with
// warm starting, as SI), their friction directions and flags, the joints' applied impulses,
// feedback and breaking (JointWriteBack.h). Releases the bodies' companion ids.
void writeBackStep(const StepProblem& p, const BulletStep& bullet, const btContactSolverInfo& info);

}  // namespace btocl
