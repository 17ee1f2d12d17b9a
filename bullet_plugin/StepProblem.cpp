#include "StepProblem.h"

#include "btOpenCLConstraintSolver.h"

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <cmath>
#include <string>

namespace btocl {
namespace {

btoclFloat4 f4(const btVector3& v, float w = 0) { return {v.x(), v.y(), v.z(), w}; }
btVector3 v3(const btoclFloat4& f) { return btVector3(f.x, f.y, f.z); }

bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// A row as btSolverConstraint holds it, before packing into the kernels' layout.
struct RowValues {
    btVector3 contactNormal1{0, 0, 0}, relpos1CrossNormal{0, 0, 0};
    btVector3 contactNormal2{0, 0, 0}, relpos2CrossNormal{0, 0, 0};
    btVector3 angularComponentA{0, 0, 0}, angularComponentB{0, 0, 0};
    btScalar rhs = 0, rhsPenetration = 0, cfm = 0, jacDiagABInv = 0;
    btScalar lowerLimit = 0, upperLimit = 0, appliedImpulse = 0, friction = 0;
};

btoclRow pack(const RowValues& r, int bodyA, int bodyB, int frictionIndex) {
    btoclRow row;
    row.contactNormal1 = f4(r.contactNormal1, r.rhs);
    row.relpos1CrossNormal = f4(r.relpos1CrossNormal, r.rhsPenetration);
    row.contactNormal2 = f4(r.contactNormal2, r.cfm);
    row.relpos2CrossNormal = f4(r.relpos2CrossNormal, r.jacDiagABInv);
    row.angularComponentA = f4(r.angularComponentA, r.lowerLimit);
    row.angularComponentB = f4(r.angularComponentB, r.upperLimit);
    row.impulses = {r.appliedImpulse, 0, r.friction, 0};
    row.bodyA = bodyA;
    row.bodyB = bodyB;
    row.frictionIndex = frictionIndex;
    row.flags = 0;
    return row;
}

// The solver-body view that row setup reads (btSolverBody's fields).
struct BodyView {
    btRigidBody* rb;  // null for the fixed body
    btVector3 linearVelocity, angularVelocity, externalForceImpulse, externalTorqueImpulse;

    BodyView(btRigidBody* body, const btoclBody& b)
        : rb(body), linearVelocity(v3(b.linearVelocity)), angularVelocity(v3(b.angularVelocity)),
          externalForceImpulse(v3(b.externalForceImpulse)), externalTorqueImpulse(v3(b.externalTorqueImpulse)) {}

