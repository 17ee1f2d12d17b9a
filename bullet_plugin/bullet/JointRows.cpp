#include "JointRows.h"

#include "BulletConversions.h"
#include "HostParallel.h"
#include "InputChecks.h"
#include "btOpenCLSolverError.h"
#include "row_setup.h"
#include "row_solve.h"

#include <BulletDynamics/ConstraintSolver/btPoint2PointConstraint.h>
#include <BulletDynamics/ConstraintSolver/btSolverConstraint.h>
#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <algorithm>
#include <string>
#include <typeinfo>

namespace btocl {
namespace {

// A joint's side as SI's convertJoint reads it. A body of the solver is its record. The fixed
// body stands for every static object, but SI reads the static body itself (its own velocity
// and inertia, usually zero) and no external impulses: so does this record.
btoclBody jointSide(const btRigidBody& rb, int index, const HostArray<btoclBody>& solverBodies) {
    return index != 0 ? solverBodies[size_t(index)] : bodyRecordOf(rb, false);
}

// The joint's rows as getInfo2 leaves them, exactly as SI's convertJoint prepares them: cleared,
// limits open, the first row's cfm the global one, the info's pointers into the first row.
// Returns the info's m_damping afterwards (a point-to-point joint sets its own).
btScalar fillRowsFromJoint(btTypedConstraint& joint, int numRows, const btContactSolverInfo& info,
                           btConstraintArray& scratch) {
    scratch.resizeNoInitialize(numRows);
    // What getInfo2 may write, through the info's pointers, and rowFromJoint reads: cleared field
    // by field (a memset of the whole row, as SI's, was a large share of this loop's time).
    for (int j = 0; j < numRows; ++j) {
        btSolverConstraint& row = scratch[j];
        row.m_contactNormal1.setZero();
        row.m_relpos1CrossNormal.setZero();
        row.m_contactNormal2.setZero();
        row.m_relpos2CrossNormal.setZero();
        row.m_rhs = 0;
        row.m_cfm = 0;
        row.m_lowerLimit = -SIMD_INFINITY;
        row.m_upperLimit = SIMD_INFINITY;
    }
    btSolverConstraint& first = scratch[0];
    btTypedConstraint::btConstraintInfo2 info2;
    info2.fps = btScalar(1) / info.m_timeStep;
    info2.erp = info.m_erp;
    info2.m_J1linearAxis = first.m_contactNormal1;
    info2.m_J1angularAxis = first.m_relpos1CrossNormal;
    info2.m_J2linearAxis = first.m_contactNormal2;
    info2.m_J2angularAxis = first.m_relpos2CrossNormal;
    info2.rowskip = int(sizeof(btSolverConstraint) / sizeof(btScalar));
    info2.m_constraintError = &first.m_rhs;
    first.m_cfm = info.m_globalCfm;
    info2.cfm = &first.m_cfm;
    info2.m_damping = info.m_damping;
    info2.m_lowerLimit = &first.m_lowerLimit;
    info2.m_upperLimit = &first.m_upperLimit;
    info2.m_numIterations = info.m_numIterations;
    joint.getInfo2(&info2);
    return info2.m_damping;
}

// What getInfo2 wrote into one row, in the lanes that btoclJointRow reads.
btoclRow rowFromJoint(const btSolverConstraint& s, int bodyA, int bodyB) {
    btoclRow r{};
    r.contactNormal1 = toFloat4(s.m_contactNormal1);
    r.relpos1CrossNormal = toFloat4(s.m_relpos1CrossNormal);
    r.contactNormal2 = toFloat4(s.m_contactNormal2);
    r.relpos2CrossNormal = toFloat4(s.m_relpos2CrossNormal);
    BTOCL_ROW_RHS(r) = s.m_rhs;
    BTOCL_ROW_CFM(r) = s.m_cfm;
    BTOCL_ROW_LOWER(r) = s.m_lowerLimit;
    BTOCL_ROW_UPPER(r) = s.m_upperLimit;
    r.bodyA = bodyA;
    r.bodyB = bodyB;
    r.frictionIndex = -1;
    return r;
}

bool isFiniteRow(const btoclRow& r) {
    const btoclFloat4 lanes[] = {r.contactNormal1, r.relpos1CrossNormal, r.contactNormal2, r.relpos2CrossNormal,
                                 r.angularComponentA, r.angularComponentB};
    for (const btoclFloat4& v : lanes)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || !std::isfinite(v.w)) return false;
    return true;
}

// The joint's point for the global split. A dynamic body's constraints must all fall within one
// cell's edge of each other (docs/architecture.md, invariant 3), and the cell is sized from the
// bodies' AABBs, within which their contact points lie. Where the two AABBs overlap (linked bodies do at their pivot: chain
// links, limbs) the point is the middle of the overlap, inside both, and neither body reaches
// further than its contacts do. Where they are apart, it is halfway across the gap on that axis,
// and each body's reach grows by half the gap: its extent says so, and the split then takes a
// bigger cell or, by its rule for big bodies, the overflow group. (The midpoint of the two centres
// would not do: by a long forearm it lies outside a small hand's AABB.) With one dynamic body, the
// middle of its AABB; with none, nothing locks and any point does.
btVector3 splitPointOf(const btTypedConstraint& joint, const StepJoint& j, bool dynamicA, bool dynamicB,
                       const SplitReach& reach) {
    if (!dynamicA && !dynamicB)
        return (joint.getRigidBodyA().getCenterOfMassPosition() + joint.getRigidBodyB().getCenterOfMassPosition()) *
               btScalar(0.5);
    const size_t a = size_t(dynamicA ? j.bodyA : j.bodyB);  // the other's, if A is not dynamic
    const size_t b = size_t(dynamicB ? j.bodyB : j.bodyA);
    btVector3 lo = reach.lo[a], hi = reach.hi[a];
    lo.setMax(reach.lo[b]);
    hi.setMin(reach.hi[b]);
    return (lo + hi) * btScalar(0.5);  // per axis: middle of the overlap, or of the gap
}

// How an error names a joint: its index among the step's joints and its type.
std::string jointName(size_t index, const btTypedConstraint& joint) {
    return "joint " + std::to_string(index) + " of the step (type " + std::to_string(int(joint.getConstraintType())) +
           ")";
}

// SI calls every joint's buildJacobian before its getInfo1, for the joints on the obsolete
// solve path. Bullet's own point-to-point joint builds three Jacobian entries there on either path
// (a large part of a chain's set-up) that only the obsolete path reads: off it, the call is left
// out. A subclass's, or any other type's, is made as SI makes it.
bool jacobianUnread(const btTypedConstraint& c) {
    if (typeid(c) != typeid(btPoint2PointConstraint)) return false;
    return !static_cast<const btPoint2PointConstraint&>(c).m_useSolveConstraintObsolete;
}

}  // namespace

