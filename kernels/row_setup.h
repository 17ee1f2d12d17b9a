// Contact rows from a contact point, with btSequentialImpulseConstraintSolver's formulas
// (setupContactConstraint, setupFrictionConstraint, setupTorsionalFrictionConstraint), written
// once for the device (kernels/setup.cl) and the host (bullet_plugin/bullet/HostRowSetup.cpp: the path
// for anisotropic friction); and joint rows finished from what a joint's getInfo2 wrote (SI's
// convertJoint; bullet_plugin/bullet/JointRows.cpp). Functions of values: the caller reads the records
// and stores the rows. The tests hold the result to SI's own rows (tests/test_row_setup.cpp,
// tests/test_joint_rows.cpp).
#ifndef BTOCL_ROW_SETUP_H
#define BTOCL_ROW_SETUP_H

#include "btocl_shared.h"
#include "vec_math.h"

#ifndef __OPENCL_VERSION__
#include <float.h>
#endif

// What all rows of one contact point share.
typedef struct {
    btoclFloat4 relPos1, relPos2;  // the point on A (on B) relative to A's (B's) centre of mass
    btoclFloat4 vel;               // velocity of A's point relative to B's, this step's external impulses
                                   // included (SI's getVelocityInLocalPointNoDelta)
    float relVel;                  // vel along the normal
    int hasA, hasB;                // a rigid body on that side (the fixed body has no velocity)
} btoclContactFrame;

BTOCL_INLINE btoclContactFrame btoclContactFrameOf(const btoclContactPoint* pt, const btoclBody* A,
                                                   const btoclBody* B) {
    btoclContactFrame f;
    f.hasA = BTOCL_BODY_IS_RIGID(*A) != 0.0f;
    f.hasB = BTOCL_BODY_IS_RIGID(*B) != 0.0f;
    f.relPos1 = btoclXyz(pt->positionOnA) - btoclXyz(A->centerOfMass);
    f.relPos2 = btoclXyz(pt->positionOnB) - btoclXyz(B->centerOfMass);
    const btoclFloat4 velA = f.hasA ? btoclXyz(A->linearVelocity + A->externalForceImpulse) +
                                          btoclCross3(A->angularVelocity + A->externalTorqueImpulse, f.relPos1)
                                    : btoclZero4();
    const btoclFloat4 velB = f.hasB ? btoclXyz(B->linearVelocity + B->externalForceImpulse) +
                                          btoclCross3(B->angularVelocity + B->externalTorqueImpulse, f.relPos2)
                                    : btoclZero4();
    f.vel = velA - velB;
    f.relVel = btoclDot3(btoclXyz(pt->normalOnB), f.vel);
    return f;
}

// World inverse inertia times axis (SI: getInvInertiaTensorWorld() * axis).
BTOCL_INLINE btoclFloat4 btoclInvInertiaTimes(const btoclBody* b, btoclFloat4 axis) {
    return btoclRowsTimes(b->invInertiaRow0, b->invInertiaRow1, b->invInertiaRow2, axis);
}
// ... then times the angular factor (SI: I * axis * getAngularFactor()).
BTOCL_INLINE btoclFloat4 btoclAngularComponent(const btoclBody* b, btoclFloat4 axis) {
    return btoclInvInertiaTimes(b, axis) * btoclXyz(b->angularFactor);
}
// The inverse inertia about an axis, axis . I axis: a body's angular share of a row's effective
// mass (SI, contact torsion and joint rows alike: iMJaA.dot(relpos1CrossNormal)).
BTOCL_INLINE float btoclInvInertiaAlong(const btoclBody* b, btoclFloat4 axis) {
    return btoclDot3(btoclInvInertiaTimes(b, axis), axis);
}
// A body's velocity along its part of a row's Jacobian (SI's vel1Dotn, vel2Dotn).
BTOCL_INLINE float btoclJacobianVelocity(btoclFloat4 linearAxis, btoclFloat4 angularAxis, btoclFloat4 linear,
                                         btoclFloat4 angular) {
    return btoclDot3(linearAxis, linear) + btoclDot3(angularAxis, angular);
}

