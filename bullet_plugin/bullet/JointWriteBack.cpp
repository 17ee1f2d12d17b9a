#include "JointWriteBack.h"

#include "BulletConversions.h"

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

namespace btocl {

void writeBackJoints(const JointRowSet& set, const btoclRow* rows, const float* appliedImpulses,
                     const btContactSolverInfo& info) {
    const btScalar dt = info.m_timeStep;
    for (const StepJoint& j : set.joints) {
        btTypedConstraint& c = *j.constraint;
        // SI clears these in its set-up, for every joint it is given; here, once the step is sure.
        btJointFeedback* fb = j.feedback;
        if (fb) {
            fb->m_appliedForceBodyA.setZero();
            fb->m_appliedTorqueBodyA.setZero();
            fb->m_appliedForceBodyB.setZero();
            fb->m_appliedTorqueBodyB.setZero();
        }
        c.internalSetAppliedImpulse(0);
        const btRigidBody& rbA = c.getRigidBodyA();
        const btRigidBody& rbB = c.getRigidBodyB();
        for (int r = j.firstRow; r < j.firstRow + j.numRows; ++r) {
            const btoclRow& row = rows[r];
            const btScalar impulse = appliedImpulses[r];
            if (fb) {
                // Impulse over the step: the force and torque the row exerted on each body.
                fb->m_appliedForceBodyA += toVector3(row.contactNormal1) * impulse * rbA.getLinearFactor() / dt;
                fb->m_appliedForceBodyB += toVector3(row.contactNormal2) * impulse * rbB.getLinearFactor() / dt;
                fb->m_appliedTorqueBodyA += toVector3(row.relpos1CrossNormal) * rbA.getAngularFactor() * impulse / dt;
                fb->m_appliedTorqueBodyB += toVector3(row.relpos2CrossNormal) * rbB.getAngularFactor() * impulse / dt;
            }
            // Each row overwrites it: the joint keeps its last row's impulse, as with SI.
            c.internalSetAppliedImpulse(impulse);
            // A row clamped at the threshold (btoclJointRow's limits) lands on it exactly: SI's test
            // of the final impulse, >=, breaks the joint in the same step.
            if (btFabs(impulse) >= j.breakingImpulseThreshold) c.setEnabled(false);
        }
    }
}

}  // namespace btocl
