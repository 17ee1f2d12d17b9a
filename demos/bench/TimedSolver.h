// A thin btConstraintSolver decorator: forwards prepareSolve / solveGroup / allSolved to the
// real solver and adds up the wall time spent in them, i.e. the world's solveConstraints part
// (gather to writeback for ours, setup to finish for Bullet's). Also counts what the solver was
// given in this step (manifolds, contact points, joints, solveGroup calls).
#pragma once

#include <BulletDynamics/ConstraintSolver/btConstraintSolver.h>

namespace btbench {

struct SolverStepCounts {
    double ms = 0;
    int manifolds = 0, contactPoints = 0, joints = 0, bodies = 0, groupCalls = 0;
};

class TimedSolver : public btConstraintSolver {
public:
    explicit TimedSolver(btConstraintSolver& inner) : m_inner(inner) {}

    void beginStep() { m_step = SolverStepCounts(); }
    const SolverStepCounts& step() const { return m_step; }
    btConstraintSolver& inner() { return m_inner; }

    void prepareSolve(int numBodies, int numManifolds) override;
    btScalar solveGroup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                        int numManifolds, btTypedConstraint** constraints, int numConstraints,
                        const btContactSolverInfo& info, btIDebugDraw* debugDrawer, btDispatcher* dispatcher) override;
    void allSolved(const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override;
    void reset() override { m_inner.reset(); }
    btConstraintSolverType getSolverType() const override { return m_inner.getSolverType(); }

private:
    btConstraintSolver& m_inner;
    SolverStepCounts m_step;
};

}  // namespace btbench