// A row's Jacobian and bodies; the scalars are left for the caller.
BTOCL_INLINE btoclRow btoclRowOfJacobian(btoclFloat4 n1, btoclFloat4 rp1, btoclFloat4 n2, btoclFloat4 rp2,
                                         btoclFloat4 angA, btoclFloat4 angB, int bodyA, int bodyB,
                                         int frictionIndex) {
    btoclRow r;
    r.contactNormal1 = btoclXyz(n1);
    r.relpos1CrossNormal = btoclXyz(rp1);
    r.contactNormal2 = btoclXyz(n2);
    r.relpos2CrossNormal = btoclXyz(rp2);
    r.angularComponentA = btoclXyz(angA);
    r.angularComponentB = btoclXyz(angB);
    r.impulses = btoclZero4();
    r.bodyA = bodyA;
    r.bodyB = bodyB;
    r.frictionIndex = frictionIndex;
    r.flags = 0;
    return r;
}

// Push (m_splitImpulse): a penetration past m_splitImpulsePenetrationThreshold is resolved by the
// push velocities (the normal row's push share, rhsPenetration) instead of the velocity.
BTOCL_INLINE int btoclPenetrationToPush(float penetration, const btoclSetupParams* prm) {
    return prm->usePush && !(penetration > prm->pushThreshold);
}
// Whether a contact point's normal row may get a push share (only a penetration has one): the one
// rule for the row and for the host's choice to run push iterations at all (passScheduleOf).
BTOCL_INLINE int btoclPointMayNeedPush(float distance, const btoclSetupParams* prm) {
    const float penetration = distance + prm->linearSlop;
    return penetration < 0.0f && btoclPenetrationToPush(penetration, prm);
}

// setupContactConstraint: the non-penetration row, its starting impulse the warm start.
BTOCL_INLINE btoclRow btoclNormalRow(const btoclContactPoint* pt, const btoclBody* A, const btoclBody* B,
                                     const btoclContactFrame* f, const btoclSetupParams* prm) {
    const btoclFloat4 zero = btoclZero4();
    const btoclFloat4 n = btoclXyz(pt->normalOnB);
    float cfm = prm->globalCfm;
    float erp = prm->erp2;
    if (pt->flags & (BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM | BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP)) {
        if (pt->flags & BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM) cfm = BTOCL_POINT_CONTACT_CFM(*pt);
        if (pt->flags & BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP) erp = BTOCL_POINT_CONTACT_ERP(*pt);
    } else if (pt->flags & BTOCL_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) {
        float denom = prm->timeStep * BTOCL_POINT_STIFFNESS(*pt) + BTOCL_POINT_DAMPING(*pt);
        if (denom < FLT_EPSILON) denom = FLT_EPSILON;
        cfm = 1.0f / denom;
        erp = (prm->timeStep * BTOCL_POINT_STIFFNESS(*pt)) / denom;
    }
    cfm *= prm->invTimeStep;

    const btoclFloat4 torqueAxis0 = btoclCross3(f->relPos1, n);
    const btoclFloat4 torqueAxis1 = btoclCross3(f->relPos2, n);
    const btoclFloat4 angA = f->hasA ? btoclAngularComponent(A, torqueAxis0) : zero;
    const btoclFloat4 angB = f->hasB ? btoclAngularComponent(B, -torqueAxis1) : zero;
    const float denom0 = f->hasA ? BTOCL_BODY_INV_MASS(*A) + btoclDot3(n, btoclCross3(angA, f->relPos1)) : 0.0f;
    const float denom1 = f->hasB ? BTOCL_BODY_INV_MASS(*B) + btoclDot3(n, btoclCross3(-angB, f->relPos2)) : 0.0f;
    const float jac = prm->sor / (denom0 + denom1 + cfm);
    btoclRow r = btoclRowOfJacobian(f->hasA ? n : zero, f->hasA ? torqueAxis0 : zero, f->hasB ? -n : zero,
                                    f->hasB ? -torqueAxis1 : zero, angA, angB, pt->bodyA, pt->bodyB, -1);

    // Restitution from the velocities at the start of the step, without external impulses.
    const float penetration = BTOCL_POINT_DISTANCE(*pt) + prm->linearSlop;
    float restitution = 0.0f;
    {
        const btoclFloat4 v1 = f->hasA ? btoclXyz(A->linearVelocity) + btoclCross3(A->angularVelocity, f->relPos1) : zero;
        const btoclFloat4 v2 = f->hasB ? btoclXyz(B->linearVelocity) + btoclCross3(B->angularVelocity, f->relPos2) : zero;
        const float rv = btoclDot3(n, v1 - v2);
        if (btoclFabs(rv) >= prm->restitutionVelocityThreshold) restitution = BTOCL_POINT_RESTITUTION(*pt) * -rv;
        if (restitution <= 0.0f) restitution = 0.0f;
    }
    const float vel1Dotn = btoclJacobianVelocity(r.contactNormal1, r.relpos1CrossNormal,
                                                 A->linearVelocity + (f->hasA ? A->externalForceImpulse : zero),
                                                 A->angularVelocity + (f->hasA ? A->externalTorqueImpulse : zero));
    const float vel2Dotn = btoclJacobianVelocity(r.contactNormal2, r.relpos2CrossNormal,
                                                 B->linearVelocity + (f->hasB ? B->externalForceImpulse : zero),
                                                 B->angularVelocity + (f->hasB ? B->externalTorqueImpulse : zero));
    float velocityError = restitution - (vel1Dotn + vel2Dotn);
    float positionalError = 0.0f;
    if (penetration > 0.0f)
        velocityError -= penetration * prm->invTimeStep;
    else
        positionalError = -penetration * erp * prm->invTimeStep;
    const float penetrationImpulse = positionalError * jac;
    const float velocityImpulse = velocityError * jac;
    if (btoclPenetrationToPush(penetration, prm)) {
        BTOCL_ROW_RHS(r) = velocityImpulse;
        BTOCL_ROW_RHS_PENETRATION(r) = penetrationImpulse;
    } else {
        BTOCL_ROW_RHS(r) = penetrationImpulse + velocityImpulse;
        BTOCL_ROW_RHS_PENETRATION(r) = 0.0f;
    }
    BTOCL_ROW_CFM(r) = cfm * jac;
    BTOCL_ROW_JAC_DIAG_INV(r) = jac;
    BTOCL_ROW_LOWER(r) = 0.0f;
    BTOCL_ROW_UPPER(r) = 1e10f;
    BTOCL_ROW_APPLIED(r) =
        (prm->solverMode & BTOCL_SOLVER_USE_WARMSTARTING) ? BTOCL_POINT_APPLIED(*pt) * prm->warmstartingFactor : 0.0f;
    BTOCL_ROW_FRICTION(r) = BTOCL_POINT_FRICTION(*pt);
    return r;
}

