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
// a device error mid-step, non-finite input from the world (named: a setting by its field, a
// body by its world index), sizes past the device's limits. A step that throws has changed
// nothing in the world, and the solver steps on. btDiscreteDynamicsWorld::stepSimulation skips
// its clearForces() when the step throws: a caller who catches and steps on calls
// world.clearForces() first, or the forces (gravity too) of the failed step count twice.
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
    // A step our solver fails to run (a device error, buffers past the device's limits) is solved
    // by btSequentialImpulseConstraintSolver instead of throwing, and counted in the stats. Bad
    // input (non-finite values, negative counts) and joints still throw.
    bool fallbackToBullet = false;
};

// What the last step did. Phase times are host wall-clock milliseconds of each stage, waits for
// the device included, except msBatch (see below).
struct btOpenCLSolverStats {
    int numBodies = 0, numContactPoints = 0, numJointRows = 0, numConstraintRows = 0;
    int numCellGroups = 0, numBatchesMax = 0, numOverflowConstraints = 0, validationFailures = 0;
    double numBatchesMean = 0;
    double msGather = 0;     // reading Bullet's bodies and manifolds into the step's records
    double msUpload = 0;     // copying them to the device
    double msSplit = 0;      // the global split, up to the read-back of its group counts
    double msBatch = 0;      // the local batching: the batch kernel's device time (OpenCL event
                             // profiling; 0 where the device does not profile)
    double msSetup = 0;      // laying constraints out in solve order and setting their rows up
    double msSolve = 0;      // the warm start and every iteration
    double msDownload = 0;   // copying velocities and impulses back
    double msWriteback = 0;  // writing them to Bullet's bodies and manifold points
    double msTotal = 0;      // from the first solveGroup to the end of allSolved, gathering included
    int numIterationsRun = 0;
    std::string lastValidationMessage;  // first invariant failure of the last step, if any
    bool solvedByBullet = false;        // fallbackToBullet solved this step (of the above, only msTotal is set)
    int numFallbackSteps = 0;           // steps solved that way so far, by this solver
    std::string lastFallbackReason;     // why the latest of them was: our solver's error
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
