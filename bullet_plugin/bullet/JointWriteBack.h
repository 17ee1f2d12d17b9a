// The joints' part of the write-back, as btSequentialImpulseConstraintSolver's
// solveGroupCacheFriendlyFinish does it (writeBackJoints), from the rows' final applied impulses.
// Called by the step's write-back once the solve succeeded: nothing here runs on a failed step.
#pragma once

#include "JointRows.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>

namespace btocl {

// For every joint of the set, rows or not: its btJointFeedback cleared and then summed over its
// rows (force and torque on both bodies), its applied impulse (internalSetAppliedImpulse) that of
// its last row, as SI leaves it, and the joint disabled when a row's final |impulse| reached its
// breaking threshold. rows[r] and appliedImpulses[r]: row r of the set (JointRowSet::rows, as the
// gather placed them in the step's rows) and its final impulse.
void writeBackJoints(const JointRowSet& set, const btoclRow* rows, const float* appliedImpulses,
                     const btContactSolverInfo& info);

}  // namespace btocl