// setupFrictionConstraint along a unit axis. normalRow: the index of the point's normal row.
BTOCL_INLINE btoclRow btoclFrictionRow(btoclFloat4 axis, const btoclContactPoint* pt, const btoclBody* A,
                                       const btoclBody* B, const btoclContactFrame* f, const btoclSetupParams* prm,
                                       float desiredVelocity, float cfmSlip, int normalRow) {
    const btoclFloat4 zero = btoclZero4();
    axis = btoclXyz(axis);
    const btoclFloat4 n1 = f->hasA ? axis : zero;
    const btoclFloat4 rp1 = f->hasA ? btoclCross3(f->relPos1, n1) : zero;
    const btoclFloat4 n2 = f->hasB ? -axis : zero;
    const btoclFloat4 rp2 = f->hasB ? btoclCross3(f->relPos2, n2) : zero;
    const btoclFloat4 angA = f->hasA ? btoclAngularComponent(A, rp1) : zero;
    const btoclFloat4 angB = f->hasB ? btoclAngularComponent(B, rp2) : zero;
    const float denom0 = f->hasA ? BTOCL_BODY_INV_MASS(*A) + btoclDot3(axis, btoclCross3(angA, f->relPos1)) : 0.0f;
    const float denom1 = f->hasB ? BTOCL_BODY_INV_MASS(*B) + btoclDot3(axis, btoclCross3(-angB, f->relPos2)) : 0.0f;
    const float jac = prm->sor / (denom0 + denom1);
    btoclRow r = btoclRowOfJacobian(n1, rp1, n2, rp2, angA, angB, pt->bodyA, pt->bodyB, normalRow);

    const float vel1Dotn = btoclJacobianVelocity(n1, rp1, f->hasA ? A->linearVelocity + A->externalForceImpulse : zero,
                                                 f->hasA ? A->angularVelocity : zero);
    const float vel2Dotn = btoclJacobianVelocity(n2, rp2, f->hasB ? B->linearVelocity + B->externalForceImpulse : zero,
                                                 f->hasB ? B->angularVelocity : zero);
    const float velocityImpulse = (desiredVelocity - (vel1Dotn + vel2Dotn)) * jac;
    float penetrationImpulse = 0.0f;
    if (pt->flags & BTOCL_CONTACT_FLAG_FRICTION_ANCHOR) {
        // Friction anchors pull the points back together along the axis.
        const float distance = btoclDot3(btoclXyz(pt->positionOnA) - btoclXyz(pt->positionOnB), axis);
        penetrationImpulse = (-distance * prm->frictionERP / prm->timeStep) * jac;
    }
    const float friction = BTOCL_POINT_FRICTION(*pt);
    BTOCL_ROW_RHS(r) = penetrationImpulse + velocityImpulse;
    BTOCL_ROW_RHS_PENETRATION(r) = 0.0f;
    BTOCL_ROW_CFM(r) = cfmSlip;
    BTOCL_ROW_JAC_DIAG_INV(r) = jac;
    BTOCL_ROW_LOWER(r) = -friction;
    BTOCL_ROW_UPPER(r) = friction;
    BTOCL_ROW_FRICTION(r) = friction;
    return r;
}

