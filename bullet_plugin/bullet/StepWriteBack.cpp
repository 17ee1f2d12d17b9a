#include "StepWriteBack.h"

#include "BulletConversions.h"
#include "HostParallel.h"
#include "JointWriteBack.h"
#include "row_setup.h"

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btTransformUtil.h>

#include <cstddef>

namespace btocl {
namespace {

// Points and bodies lie scattered in memory: each walk asks for the lines it writes this many
// elements ahead.
constexpr size_t kWriteAhead = 8;

// The lines of a Bullet point that the write-back writes, from its flags to its second friction
// direction: two of its four.
void askForPointWrites(const btManifoldPoint* point) {
    constexpr size_t first = offsetof(btManifoldPoint, m_contactPointFlags);
    constexpr size_t end = offsetof(btManifoldPoint, m_lateralFrictionDir2) + sizeof(btVector3);
    static_assert(offsetof(btManifoldPoint, m_appliedImpulse) > first && offsetof(btManifoldPoint, m_appliedImpulseLateral2) < end &&
                      offsetof(btManifoldPoint, m_lateralFrictionDir1) > first,
                  "the fields written lie between the flags and the second friction direction");
    prefetchBytes(reinterpret_cast<const char*>(point) + first, end - first, true);
}

// The lines of a rigid body that the write-back writes (its velocities and their revision count,
// its companion id) but its transform, which a push alone writes.
void askForBodyWrites(const btRigidBody* body) {
    __builtin_prefetch(&body->getLinearVelocity(), 1);
    __builtin_prefetch(&body->getAngularVelocity(), 1);
    __builtin_prefetch(&(body->*CollisionObjectMembers::updateRevision), 1);
    __builtin_prefetch(&(body->*CollisionObjectMembers::companionId), 1);
}

// One walk over the manifold points.
void writeBackPoints(const StepProblem& p, const BulletStep& bullet, const btContactSolverInfo& info) {
    const bool impulses = (info.m_solverMode & SOLVER_USE_WARMSTARTING) != 0;
    const bool two = p.frictionRowsPerPoint() == 2;
    // As SI: plane-space directions with two directions and no velocity dependence are kept.
    const bool keepDirections = two && (info.m_solverMode & SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION);
    const size_t n = p.points.size();
    // A point's friction rows are found by their index (StepProblem::firstFrictionRowOf), not read
    // from the point's record (a cache line a point, for 4 bytes).
    parallelFor(n, [&](size_t i) {
        if (i + kWriteAhead < n) askForPointWrites(bullet.manifoldPoints[i + kWriteAhead]);
        btManifoldPoint* pt = bullet.manifoldPoints[i];
        if (impulses) {
            const size_t f = size_t(p.firstFrictionRowOf(int(i)));
            pt->m_appliedImpulse = p.appliedImpulses[i];
            pt->m_appliedImpulseLateral1 = p.appliedImpulses[f];
            if (two) pt->m_appliedImpulseLateral2 = p.appliedImpulses[f + 1];
        }
        // Cached directions come back unchanged.
        pt->m_lateralFrictionDir1 = toVector3(p.lateralDirs[2 * i]);
        pt->m_lateralFrictionDir2 = toVector3(p.lateralDirs[2 * i + 1]);
        if (keepDirections) pt->m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
    });
}

// Velocities, push transforms and companion ids of the solver bodies (0 is the fixed body).
void writeBackBodies(const StepProblem& p, const BulletStep& bullet, const btContactSolverInfo& info) {
    parallelFor(size_t(p.numBodies()), [&](size_t k) {
        const size_t i = k + 1;
        if (i + kWriteAhead < bullet.original.size()) askForBodyWrites(bullet.original[i + kWriteAhead]);
        btRigidBody* rb = bullet.original[i];
        const btoclBody& b = p.bodies[i];
        const btoclBodyDelta& d = p.deltas[i];
        const btVector3 linear = toVector3(b.linearVelocity) + toVector3(d.deltaLinearVelocity);
        const btVector3 angular =
            toVector3(b.angularVelocity) + toVector3(btoclAngularChange(&b, d.deltaAngularVelocity));
        rb->setLinearVelocity(linear + toVector3(b.externalForceImpulse));
        rb->setAngularVelocity(angular + toVector3(b.externalTorqueImpulse));
        if (info.m_splitImpulse) {
            const btVector3 push = toVector3(d.pushVelocity), turn = toVector3(btoclAngularChange(&b, d.turnVelocity));
            if (!push.isZero() || !turn.isZero()) {
                btTransform next;
                btTransformUtil::integrateTransform(bullet.worldTransforms[i], push, turn * info.m_splitImpulseTurnErp,
                                                    info.m_timeStep, next);
                rb->setWorldTransform(next);
            }
        }
        rb->setCompanionId(-1);
    }, kRigidBodyWeight);
}

}  // namespace

void writeBackStep(const StepProblem& p, const BulletStep& bullet, const btContactSolverInfo& info) {
    writeBackPoints(p, bullet, info);
    const int jointStart = p.rowStart(BTOCL_ROWS_JOINT);
    writeBackJoints(bullet.joints, p.rows.data() + (jointStart - p.hostRowBase()), p.appliedImpulses.data() + jointStart,
                    info);
    writeBackBodies(p, bullet, info);
}

}  // namespace btocl