    // btSolverBody::getVelocityInLocalPointNoDelta
    btVector3 velocityNoDelta(const btVector3& relPos) const {
        if (!rb) return btVector3(0, 0, 0);
        return linearVelocity + externalForceImpulse + (angularVelocity + externalTorqueImpulse).cross(relPos);
    }
};

void applyAnisotropicFriction(const btCollisionObject* object, btVector3& direction, int mode) {
    if (!object || !object->hasAnisotropicFriction(mode)) return;
    const btMatrix3x3& basis = object->getWorldTransform().getBasis();
    btVector3 local = direction * basis;  // into the object's frame
    local *= object->getAnisotropicFriction();
    direction = basis * local;
}

// btSequentialImpulseConstraintSolver::setupFrictionConstraint
RowValues frictionRow(const btVector3& axis, const BodyView& a, const BodyView& b, const btManifoldPoint& cp,
                      const btVector3& relPos1, const btVector3& relPos2, btScalar relaxation,
                      const btContactSolverInfo& info, btScalar desiredVelocity, btScalar cfmSlip) {
    RowValues r;
    r.friction = cp.m_combinedFriction;
    if (a.rb) {
        r.contactNormal1 = axis;
        r.relpos1CrossNormal = relPos1.cross(r.contactNormal1);
        r.angularComponentA = a.rb->getInvInertiaTensorWorld() * r.relpos1CrossNormal * a.rb->getAngularFactor();
    }
    if (b.rb) {
        r.contactNormal2 = -axis;
        r.relpos2CrossNormal = relPos2.cross(r.contactNormal2);
        r.angularComponentB = b.rb->getInvInertiaTensorWorld() * r.relpos2CrossNormal * b.rb->getAngularFactor();
    }
    btScalar denom0 = 0, denom1 = 0;
    if (a.rb) denom0 = a.rb->getInvMass() + axis.dot(r.angularComponentA.cross(relPos1));
    if (b.rb) denom1 = b.rb->getInvMass() + axis.dot((-r.angularComponentB).cross(relPos2));
    r.jacDiagABInv = relaxation / (denom0 + denom1);

    const btVector3 zero(0, 0, 0);
    const btScalar vel1Dotn = r.contactNormal1.dot(a.rb ? a.linearVelocity + a.externalForceImpulse : zero) +
                              r.relpos1CrossNormal.dot(a.rb ? a.angularVelocity : zero);
    const btScalar vel2Dotn = r.contactNormal2.dot(b.rb ? b.linearVelocity + b.externalForceImpulse : zero) +
                              r.relpos2CrossNormal.dot(b.rb ? b.angularVelocity : zero);
    const btScalar velocityImpulse = (desiredVelocity - (vel1Dotn + vel2Dotn)) * r.jacDiagABInv;
    btScalar penetrationImpulse = 0;
    if (cp.m_contactPointFlags & BT_CONTACT_FLAG_FRICTION_ANCHOR) {
        const btScalar distance = (cp.getPositionWorldOnA() - cp.getPositionWorldOnB()).dot(axis);
        penetrationImpulse = (-distance * info.m_frictionERP / info.m_timeStep) * r.jacDiagABInv;
    }
    r.rhs = penetrationImpulse + velocityImpulse;
    r.cfm = cfmSlip;
    r.lowerLimit = -r.friction;
    r.upperLimit = r.friction;
    return r;
}

// btSequentialImpulseConstraintSolver::setupTorsionalFrictionConstraint (rolling and spinning)
RowValues torsionalRow(const btVector3& axis, const BodyView& a, const BodyView& b, btScalar friction) {
    RowValues r;
    r.friction = friction;
    r.relpos1CrossNormal = -axis;
    r.angularComponentA = a.rb ? a.rb->getInvInertiaTensorWorld() * r.relpos1CrossNormal * a.rb->getAngularFactor()
                               : btVector3(0, 0, 0);
    r.relpos2CrossNormal = axis;
    r.angularComponentB = b.rb ? b.rb->getInvInertiaTensorWorld() * r.relpos2CrossNormal * b.rb->getAngularFactor()
                               : btVector3(0, 0, 0);
    const btVector3 iMJaA = a.rb ? a.rb->getInvInertiaTensorWorld() * r.relpos1CrossNormal : btVector3(0, 0, 0);
    const btVector3 iMJaB = b.rb ? b.rb->getInvInertiaTensorWorld() * r.relpos2CrossNormal : btVector3(0, 0, 0);
    r.jacDiagABInv = btScalar(1) / (iMJaA.dot(r.relpos1CrossNormal) + iMJaB.dot(r.relpos2CrossNormal));

    const btVector3 zero(0, 0, 0);
    const btScalar relVel = r.relpos1CrossNormal.dot(a.rb ? a.angularVelocity : zero) +
                            r.relpos2CrossNormal.dot(b.rb ? b.angularVelocity : zero);
    r.rhs = -relVel * r.jacDiagABInv;
    r.lowerLimit = -r.friction;
    r.upperLimit = r.friction;
    return r;
}

}  // namespace

static_assert(BTOCL_SOLVER_USE_WARMSTARTING == SOLVER_USE_WARMSTARTING &&
                  BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS == SOLVER_USE_2_FRICTION_DIRECTIONS &&
                  BTOCL_SOLVER_ENABLE_FRICTION_DIRECTION_CACHING == SOLVER_ENABLE_FRICTION_DIRECTION_CACHING &&
                  BTOCL_SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION ==
                      SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION,
              "solver mode flags as Bullet's");
static_assert(BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED == BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED &&
                  BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM == BT_CONTACT_FLAG_HAS_CONTACT_CFM &&
                  BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP == BT_CONTACT_FLAG_HAS_CONTACT_ERP &&
                  BTOCL_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING == BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING &&
                  BTOCL_CONTACT_FLAG_FRICTION_ANCHOR == BT_CONTACT_FLAG_FRICTION_ANCHOR,
              "contact point flags as Bullet's");

void StepProblemBuilder::begin(const btContactSolverInfo& info, RowSetup setup) {
    m_info = info;
    m_setup = setup;
    m_manifolds.clear();
    StepProblem& p = m_problem;
    p.original.assign(1, nullptr);
    p.bodies.assign(1, btoclBody{});
    p.deltas.assign(1, btoclBodyDelta{});
    p.worldTransforms.assign(1, btTransform::getIdentity());
    p.splitBodies.assign(1, SplitBody{});
    p.constraints.clear();
    p.rows.clear();
    p.points.clear();
    p.pointTakesLateralDirs.clear();
    p.pointOfNormalRow.clear();
    p.frictionRowOfNormalRow.clear();
    p.numNormalRows = p.numFrictionRows = p.numRollingRows = 0;
    m_normalRows.clear();
    m_frictionRows.clear();
    m_rollingRows.clear();
    m_numFriction = m_numRolling = 0;
    // The fixed body: unit factors, all else zero (SI's initSolverBody without a body).
    p.bodies[0].linearFactor = {1, 1, 1, 0};
    p.bodies[0].angularFactor = {1, 1, 1, 0};
}

int StepProblemBuilder::addSolverBody(btRigidBody* rb) {
    const btScalar dt = m_info.m_timeStep;
    const btTransform& xf = rb->getWorldTransform();
    if (!finite(xf.getOrigin()) || !finite(rb->getLinearVelocity()) || !finite(rb->getAngularVelocity()) ||
        !finite(rb->getTotalForce()) || !finite(rb->getTotalTorque()))
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a rigid body has a non-finite position, velocity or force "
                                  "(body at index " + std::to_string(rb->getWorldArrayIndex()) + " of the world)");

