#include "BulletGather.h"

#include "BulletConversions.h"
#include "HostArray.h"
#include "HostParallel.h"
#include "HostRowSetup.h"
#include "InputChecks.h"
#include "btOpenCLSolverError.h"
#include "row_setup.h"

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletCollision/CollisionShapes/btConvexInternalShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cstddef>
#include <string>

namespace btocl {

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

namespace {

constexpr size_t kPrefetchAhead = 4;
// How far ahead the serial naming of the bodies asks for their lines (addBodies).
constexpr int kNameAhead = 8;

// A solver body's traits (StepGatherer::m_bodyTraits): its inverse mass is not (nearly) zero, as
// SI tests it; it is one of the step's dynamic bodies (BTOCL_BODY_IS_DYNAMIC).
constexpr unsigned char kBodyMoves = 1, kBodyDynamic = 2;

unsigned char traitsOf(const btoclBody& b) {
    return (toVector3(b.invMass).fuzzyZero() ? 0 : kBodyMoves) | (BTOCL_BODY_IS_DYNAMIC(b) ? kBodyDynamic : 0);
}

// A point record stored past the caches (StepGatherer::packManifolds): the same bytes.
void streamPoint(btoclContactPoint* to, const btoclContactPoint& from) {
#if defined(__SSE2__)
    static_assert(sizeof(btoclContactPoint) % 16 == 0 && alignof(btoclContactPoint) >= 16, "whole 16-byte stores");
    const __m128* src = reinterpret_cast<const __m128*>(&from);
    float* dst = reinterpret_cast<float*>(to);
    for (size_t q = 0; q < sizeof(btoclContactPoint) / 16; ++q) _mm_stream_ps(dst + 4 * q, src[q]);
#else
    *to = from;
#endif
}

// A manifold's tail: the lines after its points (bodies, count and thresholds).
void prefetchTail(const btPersistentManifold* m) {
    const char* tail = reinterpret_cast<const char*>(&m->getContactPoint(0)) + MANIFOLD_CACHE_SIZE * sizeof(btManifoldPoint);
    prefetchBytes(tail, size_t(reinterpret_cast<const char*>(m + 1) - tail));
}

// Manifolds lie scattered in memory: the pack asks for a manifold a few ahead, the lines of the
// points it holds (the count said how many) and its tail. Most manifolds of a heap of ragdolls
// have no point: their points' lines stay away.
void prefetchForPack(const btPersistentManifold* m, int numContacts) {
    const char* begin = reinterpret_cast<const char*>(m);
    const char* points = reinterpret_cast<const char*>(&m->getContactPoint(0));
    prefetchBytes(begin, size_t(points - begin) + size_t(numContacts) * sizeof(btManifoldPoint));
    prefetchTail(m);
}

// The count reads a manifold's tail, then a line of each point it holds (distance and rolling
// friction): the tail is asked for first, further ahead, and the points' lines once the count it
// holds has come (a manifold without points, most of a ragdoll heap's, costs one line).
void prefetchPointsForCount(const btPersistentManifold* m) {
    const char* first = reinterpret_cast<const char*>(&m->getContactPoint(0));
    for (int j = 0; j < m->getNumContacts(); ++j)
        __builtin_prefetch(first + size_t(j) * sizeof(btManifoldPoint) + offsetof(btManifoldPoint, m_distance1));
}

// The lines of a manifold's two objects that the count reads: its tail, asked for before, holds
// their addresses by now.
void prefetchObjectsForCount(const btPersistentManifold* m) {
    for (const btCollisionObject* o : {m->getBody0(), m->getBody1()}) {
        __builtin_prefetch(&(o->*CollisionObjectMembers::companionId));
        __builtin_prefetch(&(o->*CollisionObjectMembers::anisotropy));
    }
}

// The manifolds' fixed runs (StepGatherer::placeSlots): the same places whichever thread takes
// a run. The first manifold of run r (r up to kPlaceRuns: the end).
constexpr size_t kPlaceRuns = 64;
size_t runBegin(size_t n, size_t r) { return n * r / kPlaceRuns; }

// A flag that any of the threads may set, read once they are done: a line written only by the
// first to find it unset.
void setOnce(std::atomic<bool>& flag) {
    if (!flag.load(std::memory_order_relaxed)) flag.store(true, std::memory_order_relaxed);
}

}  // namespace

void StepGatherer::begin(const btContactSolverInfo& info, RowSetup setup) {
    m_info = info;
    m_setup = setup;
    m_manifolds.clear();
    m_joints.clear();
    StepProblem& p = m_problem;
    m_bullet.original.assign(1, nullptr);
    p.bodies.assign(1, btoclBody{});
    p.deltas.assign(1, btoclBodyDelta{});
    m_bodyTraits.assign(1, 0);  // the fixed body neither moves nor is dynamic
    m_bullet.worldTransforms.assign(1, btTransform::getIdentity());
    m_bullet.boxLo.assign(1, btVector3(0, 0, 0));
    m_bullet.boxHi.assign(1, btVector3(0, 0, 0));
    p.splitBodies.assign(1, SplitBody{});
    // constraints, manifoldOfConstraint, points and manifoldPoints are sized and overwritten by
    // packManifolds: kept here, they are neither zeroed nor fresh memory every step.
    p.rows.clear();
    m_bullet.joints = JointRowSet{};
    p.jointIterations = 0;
    p.regions = btoclRowRegionsOf(0, 0, 0, 0);
    p.mayNeedPush = false;
    p.setupParams = setupParamsOf(info, 0);  // the point count once the slots are placed
    // The fixed body: unit factors, all else zero (SI's initSolverBody without a body).
    p.bodies[0].linearFactor = {1, 1, 1, 0};
    p.bodies[0].angularFactor = {1, 1, 1, 0};
    BTOCL_BODY_SCALED(p.bodies[0]) = 1.0f;  // S = 0: its rows' sides move nothing either way
    p.unscaledBodies = 0;
}

// SI's initSolverBody and the external impulses of convertBodies, for the body at `index`
// (its slots made, its object in m_bullet.original).
void StepGatherer::fillSolverBody(int index) {
    StepProblem& p = m_problem;
    btRigidBody* rb = m_bullet.original[size_t(index)];
    const btScalar dt = m_info.m_timeStep;
    checkRigidBody(*rb);
    const btTransform& xf = rb->getWorldTransform();

    btoclBody b = bodyRecordOf(*rb, true);
    const btScalar invMass = rb->getInvMass();
    const btMatrix3x3& I = rb->getInvInertiaTensorWorld();
    b.centerOfMass = toFloat4(xf.getOrigin());
    b.externalForceImpulse = toFloat4(rb->getTotalForce() * invMass * dt);
    btVector3 torqueImpulse = rb->getTotalTorque() * I * dt;
    if (invMass != 0) {  // gyroscopic terms, as SI's convertBodies
        if (rb->getFlags() & BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT)
            torqueImpulse -= rb->computeGyroscopicForceExplicit(m_info.m_maxGyroscopicForce) * I * dt;
        if (rb->getFlags() & BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD)
            torqueImpulse += rb->computeGyroscopicImpulseImplicit_World(dt);
        if (rb->getFlags() & BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY)
            torqueImpulse += rb->computeGyroscopicImpulseImplicit_Body(dt);
    }
    b.externalTorqueImpulse = toFloat4(torqueImpulse);

    SplitBody split;  // its extent waits for a step that is split (addSplitGeometry)
    split.dynamic = invMass != 0;
    // Its box here, where its lines have come, rather than in a pass of its own over bodies
    // scattered in memory: a split step's reach reads it (addSplitGeometry).
    btVector3 lo = xf.getOrigin(), hi = lo;
    if (const btCollisionShape* shape = rb->getCollisionShape(); shape && split.dynamic) shape->getAabb(xf, lo, hi);
    if (BTOCL_BODY_SCALED(b) == 0.0f) __atomic_fetch_add(&p.unscaledBodies, 1, __ATOMIC_RELAXED);
    p.bodies[size_t(index)] = b;
    m_bodyTraits[size_t(index)] = traitsOf(b);
    p.deltas[size_t(index)] = btoclBodyDelta{};
    m_bullet.worldTransforms[size_t(index)] = xf;
    m_bullet.boxLo[size_t(index)] = lo;
    m_bullet.boxHi[size_t(index)] = hi;
    p.splitBodies[size_t(index)] = split;
}

// Slots for the bodies named since the last call, then their records, in parallel.
void StepGatherer::fillNewBodies() {
    StepProblem& p = m_problem;
    const size_t first = p.bodies.size(), end = m_bullet.original.size();
    p.bodies.resize(end);
    p.deltas.resize(end);
    m_bodyTraits.resize(end);
    m_bullet.worldTransforms.resize(end);
    m_bullet.boxLo.resize(end);
    m_bullet.boxHi.resize(end);
    p.splitBodies.resize(end);
    parallelFor(end - first, [&](size_t i) {
        // A rigid body's record lies in a dozen cache lines of its own, and its shape (which
        // getAabb reads) elsewhere: the record is asked for further ahead, its shape once the
        // record's line that holds the shape's address has come.
        const size_t ahead = first + i + 2 * kPrefetchAhead, near = first + i + kPrefetchAhead;
        if (ahead < end) prefetchBytes(m_bullet.original[ahead], sizeof(btRigidBody));
        if (near < end)
            if (const btCollisionShape* shape = m_bullet.original[near]->getCollisionShape())
                prefetchBytes(shape, sizeof(btConvexInternalShape));
        fillSolverBody(int(first + i));
    }, kRigidBodyWeight);
}

// Names the solver body of a rigid body; its record is filled by fillNewBodies.
int StepGatherer::nameSolverBody(btRigidBody* rb) {
    const int index = int(m_bullet.original.size());
    m_bullet.original.push_back(rb);
    rb->setCompanionId(index);
    return index;
}

// SI's getOrInitSolverBody: dynamic and kinematic rigid bodies get their own solver body, every
// other object maps to the fixed body.
int StepGatherer::solverBodyOf(btCollisionObject* object) {
    const int id = namedBodyOf(object);
    if (id > 0 && size_t(id) >= m_problem.bodies.size()) fillNewBodies();
    return id;
}

int StepGatherer::namedBodyOf(btCollisionObject* object) {
    const int id = knownBodyOf(object);
    return id >= 0 ? id : nameSolverBody(btRigidBody::upcast(object));
}

// An object's solver body if it has one or needs none (the fixed body, 0); -1 if it is a body
// still to be named. Reads only: safe in parallel.
int StepGatherer::knownBodyOf(const btCollisionObject* object) const {
    const int id = object->getCompanionId();
    if (id > 0 && id < int(m_bullet.original.size()) && m_bullet.original[size_t(id)] == object) return id;
    const btRigidBody* rb = btRigidBody::upcast(object);
    if (rb && (rb->getInvMass() != 0 || rb->isKinematicObject())) return -1;
    return 0;
}

// Indices in SI's order on this thread; the records are filled in parallel when the step is
// finished, all islands' bodies in one loop (a scene of many small islands makes a call each,
// every one too small for a parallel loop).
void StepGatherer::addBodies(btCollisionObject* const* bodies, int numBodies) {
    for (int i = 0; i < numBodies; ++i) {
        // The lines that naming reads of a body, which lie scattered, asked for ahead: its
        // companion id and type, then, once its type has come, a rigid body's inverse mass (the
        // line of its linear factor, whose address a getter gives).
        if (i + 2 * kNameAhead < numBodies) {
            const btCollisionObject* o = bodies[i + 2 * kNameAhead];
            __builtin_prefetch(&(o->*CollisionObjectMembers::companionId), 1);
            __builtin_prefetch(&(o->*CollisionObjectMembers::internalType));
        }
        if (i + kNameAhead < numBodies)
            if (const btRigidBody* rb = btRigidBody::upcast(bodies[i + kNameAhead]))
                __builtin_prefetch(&rb->getLinearFactor());
        namedBodyOf(bodies[i]);
    }
}

void StepGatherer::addManifolds(btPersistentManifold* const* manifolds, int numManifolds) {
    m_manifolds.insert(m_manifolds.end(), manifolds, manifolds + numManifolds);
}

void StepGatherer::addJoints(btTypedConstraint* const* joints, int numJoints) {
    m_joints.insert(m_joints.end(), joints, joints + numJoints);
}

// The joints' rows (JointRows.h) after every contact row, one constraint per joint with rows
// after the manifolds' constraints. Their bodies get solver bodies as SI's convertJoints gives
// them; a body's joints widen the reach the global split plans its cells for.
void StepGatherer::addJointRows() {
    StepProblem& p = m_problem;
    std::vector<JointBodies> bodies(m_joints.size());
    for (size_t i = 0; i < m_joints.size(); ++i)
        if (m_joints[i]->isEnabled()) {
            bodies[i].bodyA = solverBodyOf(&m_joints[i]->getRigidBodyA());
            bodies[i].bodyB = solverBodyOf(&m_joints[i]->getRigidBodyB());
        }
    m_bullet.joints = setUpJointRows(m_joints.data(), int(m_joints.size()), bodies.data(), p.bodies, m_info);
    p.jointIterations = m_bullet.joints.rows.empty() ? 0 : m_bullet.joints.maxIterations;
    p.regions = btoclRowRegionsOf(p.numRowsOf(BTOCL_ROWS_NORMAL), p.numRowsOf(BTOCL_ROWS_FRICTION),
                                  p.numRowsOf(BTOCL_ROWS_ROLLING), int(m_bullet.joints.rows.size()));
    for (btoclConstraint c : m_bullet.joints.constraints) {
        c.firstRow[BTOCL_ROWS_JOINT] += p.rowStart(BTOCL_ROWS_JOINT);
        p.constraints.push_back(c);
        m_bullet.manifoldOfConstraint.push_back(nullptr);
    }
    // Where no contact row is set up on the host yet, the rows move (a copy of them was a large
    // part of a joint-heavy step's gather): a host step sets its contact rows up into its solve,
    // not into p.rows (StepPipeline::solveOnHost).
    RowArray& rows = m_bullet.joints.rows;
    if (p.rows.empty())
        p.rows.swap(rows);
    else
        p.rows.insert(p.rows.end(), rows.begin(), rows.end());
    rows.clear();
}

// Two bodies that cannot move are left out (SI tests the inverse-mass vectors). Both bodies'
// records must be filled.
bool StepGatherer::canMove(const ManifoldSlot& slot) const {
    return ((m_bodyTraits[size_t(slot.bodyA)] | m_bodyTraits[size_t(slot.bodyB)]) & kBodyMoves) != 0;
}

// Whether the count takes a manifold's points as all in reach and without rolling friction,
// reading none of them: where its processing threshold is Bullet's "none" (BT_LARGE_FLOAT, every
// object's unless set), no finite distance but an absurd one is out of reach. The pack, which
// reads every point, finds where that was wrong, and the step is counted again (packManifolds).
bool StepGatherer::countsUnread(const btPersistentManifold& manifold) const {
    return !m_countEveryPoint && manifold.getContactProcessingThreshold() >= BT_LARGE_FLOAT;
}

// Looks up a manifold's bodies and counts its points in reach, reading only what the count
// needs (the points' distances and rolling friction, one cache line of each point's four; none
// where countsUnread): the points are checked as they are packed.
void StepGatherer::countPoints(size_t m) {
    ManifoldSlot& slot = m_slots[m];
    slot = ManifoldSlot{};  // every slot is written here, in parallel: no serial clearing pass
    const btPersistentManifold& manifold = *m_manifolds[m];
    // Its bodies are named even without a point, as SI names them.
    slot.bodyA = knownBodyOf(manifold.getBody0());
    slot.bodyB = knownBodyOf(manifold.getBody1());
    if (slot.bodyA < 0 || slot.bodyB < 0) setOnce(m_someUnnamed);
    slot.numContacts = manifold.getNumContacts();
    if (slot.numContacts == 0) return;  // most of a heap's manifolds: nothing more to read
    slot.anisotropic = hasAnisotropicFriction(manifold.getBody0()) || hasAnisotropicFriction(manifold.getBody1());
    if (slot.bodyA >= 0 && slot.bodyB >= 0) slot.solved = canMove(slot);
    if (countsUnread(manifold)) {
        slot.numPoints = slot.numContacts;
        return;
    }
    const btScalar threshold = manifold.getContactProcessingThreshold();
    for (int j = 0; j < manifold.getNumContacts(); ++j) {
        const btManifoldPoint& cp = manifold.getContactPoint(j);
        if (cp.getDistance() > threshold) continue;
        ++slot.numPoints;
        if (cp.m_combinedRollingFriction > 0) ++slot.numRolling;
    }
}

// SI's convertContact: the points of a manifold in reach, as records for kernels/setup.cl, at
// the places the slot was given. Rows are one normal row a point, one or two friction rows,
// three rolling rows when rolling friction is on (the host setup may drop rolling rows;
// HostRowSetup.h), in gather order: all normal rows, then friction, then rolling rows.
void StepGatherer::packManifold(size_t m, bool stream) {
    ManifoldSlot& slot = m_slots[m];
    if (slot.constraint < 0) return;
    btPersistentManifold* manifold = m_manifolds[m];
    checkManifold(*manifold, m_info, slot.anisotropic);  // before any of its points is packed
    StepProblem& p = m_problem;
    const int frictionRows = p.frictionRowsPerPoint();
    const int idA = slot.bodyA, idB = slot.bodyB;
    btoclConstraint c{};
    c.bodyA = idA;
    c.bodyB = idB;
    c.dynamicA = (m_bodyTraits[size_t(idA)] & kBodyDynamic) != 0;
    c.dynamicB = (m_bodyTraits[size_t(idB)] & kBodyDynamic) != 0;
    c.firstRow[BTOCL_ROWS_NORMAL] = slot.firstPoint;
    c.firstRow[BTOCL_ROWS_FRICTION] = p.firstFrictionRowOf(slot.firstPoint);
    c.firstRow[BTOCL_ROWS_ROLLING] = p.rowStart(BTOCL_ROWS_ROLLING) + slot.firstRolling;
    c.numRows[BTOCL_ROWS_NORMAL] = slot.numPoints;
    c.numRows[BTOCL_ROWS_FRICTION] = slot.numPoints * frictionRows;
    c.numRows[BTOCL_ROWS_ROLLING] = slot.numRolling * 3;

    int point = slot.firstPoint, rolling = c.firstRow[BTOCL_ROWS_ROLLING];
    const bool unread = countsUnread(*manifold);
    btVector3 pointSum(0, 0, 0);
    for (int j = 0; j < manifold->getNumContacts(); ++j) {
        btManifoldPoint& cp = manifold->getContactPoint(j);
        const bool outOfReach = cp.getDistance() > manifold->getContactProcessingThreshold();
        if (unread && (outOfReach || cp.m_combinedRollingFriction > 0)) {  // counted wrong: packed again
            setOnce(m_countWrong);
            return;
        }
        if (outOfReach) continue;
        if (btoclPointMayNeedPush(cp.getDistance(), &p.setupParams)) setOnce(m_someMayNeedPush);
        pointSum += (cp.getPositionWorldOnA() + cp.getPositionWorldOnB()) * btScalar(0.5);
        btoclContactPoint pt{};
        pt.positionOnA = toFloat4(cp.getPositionWorldOnA(), cp.getDistance());
        pt.positionOnB = toFloat4(cp.getPositionWorldOnB(), cp.m_combinedFriction);
        pt.normalOnB = toFloat4(cp.m_normalWorldOnB, cp.m_combinedRestitution);
        pt.lateralDir1 = toFloat4(cp.m_lateralFrictionDir1, cp.m_contactMotion1);
        pt.lateralDir2 = toFloat4(cp.m_lateralFrictionDir2, cp.m_contactMotion2);
        BTOCL_POINT_APPLIED(pt) = cp.m_appliedImpulse;
        BTOCL_POINT_ROLLING_FRICTION(pt) = cp.m_combinedRollingFriction;
        BTOCL_POINT_SPINNING_FRICTION(pt) = cp.m_combinedSpinningFriction;
        BTOCL_POINT_FRICTION_CFM(pt) = cp.m_frictionCFM;
        BTOCL_POINT_CONTACT_CFM(pt) = cp.m_contactCFM;
        BTOCL_POINT_CONTACT_ERP(pt) = cp.m_contactERP;
        BTOCL_POINT_STIFFNESS(pt) = cp.m_combinedContactStiffness1;
        BTOCL_POINT_DAMPING(pt) = cp.m_combinedContactDamping1;
        pt.bodyA = idA;
        pt.bodyB = idB;
        pt.flags = cp.m_contactPointFlags;
        pt.firstRollingRow = cp.m_combinedRollingFriction > 0 ? rolling : -1;
        if (stream)
            streamPoint(&p.points[size_t(point)], pt);
        else
            p.points[size_t(point)] = pt;
        m_bullet.manifoldPoints[size_t(point)] = &cp;
        ++point;
        if (pt.firstRollingRow >= 0) rolling += 3;
    }
    c.position = toFloat4(pointSum / btScalar(slot.numPoints));
    p.constraints[size_t(slot.constraint)] = c;
    m_bullet.manifoldOfConstraint[size_t(slot.constraint)] = manifold;
}

// Two passes over the manifolds, which lie scattered in memory: each manifold's bodies looked up,
// whether one can move, and its points counted (unread where countsUnread), in parallel; then,
// on this thread, the bodies first met here named, if any (in SI's order: manifold order), and
// places given by a running count over the slots (placeSlots); then each manifold checked and
// packed at its places, in parallel. Each pass reads what it needs of a manifold once
// (docs/performance.md, "The gather").
void StepGatherer::packManifolds() {
    StepProblem& p = m_problem;
    const size_t numManifolds = m_manifolds.size();
    fillNewBodies();  // the bodies named by addBodies: the count reads whether they can move
    // Sized with room to spare: a scene's manifolds grow for many steps, and each exact-fit
    // regrowth is fresh memory, which costs page faults.
    resizeForOverwrite(m_slots, numManifolds);
    m_someUnnamed.store(false, std::memory_order_relaxed);
    m_someMayNeedPush.store(false, std::memory_order_relaxed);
    m_countWrong.store(false, std::memory_order_relaxed);
    // In fixed runs, each run's counts kept for the slots' places (placeSlots).
    m_runs.assign(kPlaceRuns, RunCounts{});
    parallelFor(kPlaceRuns, [&](size_t r) {
        for (size_t m = runBegin(numManifolds, r); m < runBegin(numManifolds, r + 1); ++m) {
            if (m + 2 * kPrefetchAhead < numManifolds) prefetchTail(m_manifolds[m + 2 * kPrefetchAhead]);
            if (m + kPrefetchAhead < numManifolds) {
                const btPersistentManifold* ahead = m_manifolds[m + kPrefetchAhead];
                if (!countsUnread(*ahead)) prefetchPointsForCount(ahead);
                prefetchObjectsForCount(ahead);
            }
            countPoints(m);
            m_runs[r].add(m_slots[m]);
        }
    }, kManifoldWeight * (numManifolds / kPlaceRuns + 1));
    // What is new (a kinematic body, say) is named in manifold order: the order one serial pass
    // would give.
    if (m_someUnnamed.load(std::memory_order_relaxed)) {
        for (size_t m = 0; m < numManifolds; ++m) {
            ManifoldSlot& slot = m_slots[m];
            if (slot.bodyA < 0) slot.bodyA = namedBodyOf(const_cast<btCollisionObject*>(m_manifolds[m]->getBody0()));
            if (slot.bodyB < 0) slot.bodyB = namedBodyOf(const_cast<btCollisionObject*>(m_manifolds[m]->getBody1()));
        }
        fillNewBodies();
        // The slots that named a body can tell now.
        parallelFor(kPlaceRuns, [&](size_t r) {
            m_runs[r] = RunCounts{};
            for (size_t m = runBegin(numManifolds, r); m < runBegin(numManifolds, r + 1); ++m) {
                m_slots[m].solved = canMove(m_slots[m]);
                m_runs[r].add(m_slots[m]);
            }
        });
    }
    placeSlots();
    const int numPoints = btoclRegionRows(&p.regions, BTOCL_ROWS_NORMAL);
    const int numConstraints = m_numConstraints;
    resizeForOverwrite(p.points, size_t(numPoints));
    // Records that outgrow the caches are stored past them: the lanes' setup reads them slot by
    // slot after the split and the layout, from memory either way.
    const bool stream =
        m_streamPointsAlways || size_t(numPoints) * sizeof(btoclContactPoint) >= kStreamedArrayBytes;
    resizeForOverwrite(m_bullet.manifoldPoints, size_t(numPoints));
    resizeForOverwrite(p.constraints, size_t(numConstraints));
    resizeForOverwrite(m_bullet.manifoldOfConstraint, size_t(numConstraints));

    parallelFor(numManifolds, [&](size_t m) {
        const size_t ahead = m + kPrefetchAhead;
        if (ahead < numManifolds && m_slots[ahead].constraint >= 0)  // a manifold left out is not read
            prefetchForPack(m_manifolds[ahead], m_slots[ahead].numContacts);
        packManifold(m, stream);
    }, kManifoldWeight);
    if (stream) drainStreamedStores();  // the pool's threads drained theirs as they finished
    if (m_countWrong.load(std::memory_order_relaxed)) {
        // A point out of reach (an absurd distance), or rolling friction, which a scene that has
        // it keeps having: this step and the later ones read every point in the count.
        m_countEveryPoint = true;
        return packManifolds();
    }
    p.mayNeedPush = p.mayNeedPush || m_someMayNeedPush.load(std::memory_order_relaxed);
}

void StepGatherer::RunCounts::add(const ManifoldSlot& slot) {
    if (!slot.makesConstraint()) return;
    ++constraints;
    points += slot.numPoints;
    rolling += 3 * slot.numRolling;
    anisotropic = anisotropic || slot.anisotropic;
}

// Each manifold with points in reach and a body that can move gets its constraint and its places
// among the points and rolling rows, in manifold order: a running count over the runs' counts,
// then each run's slots placed from where it starts, on the host's threads (one serial pass over
// a dense block's slots took a millisecond). Sets the step's row regions.
void StepGatherer::placeSlots() {
    StepProblem& p = m_problem;
    RunCounts total;
    for (RunCounts& run : m_runs) {  // each run's counts become where it starts
        const RunCounts start = total;
        total.constraints += run.constraints;
        total.points += run.points;
        total.rolling += run.rolling;
        total.anisotropic = total.anisotropic || run.anisotropic;
        run = start;
    }
    const size_t n = m_slots.size();
    parallelFor(kPlaceRuns, [&](size_t r) {
        RunCounts at = m_runs[r];
        for (size_t m = runBegin(n, r); m < runBegin(n, r + 1); ++m) {
            ManifoldSlot& slot = m_slots[m];
            if (!slot.makesConstraint()) continue;
            slot.constraint = at.constraints++;
            slot.firstPoint = at.points;
            slot.firstRolling = at.rolling;
            at.points += slot.numPoints;
            at.rolling += 3 * slot.numRolling;
        }
    }, n / kPlaceRuns + 1);
    m_bullet.mayHaveAnisotropic = total.anisotropic;
    if (total.anisotropic) p.rowsOnDevice = false;  // the host sets up the rows (HostRowSetup.h)
    m_numConstraints = total.constraints;
    p.regions = btoclRowRegionsOf(total.points, total.points * p.frictionRowsPerPoint(), total.rolling, 0);
    p.setupParams.numPoints = total.points;  // the pack finds each point's friction rows by it
}

StepProblem& StepGatherer::finish() {
    StepProblem& p = m_problem;
    p.rowsOnDevice = m_setup == RowSetup::Device;
    packManifolds();  // a body with anisotropic friction clears rowsOnDevice
    if (!p.rowsOnDevice) setupRowsOnHost(p, m_bullet);
    if (!m_joints.empty()) addJointRows();
    return p;
}

namespace {

// Each dynamic body's extent: its reach's longest side.
void setSplitExtents(StepProblem& p, const std::vector<btVector3>& lo, const std::vector<btVector3>& hi) {
    parallelFor(p.splitBodies.size() - 1, [&](size_t i) {
        SplitBody& body = p.splitBodies[i + 1];
        if (!body.dynamic) return;
        const btVector3 size = hi[i + 1] - lo[i + 1];
        body.extent = float(size[size.maxAxis()]);
    });
}

}  // namespace

void addSplitGeometry(StepProblem& p, const BulletStep& bullet) {
    const JointRowSet& joints = bullet.joints;
    if (joints.constraints.empty()) return setSplitExtents(p, bullet.boxLo, bullet.boxHi);
    // The joints' constraints come last (StepGatherer::addJointRows); their points widen the reach.
    SplitReach reach{bullet.boxLo, bullet.boxHi};
    placeJointSplitPoints(joints, &p.constraints[p.constraints.size() - joints.constraints.size()], reach);
    setSplitExtents(p, reach.lo, reach.hi);
}

void StepGatherer::releaseBodies() {
    for (size_t i = 1; i < m_bullet.original.size(); ++i) m_bullet.original[i]->setCompanionId(-1);
}

}  // namespace btocl