// setupTorsionalFrictionConstraint: rolling (about a tangent axis) or spinning (about the normal).
BTOCL_INLINE btoclRow btoclTorsionalRow(btoclFloat4 axis, float friction, const btoclContactPoint* pt,
                                        const btoclBody* A, const btoclBody* B, const btoclContactFrame* f,
                                        int normalRow) {
    const btoclFloat4 zero = btoclZero4();
    const btoclFloat4 rp1 = -btoclXyz(axis);
    const btoclFloat4 rp2 = btoclXyz(axis);
    const btoclFloat4 angA = f->hasA ? btoclAngularComponent(A, rp1) : zero;
    const btoclFloat4 angB = f->hasB ? btoclAngularComponent(B, rp2) : zero;
    const float jac =
        1.0f / ((f->hasA ? btoclInvInertiaAlong(A, rp1) : 0.0f) + (f->hasB ? btoclInvInertiaAlong(B, rp2) : 0.0f));
    const float relVel = btoclDot3(rp1, f->hasA ? A->angularVelocity : zero) + btoclDot3(rp2, f->hasB ? B->angularVelocity : zero);
    btoclRow r = btoclRowOfJacobian(zero, rp1, zero, rp2, angA, angB, pt->bodyA, pt->bodyB, normalRow);
    BTOCL_ROW_RHS(r) = -relVel * jac;
    BTOCL_ROW_RHS_PENETRATION(r) = 0.0f;
    BTOCL_ROW_CFM(r) = 0.0f;
    BTOCL_ROW_JAC_DIAG_INV(r) = jac;
    BTOCL_ROW_LOWER(r) = -friction;
    BTOCL_ROW_UPPER(r) = friction;
    BTOCL_ROW_FRICTION(r) = friction;
    return r;
}

