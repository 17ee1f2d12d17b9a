// Bullet's own solver for a step that ours failed to run (btOpenCLSolverConfig::fallbackToBullet).
// The step's solveGroup calls are kept as Bullet made them (copies of its arrays: Bullet reuses
// them between calls) and, when the step fails, replayed through a
// btSequentialImpulseConstraintSolver. Nothing of the world is written before our solve
// succeeds, so Bullet's solver sees the step as it was.
#pragma once

#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>

#include <vector>

namespace btocl {

class SequentialFallback {
public:
    // Forgets the calls kept so far (a new step begins).
    void clear();
    // Keeps one solveGroup call.
    void keep(btCollisionObject* const* bodies, int numBodies, btPersistentManifold* const* manifolds,
              int numManifolds, btTypedConstraint* const* constraints, int numConstraints,
              const btContactSolverInfo& info, btIDebugDraw* debugDrawer, btDispatcher* dispatcher);
    // Solves the kept calls with Bullet's solver, in their order, then forgets them.
    void solve();

private:
    struct Call {
        size_t firstBody, numBodies, firstManifold, numManifolds, firstConstraint, numConstraints;
        btContactSolverInfo info;
        btIDebugDraw* debugDrawer;
        btDispatcher* dispatcher;
    };
    std::vector<Call> m_calls;
    std::vector<btCollisionObject*> m_bodies;
    std::vector<btPersistentManifold*> m_manifolds;
    std::vector<btTypedConstraint*> m_constraints;
    btSequentialImpulseConstraintSolver m_solver;
};

}  // namespace btocl
