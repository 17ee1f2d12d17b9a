#include "TimedSolver.h"

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <chrono>

namespace btbench {

namespace {
// Adds the time between construction and destruction to `ms`, also when the solver throws.
struct ScopedTimer {
    explicit ScopedTimer(double& ms) : total(ms), start(std::chrono::steady_clock::now()) {}
    ~ScopedTimer() {
        total += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    double& total;
    std::chrono::steady_clock::time_point start;
};
}  // namespace

void TimedSolver::prepareSolve(int numBodies, int numManifolds) {
    ScopedTimer t(m_step.ms);
    m_inner.prepareSolve(numBodies, numManifolds);
}

btScalar TimedSolver::solveGroup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                                 int numManifolds, btTypedConstraint** constraints, int numConstraints,
                                 const btContactSolverInfo& info, btIDebugDraw* debugDrawer, btDispatcher* dispatcher) {
    // Counting is outside the timed part: it is the harness's work, not the solver's.
    m_step.groupCalls += 1;
    m_step.bodies += numBodies;
    m_step.manifolds += numManifolds;
    m_step.joints += numConstraints;
    for (int i = 0; i < numManifolds; ++i) m_step.contactPoints += manifolds[i]->getNumContacts();
    ScopedTimer t(m_step.ms);
    return m_inner.solveGroup(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info,
                              debugDrawer, dispatcher);
}

void TimedSolver::allSolved(const btContactSolverInfo& info, btIDebugDraw* debugDrawer) {
    ScopedTimer t(m_step.ms);
    m_inner.allSolved(info, debugDrawer);
}

}  // namespace btbench