// A joint row, finished as SI's convertJoint finishes what the joint's getInfo2 wrote. `r` comes
// with the Jacobian (contactNormal1/2, relpos1/2CrossNormal), the constraint error in the rhs lane
// (getInfo2 already scaled it by ERP and 1/dt), the cfm and the limits. A and B as SI reads them
// for a joint: each rigid body's own inverse mass, inertia, angular factor and velocity, with this
// step's external impulses only for a body of the solver (BTOCL_BODY_IS_RIGID; a static one has
// none). `damping`: the m_damping that getInfo2 left (a point-to-point joint sets its own).
BTOCL_INLINE btoclRow btoclJointRow(btoclRow r, const btoclBody* A, const btoclBody* B, float damping,
                                    float breakingImpulseThreshold) {
    const btoclFloat4 zero = btoclZero4();
    // No row may carry more than the breaking impulse; a row that reaches it breaks the joint.
    float lower = BTOCL_ROW_LOWER(r), upper = BTOCL_ROW_UPPER(r);
    if (upper >= breakingImpulseThreshold) upper = breakingImpulseThreshold;
    if (lower <= -breakingImpulseThreshold) lower = -breakingImpulseThreshold;
    const float error = BTOCL_ROW_RHS(r);
    const float cfm = BTOCL_ROW_CFM(r);  // a joint's cfm is used as it is, not scaled as a contact's

    // The effective mass as SI takes it for joints: scalar inverse masses, inertia without the
    // angular factors, no SOR; a row that moves nothing (sum 0) gets no impulse.
    const float sum = btoclDot3(r.contactNormal1 * BTOCL_BODY_INV_MASS(*A), r.contactNormal1) +
                      btoclInvInertiaAlong(A, r.relpos1CrossNormal) +
                      btoclDot3(r.contactNormal2 * BTOCL_BODY_INV_MASS(*B), r.contactNormal2) +
                      btoclInvInertiaAlong(B, r.relpos2CrossNormal);
    const float jac = btoclFabs(sum) > FLT_EPSILON ? 1.0f / sum : 0.0f;

    const int extA = BTOCL_BODY_IS_RIGID(*A) != 0.0f, extB = BTOCL_BODY_IS_RIGID(*B) != 0.0f;
    const float relVel = btoclJacobianVelocity(r.contactNormal1, r.relpos1CrossNormal,
                                               A->linearVelocity + (extA ? A->externalForceImpulse : zero),
                                               A->angularVelocity + (extA ? A->externalTorqueImpulse : zero)) +
                         btoclJacobianVelocity(r.contactNormal2, r.relpos2CrossNormal,
                                               B->linearVelocity + (extB ? B->externalForceImpulse : zero),
                                               B->angularVelocity + (extB ? B->externalTorqueImpulse : zero));
    const float velocityError = 0.0f - relVel * damping;  // no restitution

    btoclRow out = btoclRowOfJacobian(r.contactNormal1, r.relpos1CrossNormal, r.contactNormal2, r.relpos2CrossNormal,
                                      btoclAngularComponent(A, r.relpos1CrossNormal),
                                      btoclAngularComponent(B, r.relpos2CrossNormal), r.bodyA, r.bodyB, -1);
    BTOCL_ROW_RHS(out) = error * jac + velocityError * jac;
    BTOCL_ROW_RHS_PENETRATION(out) = 0.0f;
    BTOCL_ROW_CFM(out) = cfm;
    BTOCL_ROW_JAC_DIAG_INV(out) = jac;
    BTOCL_ROW_LOWER(out) = lower;
    BTOCL_ROW_UPPER(out) = upper;
    return out;  // starting impulse 0 (SI does not warm-start joints); the caller sets BTOCL_ROW_ITERATIONS
}

// Whether a row's linear Jacobians are opposite (B's the negative of A's), as the solve's row
// record holds them, where they matter: a side of a body that cannot move may be anything.
BTOCL_INLINE int btoclRowFitsSolveRecord(btoclRow r, int dynamicA, int dynamicB) {
    const btoclFloat4 n1 = btoclXyz(r.contactNormal1), n2 = btoclXyz(r.contactNormal2);
    if (n1.x == -n2.x && n1.y == -n2.y && n1.z == -n2.z) return 1;
    return (!dynamicA && btoclDot3(n2, n2) != 0.0f && btoclDot3(n1, n1) == 0.0f) ||
           (!dynamicB && btoclDot3(n1, n1) != 0.0f && btoclDot3(n2, n2) == 0.0f);
}

// S v for a body's S (BTOCL_BODY_SCALED).
BTOCL_INLINE btoclFloat4 btoclAngularScaled(const btoclBody* b, btoclFloat4 v) {
    return btoclRowsTimes(b->angularScaleRow0, b->angularScaleRow1, b->angularScaleRow2, v);
}
// A body's angular velocity change from what the passes kept of it: S u where it is kept scaled.
BTOCL_INLINE btoclFloat4 btoclAngularChange(const btoclBody* b, btoclFloat4 kept) {
    return BTOCL_BODY_SCALED(*b) != 0.0f ? btoclAngularScaled(b, kept) : btoclXyz(kept);
}

