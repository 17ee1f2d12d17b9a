// Gathers one step from Bullet: the bodies and manifolds that btDiscreteDynamicsWorld passes to
// solveGroup (one or more calls per step), as the records of a StepProblem and, beside them, the
// Bullet objects they came from (BulletStep). Reads Bullet's
// objects and writes nothing back but each solver body's companion id (as SI does); everything
// else a step changes is written by writeBackStep (StepWriteBack.h) once the solve succeeded.
#pragma once

#include "BulletStep.h"
#include "StepProblem.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>

#include <atomic>
#include <vector>

class btCollisionObject;
class btPersistentManifold;
class btRigidBody;
class btTypedConstraint;

namespace btocl {

// Where contact rows are set up. The host is used anyway when an object of the step has
// anisotropic friction, which the setup kernel does not handle.
enum class RowSetup { Device, Host };

class StepGatherer {
public:
    void begin(const btContactSolverInfo& info, RowSetup setup = RowSetup::Device);
    // Names the bodies' solver bodies; their records are read by finish(), which throws InputError
    // (InputChecks.h) on a body with a non-finite state, naming its world index.
    void addBodies(btCollisionObject* const* bodies, int numBodies);
    void addManifolds(btPersistentManifold* const* manifolds, int numManifolds);
    // Joints (btTypedConstraint); disabled ones take no rows, as with SI.
    void addJoints(btTypedConstraint* const* joints, int numJoints);
    // Packs every manifold's points (and, for host setup, sets the rows up) and returns the
    // finished problem; bullet() holds where its records came from. Throws InputError on a
    // non-finite contact point.
    StepProblem& finish();
    const BulletStep& bullet() const { return m_bullet; }
    // The problem's host arrays take their storage from `source` (PinnedHostMemory on a GPU;
    // null: the heap). It must outlive this gatherer or be replaced first.
    void useHostMemory(HostMemorySource* source) { m_problem.takeHostMemoryFrom(source); }
    // Returns every body's companion id to -1 (Bullet's "not in a solver").
    void releaseBodies();
    // The point records stored past the caches however few (the tests'; else from
    // kStreamedArrayBytes on, HostParallel.h).
    void streamPointsAlways(bool always) { m_streamPointsAlways = always; }

    const btContactSolverInfo& info() const { return m_info; }
    // The solver body of an object (SI's getOrInitSolverBody): a dynamic or kinematic rigid body
    // gets its own, added on first use; any other object is the fixed body, 0. Joints' bodies
    // are looked up here.
    int solverBodyOf(btCollisionObject* object);

private:
    // A manifold's share of the step: its bodies, its points in reach and where its records go.
    struct ManifoldSlot {
        int bodyA = 0, bodyB = 0;
        bool anisotropic = false;  // a body has anisotropic friction (rows set up on the host)
        int numContacts = 0;                // the manifold's points, in reach or not
        int numPoints = 0, numRolling = 0;  // points in reach; those with rolling friction
        int constraint = -1;                // its constraint, or -1 with no point in reach
        int firstPoint = 0, firstRolling = 0;
        bool solved = false;  // a body can move (known once both bodies have records)
        bool makesConstraint() const { return solved && numPoints > 0; }
    };
    int namedBodyOf(btCollisionObject* object);
    int knownBodyOf(const btCollisionObject* object) const;
    int nameSolverBody(btRigidBody* rb);
    void fillNewBodies();
    void fillSolverBody(int index);
    void packManifolds();
    bool canMove(const ManifoldSlot& slot) const;
    bool countsUnread(const btPersistentManifold& manifold) const;
    void countPoints(size_t manifold);
    // stream: the record stored past the caches (packManifolds decides it for the step).
    void packManifold(size_t manifold, bool stream);
    // What a run of slots takes (placeSlots): constraints, points, rolling rows.
    struct RunCounts {
        int constraints = 0, points = 0, rolling = 0;
        bool anisotropic = false;
        void add(const ManifoldSlot& slot);
    };
    void placeSlots();
    void addJointRows();

    btContactSolverInfo m_info;
    RowSetup m_setup = RowSetup::Device;
    std::vector<btPersistentManifold*> m_manifolds;
    std::vector<btTypedConstraint*> m_joints;
    StepProblem m_problem;
    BulletStep m_bullet;
    std::vector<ManifoldSlot> m_slots;  // one per manifold, reused from step to step
    // Per solver body, what the manifolds' passes ask of it (kBodyMoves, kBodyDynamic): a byte
    // that stays in the caches, where its record spans three lines.
    std::vector<unsigned char> m_bodyTraits;
    // Set by the manifolds' parallel passes where any manifold has them: a body still to be
    // named, a point that may need a push.
    std::atomic<bool> m_someUnnamed{false}, m_someMayNeedPush{false};
    // Set by the pack where a manifold counted unread (countsUnread) held a point out of reach or
    // with rolling friction; from then on the count reads every point (m_countEveryPoint).
    std::atomic<bool> m_countWrong{false};
    bool m_countEveryPoint = false;
    bool m_streamPointsAlways = false;
    int m_numConstraints = 0;      // the manifolds' constraints (placeSlots)
    std::vector<RunCounts> m_runs;  // per fixed run of slots (placeSlots)
};

// The global split's geometry, which only a step that is split reads (a step solved whole or on
// the host does without it): each joint's split point (its constraint's position; a contact
// constraint's is its points' centre, set by the gather) and each dynamic body's extent
// (SplitBody::extent: the largest edge of the box that holds its AABB, read by the gather
// (BulletStep::boxLo, boxHi), and its joints' split points). Call it on a finished step, before
// the split.
void addSplitGeometry(StepProblem& p, const BulletStep& bullet);

}  // namespace btocl