    btoclBody b{};
    const btScalar invMass = rb->getInvMass();
    b.invMass = f4(btVector3(invMass, invMass, invMass) * rb->getLinearFactor(), invMass != 0 ? 1.f : 0.f);
    b.linearFactor = f4(rb->getLinearFactor(), invMass);
    b.angularFactor = f4(rb->getAngularFactor(), 1.f);
    const btMatrix3x3& I = rb->getInvInertiaTensorWorld();
    b.invInertiaRow0 = f4(I[0]);
    b.invInertiaRow1 = f4(I[1]);
    b.invInertiaRow2 = f4(I[2]);
    b.centerOfMass = f4(xf.getOrigin());
    b.linearVelocity = f4(rb->getLinearVelocity());
    b.angularVelocity = f4(rb->getAngularVelocity());
    b.externalForceImpulse = f4(rb->getTotalForce() * invMass * dt);
    btVector3 torqueImpulse = rb->getTotalTorque() * I * dt;
    if (invMass != 0) {  // gyroscopic terms, as SI's convertBodies
        if (rb->getFlags() & BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT)
            torqueImpulse -= rb->computeGyroscopicForceExplicit(m_info.m_maxGyroscopicForce) * I * dt;
        if (rb->getFlags() & BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD)
            torqueImpulse += rb->computeGyroscopicImpulseImplicit_World(dt);
        if (rb->getFlags() & BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY)
            torqueImpulse += rb->computeGyroscopicImpulseImplicit_Body(dt);
    }
    b.externalTorqueImpulse = f4(torqueImpulse);

    SplitBody split;
    split.dynamic = invMass != 0;
    if (split.dynamic) {
        btVector3 lo, hi;
        rb->getCollisionShape()->getAabb(xf, lo, hi);
        const btVector3 size = hi - lo;
        split.extent = float(size[size.maxAxis()]);
    }

    StepProblem& p = m_problem;
    const int index = int(p.bodies.size());
    p.original.push_back(rb);
    p.bodies.push_back(b);
    p.deltas.push_back(btoclBodyDelta{});
    p.worldTransforms.push_back(xf);
    p.splitBodies.push_back(split);
    rb->setCompanionId(index);
    return index;
}

// SI's getOrInitSolverBody: dynamic and kinematic rigid bodies get their own solver body, every
// other object maps to the fixed body.
int StepProblemBuilder::solverBodyOf(btCollisionObject* object) {
    const int id = object->getCompanionId();
    if (id > 0 && id < int(m_problem.original.size()) && m_problem.original[id] == object) return id;
    btRigidBody* rb = btRigidBody::upcast(object);
    if (rb && (rb->getInvMass() != 0 || rb->isKinematicObject())) return addSolverBody(rb);
    return 0;
}