// The row as the iterations read it (btoclSolveRow) for a row of kind BTOCL_ROWS_*: one linear
// Jacobian, A's (or, where A has none, the negative of B's), and the lanes that kind needs. A body
// whose angular change the passes keep scaled (BTOCL_BODY_SCALED; its inverse inertia S S) has
// both its side's angular Jacobian and component as S J: J . dw = (S J) . u and dw = S (S J) dp,
// so the passes keep u, and a row needs one angular vector a side (the lanes' rows:
// docs/architecture.md, "Lanes").
BTOCL_INLINE btoclSolveRow btoclSolveRowOf(btoclRow r, int kind, const btoclBody* A, const btoclBody* B) {
    btoclSolveRow s;
    const btoclFloat4 n1 = btoclXyz(r.contactNormal1);
    const btoclFloat4 n = btoclDot3(n1, n1) != 0.0f ? n1 : -btoclXyz(r.contactNormal2);
    btoclFloat4 jacobianA = r.relpos1CrossNormal, componentA = r.angularComponentA;
    btoclFloat4 jacobianB = r.relpos2CrossNormal, componentB = r.angularComponentB;
    if (BTOCL_BODY_SCALED(*A) != 0.0f) jacobianA = componentA = btoclAngularScaled(A, r.relpos1CrossNormal);
    if (BTOCL_BODY_SCALED(*B) != 0.0f) jacobianB = componentB = btoclAngularScaled(B, r.relpos2CrossNormal);
    s.normal = btoclWithW(n, BTOCL_ROW_RHS(r));
    s.relpos1CrossNormal = btoclWithW(jacobianA, BTOCL_ROW_CFM(r));
    s.relpos2CrossNormal = btoclWithW(jacobianB, BTOCL_ROW_JAC_DIAG_INV(r));
    s.angularComponentA = btoclWithW(componentA, kind == BTOCL_ROWS_JOINT    ? BTOCL_ROW_LOWER(r)
                                                          : kind == BTOCL_ROWS_NORMAL ? BTOCL_ROW_RHS_PENETRATION(r)
                                                                                      : 0.0f);
    s.angularComponentB = btoclWithW(componentB, kind == BTOCL_ROWS_JOINT    ? BTOCL_ROW_UPPER(r)
                                                          : kind == BTOCL_ROWS_NORMAL ? 0.0f
                                                                                      : BTOCL_ROW_FRICTION(r));
    return s;
}

// The friction directions of a point and what their rows take: from the sliding velocity, the
// plane space of the normal, or the directions cached on the point (SI's convertContact).
typedef struct {
    btoclFloat4 dir1, dir2;
    float motion1, motion2, cfmSlip;  // desired velocities and CFM of cached directions
    int chosen;                       // 1: chosen this step (written back to the point), 0: cached
    int fromVelocity;                 // chosen along the sliding velocity (else the plane space)
} btoclFrictionFrame;

BTOCL_INLINE btoclFrictionFrame btoclFrictionFrameOf(const btoclContactPoint* pt, const btoclContactFrame* f,
                                                     int solverMode) {
    btoclFrictionFrame ff;
    const btoclFloat4 n = btoclXyz(pt->normalOnB);
    ff.dir1 = btoclXyz(pt->lateralDir1);
    ff.dir2 = btoclXyz(pt->lateralDir2);
    ff.motion1 = ff.motion2 = ff.cfmSlip = 0.0f;
    ff.fromVelocity = 0;
    ff.chosen = !(solverMode & BTOCL_SOLVER_ENABLE_FRICTION_DIRECTION_CACHING) ||
                !(pt->flags & BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED);
    if (!ff.chosen) {
        ff.motion1 = BTOCL_POINT_MOTION1(*pt);
        ff.motion2 = BTOCL_POINT_MOTION2(*pt);
        ff.cfmSlip = BTOCL_POINT_FRICTION_CFM(*pt);
        return ff;
    }
    ff.dir1 = f->vel - n * f->relVel;
    const float latRelVel = btoclDot3(ff.dir1, ff.dir1);
    ff.fromVelocity = !(solverMode & BTOCL_SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION) && latRelVel > FLT_EPSILON;
    if (ff.fromVelocity) {
        ff.dir1 = btoclXyz(ff.dir1) * (1.0f / btoclSqrt(latRelVel));
        if (solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) ff.dir2 = btoclNormalize3(btoclCross3(ff.dir1, n));
    } else {
        btoclPlaneSpace(n, &ff.dir1, &ff.dir2);
    }
    return ff;
}

#endif