// Row counts first (in parallel, then their running sum), then every joint's rows (in parallel),
// then the constraints and their split points (one thread).
JointRowSet setUpJointRows(btTypedConstraint* const* joints, int numJoints, const JointBodies* bodies,
                           const HostArray<btoclBody>& solverBodies, const btContactSolverInfo& info) {
    JointRowSet set;
    set.maxIterations = info.m_numIterations;
    set.joints.resize(size_t(std::max(0, numJoints)));
    // Row counts first, as SI's convertJoints (buildJacobian serves joints on the obsolete path).
    // Each joint's calls change only its own state, as with getInfo2 below.
    parallelFor(size_t(std::max(0, numJoints)), [&](size_t i) {
        btTypedConstraint* c = joints[i];
        // The solve reads and writes a constraint's two bodies apart: one body on both sides
        // would keep only one side's change. Bullet's solver adds both; between a body and itself
        // a joint means nothing, and is refused as the caller's mistake.
        if (c->isEnabled() && bodies[i].bodyA == bodies[i].bodyB &&
            BTOCL_BODY_IS_DYNAMIC(solverBodies[size_t(bodies[i].bodyA)]) != 0.0f)
            throw InputError("btOpenCLConstraintSolver: " + jointName(i, *c) + " joins the rigid body at index " +
                             std::to_string(c->getRigidBodyA().getWorldArrayIndex()) +
                             " of the world to itself; a joint needs two bodies");
        if (!jacobianUnread(*c)) c->buildJacobian();
        StepJoint& j = set.joints[i];
        j.constraint = c;
        j.feedback = c->getJointFeedback();
        j.bodyA = bodies[i].bodyA;
        j.bodyB = bodies[i].bodyB;
        j.breakingImpulseThreshold = c->getBreakingImpulseThreshold();
        j.numIterations = c->getOverrideNumSolverIterations() > 0 ? c->getOverrideNumSolverIterations()
                                                                   : info.m_numIterations;
        if (c->isEnabled()) {
            btTypedConstraint::btConstraintInfo1 info1;
            c->getInfo1(&info1);
            if (info1.m_numConstraintRows < 0)
                throw InputError("btOpenCLConstraintSolver: " + jointName(i, *c) + " asks for " +
                                 std::to_string(info1.m_numConstraintRows) + " rows (getInfo1); a row count must not be negative");
            j.numRows = info1.m_numConstraintRows;
        }
    }, kJointWeight);
    int numRows = 0;
    for (StepJoint& j : set.joints) {
        j.firstRow = numRows;
        numRows += j.numRows;
    }
    set.rows.resize(size_t(numRows));

    // Rows: each joint's getInfo2 writes only its own rows and its own state, so the joints are
    // filled in parallel (HostParallel.h), each thread with a scratch array of its own.
    parallelFor(size_t(numJoints), [&](size_t i) {
        const StepJoint& j = set.joints[i];
        if (j.numRows == 0) return;
        thread_local btConstraintArray scratch;
        btTypedConstraint& c = *j.constraint;
        const btScalar damping = fillRowsFromJoint(c, j.numRows, info, scratch);
        const btoclBody A = jointSide(c.getRigidBodyA(), j.bodyA, solverBodies);
        const btoclBody B = jointSide(c.getRigidBodyB(), j.bodyB, solverBodies);
        for (int k = 0; k < j.numRows; ++k) {
            btoclRow r = btoclJointRow(rowFromJoint(scratch[k], j.bodyA, j.bodyB), &A, &B, damping,
                                       j.breakingImpulseThreshold);
            if (!isFiniteRow(r))
                throw InputError("btOpenCLConstraintSolver: " + jointName(i, c) +
                                 " has a non-finite row (its frames, limits or bodies)");
            BTOCL_ROW_ITERATIONS(r) = j.numIterations;
            // The solve keeps one linear Jacobian per row (btoclSolveRow): refuse a joint it would misread.
            if (!btoclRowFitsSolveRecord(r, BTOCL_BODY_IS_DYNAMIC(A) != 0.0f, BTOCL_BODY_IS_DYNAMIC(B) != 0.0f))
                throw btOpenCLSolverError("btOpenCLConstraintSolver: " + jointName(i, c) +
                                          " has a row whose linear Jacobians on its two bodies are not opposite; "
                                          "the solver holds them as one");
            set.rows[size_t(j.firstRow + k)] = r;
        }
    }, kJointWeight);

    // One constraint per joint with rows; its split point waits for a step that is split
    // (placeJointSplitPoints).
    set.constraints.reserve(set.joints.size());
    for (StepJoint& j : set.joints) {
        if (j.numRows == 0) continue;
        set.maxIterations = std::max(set.maxIterations, j.numIterations);
        btoclConstraint con{};
        con.bodyA = j.bodyA;
        con.bodyB = j.bodyB;
        con.dynamicA = BTOCL_BODY_IS_DYNAMIC(solverBodies[size_t(j.bodyA)]) != 0;
        con.dynamicB = BTOCL_BODY_IS_DYNAMIC(solverBodies[size_t(j.bodyB)]) != 0;
        con.firstRow[BTOCL_ROWS_JOINT] = j.firstRow;
        con.numRows[BTOCL_ROWS_JOINT] = j.numRows;
        con.position = btoclFloat4{0, 0, 0, float(j.numIterations)};
        j.constraintIndex = int(set.constraints.size());
        set.constraints.push_back(con);
    }
    return set;
}

// On one thread: a joint's point depends on how far the joints before it stretched its bodies'
// reach.
void placeJointSplitPoints(const JointRowSet& set, btoclConstraint* constraints, SplitReach& reach) {
    for (const StepJoint& j : set.joints) {
        if (j.numRows == 0) continue;
        btoclConstraint& con = constraints[size_t(j.constraintIndex)];
        const btVector3 point = splitPointOf(*j.constraint, j, con.dynamicA != 0, con.dynamicB != 0, reach);
        con.position = toFloat4(point, con.position.w);
        if (con.dynamicA) reach.grow(j.bodyA, point);
        if (con.dynamicB) reach.grow(j.bodyB, point);
    }
}

}  // namespace btocl
