// Bullet's btSequentialImpulseConstraintSolver, unchanged, that also records how many solver
// rows (contact, friction, rolling friction, joint) it set up in the current step, so the
// summary can put its row count beside ours, and how long its three phases took (set-up,
// iterations, finish), so that its phases can be read beside ours.
#pragma once

#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>

#include <chrono>

namespace btbench {

class CountingSISolver : public btSequentialImpulseConstraintSolver {
public:
    void prepareSolve(int numBodies, int numManifolds) override {
        m_rowsThisStep = m_jointRowsThisStep = 0;
        m_msSetup = m_msIterations = m_msFinish = 0;
        btSequentialImpulseConstraintSolver::prepareSolve(numBodies, numManifolds);
    }
    int rowsThisStep() const { return m_rowsThisStep; }
    int jointRowsThisStep() const { return m_jointRowsThisStep; }
    // This step's time in SI's phases, over its solveGroup calls (ms): rows set up (bodies, contact
    // and joint rows, the warm start), the iterations (push iterations included), and the finish
    // (velocities, impulses and joint feedback written back).
    double msSetup() const { return m_msSetup; }
    double msIterations() const { return m_msIterations; }
    double msFinish() const { return m_msFinish; }

protected:
    btScalar solveGroupCacheFriendlySetup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                                          int numManifolds, btTypedConstraint** constraints, int numConstraints,
                                          const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override {
        const auto t0 = Clock::now();
        const btScalar r = btSequentialImpulseConstraintSolver::solveGroupCacheFriendlySetup(
            bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer);
        m_msSetup += msSince(t0);
        return r;
    }
    btScalar solveGroupCacheFriendlyFinish(btCollisionObject** bodies, int numBodies,
                                           const btContactSolverInfo& info) override {
        const auto t0 = Clock::now();
        const btScalar r = btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyFinish(bodies, numBodies, info);
        m_msFinish += msSince(t0);
        return r;
    }

    // Called between setup and finish of every solveGroup, when the row pools are full.
    btScalar solveGroupCacheFriendlyIterations(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                                               int numManifolds, btTypedConstraint** constraints, int numConstraints,
                                               const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override {
        m_rowsThisStep += m_tmpSolverContactConstraintPool.size() + m_tmpSolverContactFrictionConstraintPool.size() +
                          m_tmpSolverContactRollingFrictionConstraintPool.size() +
                          m_tmpSolverNonContactConstraintPool.size();
        m_jointRowsThisStep += m_tmpSolverNonContactConstraintPool.size();
        const auto t0 = Clock::now();
        const btScalar r = btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyIterations(
            bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer);
        m_msIterations += msSince(t0);
        return r;
    }

private:
    using Clock = std::chrono::steady_clock;
    static double msSince(Clock::time_point t0) {
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }
    int m_rowsThisStep = 0, m_jointRowsThisStep = 0;
    double m_msSetup = 0, m_msIterations = 0, m_msFinish = 0;
};

}  // namespace btbench