void StepProblemBuilder::addBodies(btCollisionObject* const* bodies, int numBodies) {
    for (int i = 0; i < numBodies; ++i) solverBodyOf(bodies[i]);
}

void StepProblemBuilder::addManifolds(btPersistentManifold* const* manifolds, int numManifolds) {
    m_manifolds.insert(m_manifolds.end(), manifolds, manifolds + numManifolds);
}

namespace {

constexpr size_t kPrefetchAhead = 4;

void prefetchPoints(const btPersistentManifold* m) {
    const int n = m->getNumContacts();
    if (n == 0) return;
    const char* first = reinterpret_cast<const char*>(&m->getContactPoint(0));
    const char* end = reinterpret_cast<const char*>(&m->getContactPoint(n - 1)) + sizeof(btManifoldPoint);
    for (const char* a = first; a < end; a += 64) __builtin_prefetch(a);
}

void checkPoint(const btManifoldPoint& cp) {
    if (!finite(cp.getPositionWorldOnA()) || !finite(cp.getPositionWorldOnB()) || !finite(cp.m_normalWorldOnB) ||
        !std::isfinite(cp.getDistance()))
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a contact point has a non-finite position, normal "
                                  "or distance");
}

}  // namespace

// The part of SI's convertContact before the points: solver bodies, and the skip of pairs that
// cannot move. Returns false for a skipped manifold.
bool StepProblemBuilder::beginManifold(btPersistentManifold* manifold, btoclConstraint& c) {
    const int idA = solverBodyOf(const_cast<btCollisionObject*>(manifold->getBody0()));
    const int idB = solverBodyOf(const_cast<btCollisionObject*>(manifold->getBody1()));
    const StepProblem& p = m_problem;
    // No response between two bodies that cannot move (SI tests the inverse-mass vectors).
    if (v3(p.bodies[idA].invMass).fuzzyZero() && v3(p.bodies[idB].invMass).fuzzyZero()) return false;
    c = btoclConstraint{};
    c.bodyA = idA;
    c.bodyB = idB;
    c.dynamicA = BTOCL_BODY_IS_DYNAMIC(p.bodies[idA]) != 0;
    c.dynamicB = BTOCL_BODY_IS_DYNAMIC(p.bodies[idB]) != 0;
    c.firstRow[BTOCL_ROWS_NORMAL] = int(p.pointOfNormalRow.size());
    c.firstRow[BTOCL_ROWS_FRICTION] = m_numFriction;
    c.firstRow[BTOCL_ROWS_ROLLING] = m_numRolling;
    return true;
}

void StepProblemBuilder::endManifold(btoclConstraint& c, const btVector3& pointSum) {
    StepProblem& p = m_problem;
    c.numRows[BTOCL_ROWS_NORMAL] = int(p.pointOfNormalRow.size()) - c.firstRow[BTOCL_ROWS_NORMAL];
    c.numRows[BTOCL_ROWS_FRICTION] = m_numFriction - c.firstRow[BTOCL_ROWS_FRICTION];
    c.numRows[BTOCL_ROWS_ROLLING] = m_numRolling - c.firstRow[BTOCL_ROWS_ROLLING];
    if (c.numRows[BTOCL_ROWS_NORMAL] == 0) return;
    c.position = f4(pointSum / btScalar(c.numRows[BTOCL_ROWS_NORMAL]));
    p.constraints.push_back(c);
}

