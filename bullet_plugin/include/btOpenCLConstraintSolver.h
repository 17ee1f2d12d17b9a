// btOpenCLConstraintSolver: Bullet's contact solver (projected Gauss-Seidel, as
// btSequentialImpulseConstraintSolver) run on an OpenCL device with the batching of
// Harada, "A Parallel Constraint Solver for a Rigid Body Simulation" (2011).
//
// Use it in place of btSequentialImpulseConstraintSolver:
//     btOpenCLConstraintSolver solver;
//     btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
#pragma once

#include <BulletDynamics/ConstraintSolver/btConstraintSolver.h>
#include <LinearMath/btScalar.h>

#include <memory>
#include <stdexcept>
#include <string>

// Every error the solver reports: no device, a kernel build failure (with the compiler's log),
// a device error mid-step, non-finite input from the world, sizes past the device's limits.
class btOpenCLSolverError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct btOpenCLSolverConfig {
    std::string device;       // "" = env BT_OPENCL_DEVICE, else first GPU, else first CPU device
    btScalar cellSize = 0;    // global-split cell edge in world units; 0 = automatic
    int batchIterations = 4;  // locking rounds per streamed chunk (the paper's 4)
    int workGroupSize = 64;   // lanes per work-group
    bool validate = false;    // check the split and batch invariants every step (tests use it)
};

struct btOpenCLSolverStats {  // of the last step
    int numBodies = 0, numContactPoints = 0, numJointRows = 0, numConstraintRows = 0;
    int numCellGroups = 0, numBatchesMax = 0, numOverflowConstraints = 0, validationFailures = 0;
    double numBatchesMean = 0;
    double msGather = 0, msSplit = 0, msBatch = 0, msSolve = 0, msWriteback = 0, msTotal = 0;
    // Finer phases (OpenCL event profiling where the device supports it).
    double msUpload = 0, msSetup = 0, msDownload = 0;
    int numIterationsRun = 0;
    std::string lastValidationMessage;  // first invariant failure of the last step, if any
};

class btOpenCLConstraintSolver : public btConstraintSolver {
public:
    btOpenCLConstraintSolver();  // default config
    explicit btOpenCLConstraintSolver(const btOpenCLSolverConfig& config);
    ~btOpenCLConstraintSolver() override;

    btOpenCLConstraintSolver(const btOpenCLConstraintSolver&) = delete;
    btOpenCLConstraintSolver& operator=(const btOpenCLConstraintSolver&) = delete;

    void prepareSolve(int numBodies, int numManifolds) override;
    btScalar solveGroup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                        int numManifolds, btTypedConstraint** constraints, int numConstraints,
                        const btContactSolverInfo& info, btIDebugDraw* debugDrawer,
                        btDispatcher* dispatcher) override;
    void allSolved(const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override;
    void reset() override;
    btConstraintSolverType getSolverType() const override;

    const btOpenCLSolverStats& getLastStats() const;
    std::string getDeviceName() const;
    const btOpenCLSolverConfig& getConfig() const;

    struct Impl;

private:
    std::unique_ptr<Impl> m_impl;
};
