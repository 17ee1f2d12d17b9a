// Constraint rows from contact points, one work-item per point: the normal row, one or two
// friction rows and the rolling/spinning rows, set up as btSequentialImpulseConstraintSolver's
// setupContactConstraint, setupFrictionConstraint and setupTorsionalFrictionConstraint do.
// Host reference: StepProblemBuilder's host setup (bullet_plugin/StepProblem.cpp).
#include "btocl_shared.h"

inline float4 cross3(float4 a, float4 b) {
    return (float4)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x, 0.0f);
}
inline float dot3s(float4 a, float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float4 xyz(float4 v) { return (float4)(v.x, v.y, v.z, 0.0f); }

// World inverse inertia times v, then times the angular factor (SI: I * axis * factor).
inline float4 angularComponent(const btoclBody* b, float4 axis) {
    const float4 iv = (float4)(dot3s(b->invInertiaRow0, axis), dot3s(b->invInertiaRow1, axis),
                               dot3s(b->invInertiaRow2, axis), 0.0f);
    return iv * xyz(b->angularFactor);
}
inline float4 inertiaTimes(const btoclBody* b, float4 axis) {
    return (float4)(dot3s(b->invInertiaRow0, axis), dot3s(b->invInertiaRow1, axis), dot3s(b->invInertiaRow2, axis), 0.0f);
}

// Two unit axes orthogonal to unit n (Bullet's btPlaneSpace1 convention: p first, q = n x p).
inline void planeSpace(float4 n, float4* p, float4* q) {
    if (fabs(n.z) > 0.70710678f) {
        const float a = n.y * n.y + n.z * n.z;
        const float k = 1.0f / sqrt(a);
        *p = (float4)(0.0f, -n.z * k, n.y * k, 0.0f);
        *q = (float4)(a * k, -n.x * p->z, n.x * p->y, 0.0f);
    } else {
        const float a = n.x * n.x + n.y * n.y;
        const float k = 1.0f / sqrt(a);
        *p = (float4)(-n.y * k, n.x * k, 0.0f, 0.0f);
        *q = (float4)(-n.z * p->y, n.z * p->x, a * k, 0.0f);
    }
}

// Row `index` of the solve-order layout, and its starting impulses in the compact arrays.
inline void storeRow(__global btoclRow* rows, __global float* appliedImpulses, __global float* pushImpulses, int index,
                     float4 n1, float4 rp1, float4 n2, float4 rp2, float4 angA, float4 angB,
                     float rhs, float rhsPenetration, float cfm, float jacDiagABInv, float lower, float upper,
                     float applied, float friction, int bodyA, int bodyB, int frictionIndex) {
    __global btoclRow* row = rows + index;
    row->contactNormal1 = (float4)(n1.xyz, rhs);
    row->relpos1CrossNormal = (float4)(rp1.xyz, rhsPenetration);
    row->contactNormal2 = (float4)(n2.xyz, cfm);
    row->relpos2CrossNormal = (float4)(rp2.xyz, jacDiagABInv);
    row->angularComponentA = (float4)(angA.xyz, lower);
    row->angularComponentB = (float4)(angB.xyz, upper);
    row->impulses = (float4)(applied, 0.0f, friction, 0.0f);
    appliedImpulses[index] = applied;
    pushImpulses[index] = 0.0f;
    row->bodyA = bodyA;
    row->bodyB = bodyB;
    row->frictionIndex = frictionIndex;
    row->flags = 0;
}

// setupFrictionConstraint
void frictionRow(__global btoclRow* rows, __global float* applied, __global float* pushApplied, int index, float4 axis, const btoclBody* A, const btoclBody* B, int hasA, int hasB,
                 float4 relPos1, float4 relPos2, const btoclContactPoint* pt, btoclSetupParams prm,
                 float desiredVelocity, float cfmSlip, int pointIndex) {
    const float4 zero = (float4)(0.0f);
    const float4 n1 = hasA ? axis : zero;
    const float4 rp1 = hasA ? cross3(relPos1, n1) : zero;
    const float4 angA = hasA ? angularComponent(A, rp1) : zero;
    const float4 n2 = hasB ? -axis : zero;
    const float4 rp2 = hasB ? cross3(relPos2, n2) : zero;
    const float4 angB = hasB ? angularComponent(B, rp2) : zero;
    const float denom0 = hasA ? BTOCL_BODY_INV_MASS(*A) + dot3s(axis, cross3(angA, relPos1)) : 0.0f;
    const float denom1 = hasB ? BTOCL_BODY_INV_MASS(*B) + dot3s(axis, cross3(-angB, relPos2)) : 0.0f;
    const float jac = prm.sor / (denom0 + denom1);
    const float vel1Dotn = dot3s(n1, hasA ? A->linearVelocity + A->externalForceImpulse : zero) +
                           dot3s(rp1, hasA ? A->angularVelocity : zero);
    const float vel2Dotn = dot3s(n2, hasB ? B->linearVelocity + B->externalForceImpulse : zero) +
                           dot3s(rp2, hasB ? B->angularVelocity : zero);
    const float velocityImpulse = (desiredVelocity - (vel1Dotn + vel2Dotn)) * jac;
    float penetrationImpulse = 0.0f;
    if (pt->flags & BTOCL_CONTACT_FLAG_FRICTION_ANCHOR) {
        const float distance = dot3s(xyz(pt->positionOnA) - xyz(pt->positionOnB), axis);
        penetrationImpulse = (-distance * prm.frictionERP / prm.timeStep) * jac;
    }
    const float friction = BTOCL_POINT_FRICTION(*pt);
    storeRow(rows, applied, pushApplied, index, n1, rp1, n2, rp2, angA, angB, penetrationImpulse + velocityImpulse, 0.0f, cfmSlip, jac, -friction,
             friction, 0.0f, friction, pt->bodyA, pt->bodyB, pointIndex);
}

// setupTorsionalFrictionConstraint
void torsionalRow(__global btoclRow* rows, __global float* applied, __global float* pushApplied, int index, float4 axis, const btoclBody* A, const btoclBody* B, int hasA, int hasB,
                  float friction, int bodyA, int bodyB, int pointIndex) {
    const float4 zero = (float4)(0.0f);
    const float4 rp1 = -axis;
    const float4 rp2 = axis;
    const float4 angA = hasA ? angularComponent(A, rp1) : zero;
    const float4 angB = hasB ? angularComponent(B, rp2) : zero;
    const float4 iA = hasA ? inertiaTimes(A, rp1) : zero;
    const float4 iB = hasB ? inertiaTimes(B, rp2) : zero;
    const float jac = 1.0f / (dot3s(iA, rp1) + dot3s(iB, rp2));
    const float relVel = dot3s(rp1, hasA ? A->angularVelocity : zero) + dot3s(rp2, hasB ? B->angularVelocity : zero);
    storeRow(rows, applied, pushApplied, index, zero, rp1, zero, rp2, angA, angB, -relVel * jac, 0.0f, 0.0f, jac, -friction, friction, 0.0f,
             friction, bodyA, bodyB, pointIndex);
}

// rowMap: where each row (by its index in gather order) lives in the solve-order layout.
__kernel void setupContactRows(__global const btoclContactPoint* points, __global const btoclBody* bodies,
                               __global const int* rowMap, __global btoclRow* rows, __global float* applied,
                               __global float* pushApplied, __global float4* lateralDirs, __global int* control,
                               btoclSetupParams prm) {
    const int i = get_global_id(0);
    if (i >= prm.numPoints) return;
    const btoclContactPoint pt = points[i];
    const btoclBody A = bodies[pt.bodyA];
    const btoclBody B = bodies[pt.bodyB];
    const int hasA = BTOCL_BODY_IS_RIGID(A) != 0.0f;
    const int hasB = BTOCL_BODY_IS_RIGID(B) != 0.0f;
    const float4 zero = (float4)(0.0f);
    const float4 n = xyz(pt.normalOnB);
    const float4 relPos1 = xyz(pt.positionOnA) - xyz(A.centerOfMass);
    const float4 relPos2 = xyz(pt.positionOnB) - xyz(B.centerOfMass);
    // btSolverBody::getVelocityInLocalPointNoDelta
    const float4 velA = hasA ? xyz(A.linearVelocity + A.externalForceImpulse) +
                                   cross3(A.angularVelocity + A.externalTorqueImpulse, relPos1)
                             : zero;
    const float4 velB = hasB ? xyz(B.linearVelocity + B.externalForceImpulse) +
                                   cross3(B.angularVelocity + B.externalTorqueImpulse, relPos2)
                             : zero;
    const float4 vel = velA - velB;
    const float relVel = dot3s(n, vel);

    // --- the normal row (setupContactConstraint) ---
    float cfm = prm.globalCfm;
    float erp = prm.erp2;
    if (pt.flags & (BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM | BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP)) {
        if (pt.flags & BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM) cfm = BTOCL_POINT_CONTACT_CFM(pt);
        if (pt.flags & BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP) erp = BTOCL_POINT_CONTACT_ERP(pt);
    } else if (pt.flags & BTOCL_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) {
        float denom = prm.timeStep * BTOCL_POINT_STIFFNESS(pt) + BTOCL_POINT_DAMPING(pt);
        if (denom < FLT_EPSILON) denom = FLT_EPSILON;
        cfm = 1.0f / denom;
        erp = (prm.timeStep * BTOCL_POINT_STIFFNESS(pt)) / denom;
    }
    cfm *= prm.invTimeStep;
    const float4 torqueAxis0 = cross3(relPos1, n);
    const float4 torqueAxis1 = cross3(relPos2, n);
    const float4 angA = hasA ? angularComponent(&A, torqueAxis0) : zero;
    const float4 angB = hasB ? angularComponent(&B, -torqueAxis1) : zero;
    const float denom0 = hasA ? BTOCL_BODY_INV_MASS(A) + dot3s(n, cross3(angA, relPos1)) : 0.0f;
    const float denom1 = hasB ? BTOCL_BODY_INV_MASS(B) + dot3s(n, cross3(-angB, relPos2)) : 0.0f;
    const float jac = prm.sor / (denom0 + denom1 + cfm);
    const float4 n1 = hasA ? n : zero;
    const float4 rp1 = hasA ? torqueAxis0 : zero;
    const float4 n2 = hasB ? -n : zero;
    const float4 rp2 = hasB ? -torqueAxis1 : zero;
    const float penetration = BTOCL_POINT_DISTANCE(pt) + prm.linearSlop;
    float restitution = 0.0f;
    {
        const float4 v1 = hasA ? xyz(A.linearVelocity) + cross3(A.angularVelocity, relPos1) : zero;
        const float4 v2 = hasB ? xyz(B.linearVelocity) + cross3(B.angularVelocity, relPos2) : zero;
        const float rv = dot3s(n, v1 - v2);
        if (fabs(rv) >= prm.restitutionVelocityThreshold) restitution = BTOCL_POINT_RESTITUTION(pt) * -rv;
        if (restitution <= 0.0f) restitution = 0.0f;
    }
    const float warmStart = (prm.solverMode & BTOCL_SOLVER_USE_WARMSTARTING) ? BTOCL_POINT_APPLIED(pt) * prm.warmstartingFactor : 0.0f;
    const float vel1Dotn = dot3s(n1, A.linearVelocity + (hasA ? A.externalForceImpulse : zero)) +
                           dot3s(rp1, A.angularVelocity + (hasA ? A.externalTorqueImpulse : zero));
    const float vel2Dotn = dot3s(n2, B.linearVelocity + (hasB ? B.externalForceImpulse : zero)) +
                           dot3s(rp2, B.angularVelocity + (hasB ? B.externalTorqueImpulse : zero));
    float velocityError = restitution - (vel1Dotn + vel2Dotn);
    float positionalError = 0.0f;
    if (penetration > 0.0f)
        velocityError -= penetration * prm.invTimeStep;
    else
        positionalError = -penetration * erp * prm.invTimeStep;
    const float penetrationImpulse = positionalError * jac;
    const float velocityImpulse = velocityError * jac;
    float rhs = penetrationImpulse + velocityImpulse, rhsPenetration = 0.0f;
    if (prm.splitImpulse && !(penetration > prm.splitImpulsePenetrationThreshold)) {
        rhs = velocityImpulse;
        rhsPenetration = penetrationImpulse;
        // Most steps have no point this deep: the host then launches no split-impulse pass.
        if (rhsPenetration != 0.0f) atomic_or(control + BTOCL_CONTROL_HAS_PENETRATION, 1);
    }
    const float friction = BTOCL_POINT_FRICTION(pt);
    const int normalRow = rowMap[i];
    storeRow(rows, applied, pushApplied, normalRow, n1, rp1, n2, rp2, angA, angB, rhs, rhsPenetration, cfm * jac, jac, 0.0f, 1e10f, warmStart,
             friction, pt.bodyA, pt.bodyB, -1);

    // --- rolling and spinning friction ---
    if (pt.firstRollingRow >= 0) {
        float4 axis0, axis1;
        planeSpace(n, &axis0, &axis1);
        axis0 = normalize(axis0);
        axis1 = normalize(axis1);
        torsionalRow(rows, applied, pushApplied, rowMap[pt.firstRollingRow], n, &A, &B, hasA, hasB, BTOCL_POINT_SPINNING_FRICTION(pt), pt.bodyA, pt.bodyB,
                     normalRow);
        torsionalRow(rows, applied, pushApplied, rowMap[pt.firstRollingRow + 1], axis0, &A, &B, hasA, hasB, BTOCL_POINT_ROLLING_FRICTION(pt), pt.bodyA,
                     pt.bodyB, normalRow);
        torsionalRow(rows, applied, pushApplied, rowMap[pt.firstRollingRow + 2], axis1, &A, &B, hasA, hasB, BTOCL_POINT_ROLLING_FRICTION(pt), pt.bodyA,
                     pt.bodyB, normalRow);
    }

    // --- friction rows: from the sliding velocity, the plane space, or the cached directions ---
    const int two = (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) != 0;
    float4 dir1 = xyz(pt.lateralDir1), dir2 = xyz(pt.lateralDir2);
    float motion1 = 0.0f, motion2 = 0.0f, cfmSlip = 0.0f;
    if (!(prm.solverMode & BTOCL_SOLVER_ENABLE_FRICTION_DIRECTION_CACHING) ||
        !(pt.flags & BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED)) {
        dir1 = vel - n * relVel;
        const float latRelVel = dot3s(dir1, dir1);
        if (!(prm.solverMode & BTOCL_SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION) && latRelVel > FLT_EPSILON) {
            dir1 *= 1.0f / sqrt(latRelVel);
            if (two) dir2 = normalize(cross3(dir1, n));
        } else {
            planeSpace(n, &dir1, &dir2);
        }
        lateralDirs[2 * i] = dir1;
        lateralDirs[2 * i + 1] = dir2;
    } else {
        motion1 = BTOCL_POINT_MOTION1(pt);
        motion2 = BTOCL_POINT_MOTION2(pt);
        cfmSlip = BTOCL_POINT_FRICTION_CFM(pt);
    }
    frictionRow(rows, applied, pushApplied, rowMap[pt.firstFrictionRow], dir1, &A, &B, hasA, hasB, relPos1, relPos2, &pt, prm, motion1,
                cfmSlip, normalRow);
    if (two)
        frictionRow(rows, applied, pushApplied, rowMap[pt.firstFrictionRow + 1], dir2, &A, &B, hasA, hasB, relPos1, relPos2, &pt, prm,
                    motion2, cfmSlip, normalRow);
}