// The points of a manifold as records for kernels/setup.cl. Row counts are known here: one
// normal row, one or two friction rows, three rolling rows when rolling friction is on.
void StepProblemBuilder::packManifoldForDevice(btPersistentManifold* manifold) {
    btoclConstraint c;
    if (!beginManifold(manifold, c)) return;
    StepProblem& p = m_problem;
    const int mode = m_info.m_solverMode;
    const int frictionRows = (mode & SOLVER_USE_2_FRICTION_DIRECTIONS) ? 2 : 1;
    btVector3 pointSum(0, 0, 0);
    for (int j = 0; j < manifold->getNumContacts(); ++j) {
        btManifoldPoint& cp = manifold->getContactPoint(j);
        if (cp.getDistance() > manifold->getContactProcessingThreshold()) continue;
        checkPoint(cp);
        pointSum += (cp.getPositionWorldOnA() + cp.getPositionWorldOnB()) * btScalar(0.5);
        btoclContactPoint pt;
        pt.positionOnA = f4(cp.getPositionWorldOnA(), cp.getDistance());
        pt.positionOnB = f4(cp.getPositionWorldOnB(), cp.m_combinedFriction);
        pt.normalOnB = f4(cp.m_normalWorldOnB, cp.m_combinedRestitution);
        pt.lateralDir1 = f4(cp.m_lateralFrictionDir1, cp.m_contactMotion1);
        pt.lateralDir2 = f4(cp.m_lateralFrictionDir2, cp.m_contactMotion2);
        pt.impulseFriction = {cp.m_appliedImpulse, cp.m_combinedRollingFriction, cp.m_combinedSpinningFriction,
                              cp.m_frictionCFM};
        pt.contactCfmErp = {cp.m_contactCFM, cp.m_contactERP, cp.m_combinedContactStiffness1,
                            cp.m_combinedContactDamping1};
        pt.bodyA = c.bodyA;
        pt.bodyB = c.bodyB;
        pt.flags = cp.m_contactPointFlags;
        pt.firstFrictionRow = m_numFriction;
        pt.firstRollingRow = cp.m_combinedRollingFriction > 0 ? m_numRolling : -1;
        pt.pad0 = pt.pad1 = pt.pad2 = 0;
        const bool cached = (mode & SOLVER_ENABLE_FRICTION_DIRECTION_CACHING) &&
                            (cp.m_contactPointFlags & BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED);
        // As SI: plane-space directions with two directions and no velocity dependence are kept.
        if (!cached && (mode & SOLVER_USE_2_FRICTION_DIRECTIONS) &&
            (mode & SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION))
            cp.m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
        p.points.push_back(pt);
        p.pointTakesLateralDirs.push_back(!cached);
        p.pointOfNormalRow.push_back(&cp);
        p.frictionRowOfNormalRow.push_back(m_numFriction);
        m_numFriction += frictionRows;
        if (pt.firstRollingRow >= 0) m_numRolling += 3;
    }
    endManifold(c, pointSum);
}

