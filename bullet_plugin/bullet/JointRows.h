// Joint rows on the host, as btSequentialImpulseConstraintSolver makes them (convertJoints,
// convertJoint): each btTypedConstraint's getInfo1/getInfo2, finished with the row math that the
// contact rows share (kernels/row_setup.h: btoclJointRow), as btoclRow records and one
// btoclConstraint per joint for the split, the batches and the solve. What the write-back needs
// stays beside them (StepJoint; JointWriteBack.h). Reads Bullet and writes nothing to it but what
// getInfo1/getInfo2 keep inside each joint (limit and motor state), as SI's set-up does.
#pragma once

#include "HostArray.h"
#include "StepProblem.h"
#include "btocl_shared.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>
#include <LinearMath/btVector3.h>

#include <vector>

class btTypedConstraint;
struct btJointFeedback;

namespace btocl {

// The two solver bodies of a joint (StepGatherer::solverBodyOf; 0 is the fixed body).
struct JointBodies {
    int bodyA = 0, bodyB = 0;
};

// One btTypedConstraint of the step, with or without rows (SI resets the feedback and the
// applied impulse of a disabled joint too).
struct StepJoint {
    btTypedConstraint* constraint = nullptr;
    btJointFeedback* feedback = nullptr;  // its getJointFeedback(), or null
    int bodyA = 0, bodyB = 0;             // solver body indices
    int firstRow = 0, numRows = 0;        // its rows in JointRowSet::rows (0 rows: disabled, or none asked)
    int constraintIndex = -1;             // its btoclConstraint in JointRowSet::constraints, -1 without rows
    int numIterations = 0;                // SI's override: getOverrideNumSolverIterations(), else m_numIterations
    float breakingImpulseThreshold = 0;
};

struct JointRowSet {
    std::vector<StepJoint> joints;  // every constraint passed, in the order passed
    // The rows of all joints, joint after joint in that order (SI's m_tmpSolverNonContactConstraintPool).
    // The gather moves them into the step's rows (StepProblem::rows), leaving this empty.
    RowArray rows;
    // One per joint with rows, in the same order: rows [firstRow, firstRow + numRows) of kind
    // BTOCL_ROWS_JOINT index `rows` (no rows of other kinds); position.w is the joint's iteration
    // count, and its xyz the joint's split point once placeJointSplitPoints has placed it.
    std::vector<btoclConstraint> constraints;
    // The step's velocity iterations: max(m_numIterations, every joint's override), SI's maxIterations.
    int maxIterations = 0;
};

// Rows for `numJoints` joints. bodies[i]: joint i's solver bodies; solverBodies: the step's
// body records (StepProblem::bodies), read for the external impulses of this step and the
// dynamic bodies' state. Throws btOpenCLSolverError when a joint's row is not finite.
JointRowSet setUpJointRows(btTypedConstraint* const* joints, int numJoints, const JointBodies* bodies,
                           const HostArray<btoclBody>& solverBodies, const btContactSolverInfo& info);

// The box each dynamic solver body's constraints reach, for the global split: its AABB, grown by
// the split points of its joints (placeJointSplitPoints). Only dynamic bodies' boxes are read.
struct SplitReach {
    std::vector<btVector3> lo, hi;

    void grow(int body, const btVector3& p) {
        lo[size_t(body)].setMin(p);
        hi[size_t(body)].setMax(p);
    }
};

// The joints' part of the global split's geometry, which only a split step reads: each joint's
// split point into the xyz of its constraint in `constraints` (set.constraints' copies, in their
// order), and `reach` grown to hold it (docs/architecture.md, invariant 3).
void placeJointSplitPoints(const JointRowSet& set, btoclConstraint* constraints, SplitReach& reach);

}  // namespace btocl
