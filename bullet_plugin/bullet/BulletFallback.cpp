#include "BulletFallback.h"

namespace btocl {

void SequentialFallback::clear() {
    m_calls.clear();
    m_bodies.clear();
    m_manifolds.clear();
    m_constraints.clear();
}

void SequentialFallback::keep(btCollisionObject* const* bodies, int numBodies, btPersistentManifold* const* manifolds,
                              int numManifolds, btTypedConstraint* const* constraints, int numConstraints,
                              const btContactSolverInfo& info, btIDebugDraw* debugDrawer, btDispatcher* dispatcher) {
    m_calls.push_back({m_bodies.size(), size_t(numBodies), m_manifolds.size(), size_t(numManifolds),
                       m_constraints.size(), size_t(numConstraints), info, debugDrawer, dispatcher});
    m_bodies.insert(m_bodies.end(), bodies, bodies + numBodies);
    m_manifolds.insert(m_manifolds.end(), manifolds, manifolds + numManifolds);
    m_constraints.insert(m_constraints.end(), constraints, constraints + numConstraints);
}

void SequentialFallback::solve() {
    if (m_calls.empty()) return;
    m_solver.prepareSolve(int(m_bodies.size()), int(m_manifolds.size()));
    for (const Call& c : m_calls)
        m_solver.solveGroup(m_bodies.data() + c.firstBody, int(c.numBodies), m_manifolds.data() + c.firstManifold,
                            int(c.numManifolds), m_constraints.data() + c.firstConstraint, int(c.numConstraints),
                            c.info, c.debugDrawer, c.dispatcher);
    m_solver.allSolved(m_calls.back().info, m_calls.back().debugDrawer);
    clear();
}

}  // namespace btocl