// btSequentialImpulseConstraintSolver::convertContact on the host, rows appended per pass.
void StepProblemBuilder::setupManifoldOnHost(btPersistentManifold* manifold) {
    btoclConstraint c;
    if (!beginManifold(manifold, c)) return;
    btCollisionObject* obj0 = const_cast<btCollisionObject*>(manifold->getBody0());
    btCollisionObject* obj1 = const_cast<btCollisionObject*>(manifold->getBody1());
    const int idA = c.bodyA, idB = c.bodyB;
    StepProblem& p = m_problem;
    const btContactSolverInfo& info = m_info;
    const int mode = info.m_solverMode;
    const btScalar invDt = btScalar(1) / info.m_timeStep;
    const BodyView a(p.original[idA], p.bodies[idA]);
    const BodyView b(p.original[idB], p.bodies[idB]);
    btVector3 pointSum(0, 0, 0);

    for (int j = 0; j < manifold->getNumContacts(); ++j) {
        btManifoldPoint& cp = manifold->getContactPoint(j);
        if (cp.getDistance() > manifold->getContactProcessingThreshold()) continue;
        checkPoint(cp);
        const int normalIndex = int(m_normalRows.size());
        const btVector3 relPos1 = cp.getPositionWorldOnA() - obj0->getWorldTransform().getOrigin();
        const btVector3 relPos2 = cp.getPositionWorldOnB() - obj1->getWorldTransform().getOrigin();
        const btVector3 vel = a.velocityNoDelta(relPos1) - b.velocityNoDelta(relPos2);
        const btScalar relVel = cp.m_normalWorldOnB.dot(vel);
        pointSum += (cp.getPositionWorldOnA() + cp.getPositionWorldOnB()) * btScalar(0.5);

        // --- the normal row (setupContactConstraint) ---
        RowValues n;
        const btScalar relaxation = info.m_sor;
        btScalar cfm = info.m_globalCfm;
        btScalar erp = info.m_erp2;
        if (cp.m_contactPointFlags & (BT_CONTACT_FLAG_HAS_CONTACT_CFM | BT_CONTACT_FLAG_HAS_CONTACT_ERP)) {
            if (cp.m_contactPointFlags & BT_CONTACT_FLAG_HAS_CONTACT_CFM) cfm = cp.m_contactCFM;
            if (cp.m_contactPointFlags & BT_CONTACT_FLAG_HAS_CONTACT_ERP) erp = cp.m_contactERP;
        } else if (cp.m_contactPointFlags & BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) {
            btScalar denom = info.m_timeStep * cp.m_combinedContactStiffness1 + cp.m_combinedContactDamping1;
            if (denom < SIMD_EPSILON) denom = SIMD_EPSILON;
            cfm = btScalar(1) / denom;
            erp = (info.m_timeStep * cp.m_combinedContactStiffness1) / denom;
        }
        cfm *= invDt;

        const btVector3 torqueAxis0 = relPos1.cross(cp.m_normalWorldOnB);
        const btVector3 torqueAxis1 = relPos2.cross(cp.m_normalWorldOnB);
        if (a.rb) n.angularComponentA = a.rb->getInvInertiaTensorWorld() * torqueAxis0 * a.rb->getAngularFactor();
        if (b.rb) n.angularComponentB = b.rb->getInvInertiaTensorWorld() * -torqueAxis1 * b.rb->getAngularFactor();
        btScalar denom0 = 0, denom1 = 0;
        if (a.rb) denom0 = a.rb->getInvMass() + cp.m_normalWorldOnB.dot(n.angularComponentA.cross(relPos1));
        if (b.rb) denom1 = b.rb->getInvMass() + cp.m_normalWorldOnB.dot((-n.angularComponentB).cross(relPos2));
        n.jacDiagABInv = relaxation / (denom0 + denom1 + cfm);
        if (a.rb) {
            n.contactNormal1 = cp.m_normalWorldOnB;
            n.relpos1CrossNormal = torqueAxis0;
        }
        if (b.rb) {
            n.contactNormal2 = -cp.m_normalWorldOnB;
            n.relpos2CrossNormal = -torqueAxis1;
        }
        const btScalar penetration = cp.getDistance() + info.m_linearSlop;
        btScalar restitution = 0;
        {
            const btVector3 vel1 = a.rb ? a.rb->getVelocityInLocalPoint(relPos1) : btVector3(0, 0, 0);
            const btVector3 vel2 = b.rb ? b.rb->getVelocityInLocalPoint(relPos2) : btVector3(0, 0, 0);
            const btScalar rv = cp.m_normalWorldOnB.dot(vel1 - vel2);
            n.friction = cp.m_combinedFriction;
            if (btFabs(rv) >= info.m_restitutionVelocityThreshold) restitution = cp.m_combinedRestitution * -rv;
            if (restitution <= 0) restitution = 0;
        }
        if (mode & SOLVER_USE_WARMSTARTING) {
            n.appliedImpulse = cp.m_appliedImpulse * info.m_warmstartingFactor;
            // btSolverBody::internalApplyImpulse, as SI applies the warm start.
            auto apply = [&](int id, const btVector3& linear, const btVector3& angular, btScalar impulse) {
                btoclBodyDelta& d = p.deltas[id];
                const btoclBody& body = p.bodies[id];
                d.deltaLinearVelocity = f4(v3(d.deltaLinearVelocity) + linear * impulse * v3(body.linearFactor));
                d.deltaAngularVelocity =
                    f4(v3(d.deltaAngularVelocity) + angular * (impulse * v3(body.angularFactor)));
            };
            if (a.rb) apply(idA, n.contactNormal1 * v3(p.bodies[idA].invMass), n.angularComponentA, n.appliedImpulse);
            if (b.rb)
                apply(idB, -n.contactNormal2 * v3(p.bodies[idB].invMass), -n.angularComponentB, -n.appliedImpulse);
        }
        {
            const btVector3 zero(0, 0, 0);
            const btScalar vel1Dotn =
                n.contactNormal1.dot(a.linearVelocity + (a.rb ? a.externalForceImpulse : zero)) +
                n.relpos1CrossNormal.dot(a.angularVelocity + (a.rb ? a.externalTorqueImpulse : zero));
            const btScalar vel2Dotn =
                n.contactNormal2.dot(b.linearVelocity + (b.rb ? b.externalForceImpulse : zero)) +
                n.relpos2CrossNormal.dot(b.angularVelocity + (b.rb ? b.externalTorqueImpulse : zero));
            btScalar velocityError = restitution - (vel1Dotn + vel2Dotn);
            btScalar positionalError = 0;
            if (penetration > 0)
                velocityError -= penetration * invDt;
            else
                positionalError = -penetration * erp * invDt;
            const btScalar penetrationImpulse = positionalError * n.jacDiagABInv;
            const btScalar velocityImpulse = velocityError * n.jacDiagABInv;
            if (!info.m_splitImpulse || penetration > info.m_splitImpulsePenetrationThreshold) {
                n.rhs = penetrationImpulse + velocityImpulse;
                n.rhsPenetration = 0;
            } else {
                n.rhs = velocityImpulse;
                n.rhsPenetration = penetrationImpulse;
            }
            n.cfm = cfm * n.jacDiagABInv;
            n.lowerLimit = 0;
            n.upperLimit = 1e10f;
        }
        m_normalRows.push_back(pack(n, idA, idB, -1));
        p.pointOfNormalRow.push_back(&cp);
        p.frictionRowOfNormalRow.push_back(int(m_frictionRows.size()));

        // --- rolling and spinning friction (addTorsionalFrictionConstraint) ---
        if (cp.m_combinedRollingFriction > 0) {
            m_rollingRows.push_back(pack(torsionalRow(cp.m_normalWorldOnB, a, b, cp.m_combinedSpinningFriction),
                                         idA, idB, normalIndex));
            btVector3 axis0, axis1;
            btPlaneSpace1(cp.m_normalWorldOnB, axis0, axis1);
            axis0.normalize();
            axis1.normalize();
            applyAnisotropicFriction(obj0, axis0, btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION);
            applyAnisotropicFriction(obj1, axis0, btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION);
            applyAnisotropicFriction(obj0, axis1, btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION);
            applyAnisotropicFriction(obj1, axis1, btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION);
            if (axis0.length() > 0.001)
                m_rollingRows.push_back(pack(torsionalRow(axis0, a, b, cp.m_combinedRollingFriction), idA, idB, normalIndex));
            if (axis1.length() > 0.001)
                m_rollingRows.push_back(pack(torsionalRow(axis1, a, b, cp.m_combinedRollingFriction), idA, idB, normalIndex));
        }

        // --- friction rows: direction from the sliding velocity, the plane space, or the cache ---
        auto addFriction = [&](const btVector3& axis, btScalar desiredVelocity, btScalar cfmSlip) {
            m_frictionRows.push_back(pack(frictionRow(axis, a, b, cp, relPos1, relPos2, relaxation, info,
                                                      desiredVelocity, cfmSlip),
                                          idA, idB, normalIndex));
        };
        const bool twoDirections = (mode & SOLVER_USE_2_FRICTION_DIRECTIONS) != 0;
        if (!(mode & SOLVER_ENABLE_FRICTION_DIRECTION_CACHING) ||
            !(cp.m_contactPointFlags & BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED)) {
            cp.m_lateralFrictionDir1 = vel - cp.m_normalWorldOnB * relVel;
            const btScalar latRelVel = cp.m_lateralFrictionDir1.length2();
            if (!(mode & SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION) && latRelVel > SIMD_EPSILON) {
                cp.m_lateralFrictionDir1 *= 1.f / btSqrt(latRelVel);
                applyAnisotropicFriction(obj0, cp.m_lateralFrictionDir1, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                applyAnisotropicFriction(obj1, cp.m_lateralFrictionDir1, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                addFriction(cp.m_lateralFrictionDir1, 0, 0);
                if (twoDirections) {
                    cp.m_lateralFrictionDir2 = cp.m_lateralFrictionDir1.cross(cp.m_normalWorldOnB);
                    cp.m_lateralFrictionDir2.normalize();
                    applyAnisotropicFriction(obj0, cp.m_lateralFrictionDir2, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                    applyAnisotropicFriction(obj1, cp.m_lateralFrictionDir2, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                    addFriction(cp.m_lateralFrictionDir2, 0, 0);
                }
            } else {
                btPlaneSpace1(cp.m_normalWorldOnB, cp.m_lateralFrictionDir1, cp.m_lateralFrictionDir2);
                applyAnisotropicFriction(obj0, cp.m_lateralFrictionDir1, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                applyAnisotropicFriction(obj1, cp.m_lateralFrictionDir1, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                addFriction(cp.m_lateralFrictionDir1, 0, 0);
                if (twoDirections) {
                    applyAnisotropicFriction(obj0, cp.m_lateralFrictionDir2, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                    applyAnisotropicFriction(obj1, cp.m_lateralFrictionDir2, btCollisionObject::CF_ANISOTROPIC_FRICTION);
                    addFriction(cp.m_lateralFrictionDir2, 0, 0);
                }
                if (twoDirections && (mode & SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION))
                    cp.m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
            }
        } else {
            addFriction(cp.m_lateralFrictionDir1, cp.m_contactMotion1, cp.m_frictionCFM);
            if (twoDirections) addFriction(cp.m_lateralFrictionDir2, cp.m_contactMotion2, cp.m_frictionCFM);
        }
        m_numFriction = int(m_frictionRows.size());
        m_numRolling = int(m_rollingRows.size());
    }
    endManifold(c, pointSum);
}

StepProblem& StepProblemBuilder::finish() {
    StepProblem& p = m_problem;
    bool onDevice = m_setup == RowSetup::Device;
    for (const btPersistentManifold* m : m_manifolds)
        if (m->getBody0()->hasAnisotropicFriction(btCollisionObject::CF_ANISOTROPIC_FRICTION |
                                                  btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION) ||
            m->getBody1()->hasAnisotropicFriction(btCollisionObject::CF_ANISOTROPIC_FRICTION |
                                                  btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION))
            onDevice = false;
    p.rowsOnDevice = onDevice;
    for (size_t i = 0; i < m_manifolds.size(); ++i) {
        // Manifolds lie scattered in memory: ask for the points of one a few ahead meanwhile.
        if (i + kPrefetchAhead < m_manifolds.size()) prefetchPoints(m_manifolds[i + kPrefetchAhead]);
        if (onDevice)
            packManifoldForDevice(m_manifolds[i]);
        else
            setupManifoldOnHost(m_manifolds[i]);
    }
    p.numNormalRows = int(p.pointOfNormalRow.size());
    p.numFrictionRows = m_numFriction;
    p.numRollingRows = m_numRolling;
    const int frictionBase = p.numNormalRows;
    const int rollingBase = frictionBase + p.numFrictionRows;
    for (btoclConstraint& c : p.constraints) {
        c.firstRow[BTOCL_ROWS_FRICTION] += frictionBase;
        c.firstRow[BTOCL_ROWS_ROLLING] += rollingBase;
    }
    for (btoclContactPoint& pt : p.points) {
        pt.firstFrictionRow += frictionBase;
        if (pt.firstRollingRow >= 0) pt.firstRollingRow += rollingBase;
    }
    for (int& f : p.frictionRowOfNormalRow) f += frictionBase;
    if (!onDevice) {
        // Rows flat as the kernels read them; friction rows point at their normal row already.
        p.rows.clear();
        p.rows.reserve(size_t(p.numRows()));
        p.rows.insert(p.rows.end(), m_normalRows.begin(), m_normalRows.end());
        p.rows.insert(p.rows.end(), m_frictionRows.begin(), m_frictionRows.end());
        p.rows.insert(p.rows.end(), m_rollingRows.begin(), m_rollingRows.end());
    }
    const btContactSolverInfo& info = m_info;
    btoclSetupParams& prm = p.setupParams;
    prm = btoclSetupParams{};
    prm.timeStep = info.m_timeStep;
    prm.invTimeStep = btScalar(1) / info.m_timeStep;
    prm.sor = info.m_sor;
    prm.globalCfm = info.m_globalCfm;
    prm.erp2 = info.m_erp2;
    prm.linearSlop = info.m_linearSlop;
    prm.restitutionVelocityThreshold = info.m_restitutionVelocityThreshold;
    prm.warmstartingFactor = info.m_warmstartingFactor;
    prm.splitImpulsePenetrationThreshold = info.m_splitImpulsePenetrationThreshold;
    prm.frictionERP = info.m_frictionERP;
    prm.splitImpulse = info.m_splitImpulse;
    prm.solverMode = info.m_solverMode;
    prm.numPoints = int(p.points.size());
    return p;
}

void StepProblemBuilder::releaseBodies() {
    for (size_t i = 1; i < m_problem.original.size(); ++i) m_problem.original[i]->setCompanionId(-1);
}

}  // namespace btocl
