// Bullet's vectors and bodies to and from the kernels' records.
#pragma once

#include "SolveSettings.h"
#include "btocl_shared.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btVector3.h>

#include <algorithm>
#include <cmath>

namespace btocl {

inline btoclFloat4 toFloat4(const btVector3& v, float w = 0) { return {v.x(), v.y(), v.z(), w}; }
inline btVector3 toVector3(const btoclFloat4& f) { return btVector3(f.x, f.y, f.z); }
inline bool isFinite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// Pointers to protected members of a collision object that the gather and the write-back ask
// for ahead (a class of its own names them; any collision object is read through them).
struct CollisionObjectMembers : btCollisionObject {
    static constexpr int btCollisionObject::*companionId = &CollisionObjectMembers::m_companionId;
    static constexpr int btCollisionObject::*anisotropy = &CollisionObjectMembers::m_hasAnisotropicFriction;
    static constexpr int btCollisionObject::*updateRevision = &CollisionObjectMembers::m_updateRevision;
    static constexpr int btCollisionObject::*internalType = &CollisionObjectMembers::m_internalType;
};

// The square root of a body's world inverse inertia, S = R diag(sqrt(d)) R^T for its basis R and
// local inverse inertia d, where the passes may keep its angular velocity change scaled by it
// (btoclSolveRowOf): an angular factor of 1 (0: S is 0), and the tensor Bullet holds the basis's
// (updateInertiaTensor; a body moved without it keeps SI's tensor and SI's rows). False elsewhere.
inline bool angularScaleOf(const btRigidBody& rb, btMatrix3x3& S) {
    const btVector3& factor = rb.getAngularFactor();
    const bool none = factor.isZero();
    if (!none && factor != btVector3(1, 1, 1)) return false;
    const btVector3& d = rb.getInvInertiaDiagLocal();
    if (!(d.x() >= 0 && d.y() >= 0 && d.z() >= 0)) return false;
    const btMatrix3x3& R = rb.getWorldTransform().getBasis();
    const btMatrix3x3& I = rb.getInvInertiaTensorWorld();
    const btMatrix3x3 fromBasis = R.scaled(d) * R.transpose();
    btScalar largest = 0, gap = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            largest = std::max(largest, btFabs(I[i][j]));
            gap = std::max(gap, btFabs(I[i][j] - fromBasis[i][j]));
        }
    if (!(gap <= largest * btScalar(1e-5))) return false;
    if (none) {
        S.setValue(0, 0, 0, 0, 0, 0, 0, 0, 0);
        return true;
    }
    S = R.scaled(btVector3(btSqrt(d.x()), btSqrt(d.y()), btSqrt(d.z()))) * R.transpose();
    return true;
}

// A rigid body as SI's solver body holds it (initSolverBody): inverse mass and linear factor,
// angular factor, world inverse inertia, velocities; no centre or external impulses (the gather
// adds them). solverBody: the body has a solver body of its own (w lanes: dynamic, rigid); false
// for a static body that a joint reads as SI's convertJoint reads it, while the solve's fixed
// body stands for it.
inline btoclBody bodyRecordOf(const btRigidBody& rb, bool solverBody) {
    btoclBody b{};
    const btScalar invMass = rb.getInvMass();
    b.invMass = toFloat4(btVector3(invMass, invMass, invMass) * rb.getLinearFactor(),
                         solverBody && invMass != 0 ? 1.f : 0.f);
    b.linearFactor = toFloat4(rb.getLinearFactor(), invMass);
    b.angularFactor = toFloat4(rb.getAngularFactor(), solverBody ? 1.f : 0.f);
    const btMatrix3x3& I = rb.getInvInertiaTensorWorld();
    b.invInertiaRow0 = toFloat4(I[0]);
    b.invInertiaRow1 = toFloat4(I[1]);
    b.invInertiaRow2 = toFloat4(I[2]);
    btMatrix3x3 S;
    const bool scaled = angularScaleOf(rb, S);
    if (!scaled) S.setValue(0, 0, 0, 0, 0, 0, 0, 0, 0);
    b.angularScaleRow0 = toFloat4(S[0], scaled ? 1.f : 0.f);
    b.angularScaleRow1 = toFloat4(S[1]);
    b.angularScaleRow2 = toFloat4(S[2]);
    b.linearVelocity = toFloat4(rb.getLinearVelocity());
    b.angularVelocity = toFloat4(rb.getAngularVelocity());
    return b;
}

