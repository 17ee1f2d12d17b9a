// Bullet's btSequentialImpulseConstraintSolver, unchanged, that also records how many solver
// rows (contact, friction, rolling friction, joint) it set up in the current step, so the
// summary can put its row count beside ours.
#pragma once

#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>

namespace btbench {

class CountingSISolver : public btSequentialImpulseConstraintSolver {
public:
    void prepareSolve(int numBodies, int numManifolds) override {
        m_rowsThisStep = m_jointRowsThisStep = 0;
        btSequentialImpulseConstraintSolver::prepareSolve(numBodies, numManifolds);
    }
    int rowsThisStep() const { return m_rowsThisStep; }
    int jointRowsThisStep() const { return m_jointRowsThisStep; }

protected:
    // Called between setup and finish of every solveGroup, when the row pools are full.
    btScalar solveGroupCacheFriendlyIterations(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                                               int numManifolds, btTypedConstraint** constraints, int numConstraints,
                                               const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override {
        m_rowsThisStep += m_tmpSolverContactConstraintPool.size() + m_tmpSolverContactFrictionConstraintPool.size() +
                          m_tmpSolverContactRollingFrictionConstraintPool.size() +
                          m_tmpSolverNonContactConstraintPool.size();
        m_jointRowsThisStep += m_tmpSolverNonContactConstraintPool.size();
        return btSequentialImpulseConstraintSolver::solveGroupCacheFriendlyIterations(
            bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer);
    }

private:
    int m_rowsThisStep = 0, m_jointRowsThisStep = 0;
};

}  // namespace btbench
