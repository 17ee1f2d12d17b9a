#include "btOpenCLConstraintSolver.h"

#include "OclRuntime.h"

// Skeleton: the device solve lands with the solver issue.
struct btOpenCLConstraintSolver::Impl {
    explicit Impl(const btOpenCLSolverConfig& c) : config(c), runtime(c.device) {}
    btOpenCLSolverConfig config;
    btocl::OclRuntime runtime;
    btOpenCLSolverStats stats;
};

btOpenCLConstraintSolver::btOpenCLConstraintSolver() : btOpenCLConstraintSolver(btOpenCLSolverConfig{}) {}
btOpenCLConstraintSolver::btOpenCLConstraintSolver(const btOpenCLSolverConfig& config)
    : m_impl(std::make_unique<Impl>(config)) {}
btOpenCLConstraintSolver::~btOpenCLConstraintSolver() = default;

void btOpenCLConstraintSolver::prepareSolve(int, int) {}
btScalar btOpenCLConstraintSolver::solveGroup(btCollisionObject**, int, btPersistentManifold**, int,
                                              btTypedConstraint**, int, const btContactSolverInfo&,
                                              btIDebugDraw*, btDispatcher*) {
    throw btOpenCLSolverError("btOpenCLConstraintSolver: solving is not implemented yet");
}
void btOpenCLConstraintSolver::allSolved(const btContactSolverInfo&, btIDebugDraw*) {}
void btOpenCLConstraintSolver::reset() {}
btConstraintSolverType btOpenCLConstraintSolver::getSolverType() const { return BT_SEQUENTIAL_IMPULSE_SOLVER; }
const btOpenCLSolverStats& btOpenCLConstraintSolver::getLastStats() const { return m_impl->stats; }
std::string btOpenCLConstraintSolver::getDeviceName() const { return m_impl->runtime.deviceName(); }
const btOpenCLSolverConfig& btOpenCLConstraintSolver::getConfig() const { return m_impl->config; }