// An object whose friction or rolling friction is anisotropic: the device's row setup does not
// handle it (HostRowSetup.h).
inline bool hasAnisotropicFriction(const btCollisionObject* o) {
    return o->hasAnisotropicFriction(btCollisionObject::CF_ANISOTROPIC_FRICTION |
                                     btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION);
}

// What the iterations read of a btContactSolverInfo. rotatePoints: each iteration starts a
// manifold's points at another one (btOpenCLSolverConfig). orderSeed: the step's seed of its
// shuffled orders with SOLVER_RANDMIZE_ORDER.
inline SolveSettings solveSettingsOf(const btContactSolverInfo& info, bool rotatePoints, unsigned orderSeed = 0) {
    SolveSettings s;
    s.numIterations = info.m_numIterations;
    s.residualThreshold = info.m_leastSquaresResidualThreshold;
    s.usePush = info.m_splitImpulse != 0;
    s.warmStart = (info.m_solverMode & SOLVER_USE_WARMSTARTING) != 0;
    // SI's SIMD row update scales by the factors once (in the row); its scalar one twice.
    if (!(info.m_solverMode & SOLVER_SIMD)) s.flags |= BTOCL_FLAG_APPLY_FACTORS;
    if (s.residualThreshold > 0) s.flags |= BTOCL_FLAG_TRACK_RESIDUAL;
    if (rotatePoints) s.flags |= BTOCL_FLAG_ROTATE_POINTS;
    if (info.m_solverMode & SOLVER_RANDMIZE_ORDER) s.flags |= BTOCL_FLAG_RANDOM_ORDER;
    if (info.m_solverMode & SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS) s.flags |= BTOCL_FLAG_INTERLEAVE_FRICTION;
    s.orderSeed = orderSeed;
    return s;
}

// What the contact row setup reads of a btContactSolverInfo (kernels/row_setup.h).
inline btoclSetupParams setupParamsOf(const btContactSolverInfo& info, int numPoints) {
    btoclSetupParams prm{};
    prm.timeStep = info.m_timeStep;
    prm.invTimeStep = btScalar(1) / info.m_timeStep;
    prm.sor = info.m_sor;
    prm.globalCfm = info.m_globalCfm;
    prm.erp2 = info.m_erp2;
    prm.linearSlop = info.m_linearSlop;
    prm.restitutionVelocityThreshold = info.m_restitutionVelocityThreshold;
    prm.warmstartingFactor = info.m_warmstartingFactor;
    prm.pushThreshold = info.m_splitImpulsePenetrationThreshold;
    prm.frictionERP = info.m_frictionERP;
    prm.usePush = info.m_splitImpulse;
    prm.solverMode = info.m_solverMode;
    prm.numPoints = numPoints;
    return prm;
}

// Whether two btContactSolverInfo agree in every setting a step reads: solveSettingsOf's and
// setupParamsOf's, the joints' (m_erp, m_damping, m_globalCfm, m_numIterations, m_timeStep), the
// gather's gyroscopic limit and the write-back's turn. A setting read anywhere else belongs here
// too: solveGroup calls of one step are gathered into one solve only while this holds.
inline bool sameStepSettings(const btContactSolverInfo& a, const btContactSolverInfo& b) {
    return a.m_timeStep == b.m_timeStep && a.m_numIterations == b.m_numIterations && a.m_solverMode == b.m_solverMode &&
           a.m_leastSquaresResidualThreshold == b.m_leastSquaresResidualThreshold && a.m_sor == b.m_sor &&
           a.m_globalCfm == b.m_globalCfm && a.m_erp2 == b.m_erp2 && a.m_erp == b.m_erp && a.m_damping == b.m_damping &&
           a.m_linearSlop == b.m_linearSlop && a.m_restitutionVelocityThreshold == b.m_restitutionVelocityThreshold &&
           a.m_warmstartingFactor == b.m_warmstartingFactor && a.m_frictionERP == b.m_frictionERP &&
           a.m_splitImpulse == b.m_splitImpulse &&
           a.m_splitImpulsePenetrationThreshold == b.m_splitImpulsePenetrationThreshold &&
           a.m_splitImpulseTurnErp == b.m_splitImpulseTurnErp && a.m_maxGyroscopicForce == b.m_maxGyroscopicForce;
}

}  // namespace btocl
