// btOpenCLConstraintSolver: Bullet's contact solver (projected Gauss-Seidel, as
// btSequentialImpulseConstraintSolver) run on an OpenCL device with the batching of
// Harada, "A Parallel Constraint Solver for a Rigid Body Simulation" (2011).
//
// Use it in place of btSequentialImpulseConstraintSolver:
//     btOpenCLConstraintSolver solver;
//     btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
#pragma once

#include "btOpenCLSolverError.h"
#include "btOpenCLSolverExport.h"
#include "btOpenCLSolverVersion.h"  // BTOCL_VERSION_MAJOR, ..._MINOR, ..._PATCH, BTOCL_VERSION_STRING

#include <BulletDynamics/ConstraintSolver/btConstraintSolver.h>
#include <LinearMath/btScalar.h>

#include <memory>
#include <string>

// How the device walks the constraints of a cell group.
enum class btOpenCLSolvePath {
    Auto,    // env BT_OPENCL_SOLVE_PATH ("auto", "serial" or "wide"), else serial on a CPU device,
             // wide on any other
    Serial,  // one work-item per group walks its constraints in order; no local batches are built
             // (a CPU runs a work-group's lanes one after another anyway)
    Wide,    // workGroupSize lanes per group, batch by batch, with the sort and scan a GPU gets
};

struct btOpenCLSolverConfig {
    std::string device;       // "" = env BT_OPENCL_DEVICE, else first GPU, else first CPU device
    btScalar cellSize = 0;    // global-split cell edge in world units; 0 = automatic
    int batchIterations = 4;  // locking rounds per streamed chunk (the paper's 4)
    int workGroupSize = 64;   // lanes per work-group (wide path)
    bool validate = false;    // check the split and batch invariants every step (tests use it)
    btOpenCLSolvePath solvePath = btOpenCLSolvePath::Auto;
    // A small step is solved whole, by one work-group in one launch, without the global split:
    // there the launches per set and pass would cost more than the split saves. -1: the solver
    // decides (wide path: at most 1,024 constraints; serial path: by rows and compute units,
    // docs/architecture.md, "The plan and the passes"); 0: every step is split; n > 0: steps of at
    // most n rows.
    int wholeStepMaxRows = -1;
    // A step this small is solved on the calling thread, without the device, with the same row
    // code and in the order of a whole step: there a device launch would cost more than the step's
    // work. -1: the solver decides (env BT_OPENCL_HOST_STEPS: "never", "always", else "auto", a
    // threshold measured for the device's type, docs/performance.md); 0: never; n > 0: steps of
    // at most n rows.
    int hostStepMaxRows = -1;
    // On a CPU device, a split step that the device would solve in one claimed launch (the serial
    // path) can be solved on the calling thread instead, split alike and in the same order, to
    // the same bits. -1: the solver times both and runs each step where the recent ones ran
    // faster, by a mean that counts the worst steps (another process busy on a core stalls the
    // device's step, not the calling thread's: docs/performance.md, "Split steps on the host");
    // never where host steps are off (hostStepMaxRows 0, BT_OPENCL_HOST_STEPS "never"). 0: never;
    // 1: always.
    int splitStepsOnHost = -1;
    // Each iteration starts the walk over a contact manifold's points at another point (the same
    // from run to run): resting stacks drift and jitter several times less than with Bullet's one
    // fixed order (docs/quality.md, "Resting stacks"). Off: every iteration walks the points in one fixed
    // order, as Bullet's solver does. With SOLVER_RANDMIZE_ORDER in the solver info the points'
    // order is shuffled instead (docs/usage.md, "Solver modes").
    bool rotatePoints = false;
    // On a CPU device, the serial path can solve a split step's groups W at a time in the lanes of
    // the vector unit, W constraints of a set side by side, those on each body in their group's
    // order as a work-item walks them (the same results to the bit), where every row of the step
    // is a contact's normal or friction row in a fixed order (no joints, rolling friction,
    // SOLVER_RANDMIZE_ORDER, interleaved friction, rotatePoints or residual threshold: those
    // steps walk one group a work-item). -1: the solver
    // decides, or env BT_OPENCL_SIMD_LANES ("auto", 1, 4, 8, 16): on PoCL where the CPU has AVX2,
    // 8, the host setting the lanes' rows up, for each step whose lane layout fills its rows'
    // places well (others walk one group a work-item); elsewhere one group a work-item
    // (docs/performance.md, "Lanes set up by the host"); 1: never; 4, 8 or 16: that W, always.
    int simdLanes = -1;
    // A step our solver fails to run (a device error, buffers past the device's limits) is solved
    // by btSequentialImpulseConstraintSolver instead of throwing, and counted in the stats. Bad
    // input (non-finite values, negative counts) still throws.
    bool fallbackToBullet = false;
    // On PoCL's CPU device: its worker threads pinned to cores (the library sets POCL_AFFINITY=1
    // in the process's environment), which on a quiet machine halves the time of a split step
    // and its worst steps (docs/performance.md). PoCL reads the variable once per process, at
    // the first device query: the first solver made decides, and a value already in the
    // environment is kept. Off: the threads left to the OS, which moves them away from another
    // busy process's core.
    bool pinPoclThreads = true;
    // Every kernel the solver can launch is compiled when the solver is made, so that no step
    // waits for a compile. An OpenCL device compiles a kernel's code at its first launch: on a
    // CPU through PoCL, with an empty kernel cache (a new machine or PoCL version), seconds in all
    // (docs/performance.md, "Start-up"). Off: the solver is made without, and warmUp() does it at the
    // moment the caller chooses; until then each step compiles what it launches first.
    bool warmUpAtConstruction = true;
    // Programs are built from the binaries the library's build made for this machine's devices
    // where there is one for the device, driver and kernels in use: no compile at all, even with
    // an empty kernel cache. Off, or with none (another machine, PoCL version or device), the
    // kernels are compiled (docs/usage.md, "Kernel binaries").
    bool kernelBinaries = true;
    // The folder they are read from: "" = the environment variable BT_OPENCL_KERNEL_BINARIES (a
    // folder, or "off"), else the build tree's and the installed folder.
    std::string kernelBinaryDir;
};

// What the last step did. Times in milliseconds: the host's stages by the host's clock, the
// device's phases as the device's time of their commands (OpenCL profiling events; 0 where the
// device does not profile). The device's phases are enqueued without waits and may overlap the
// host's work and each other, so they need not add up to msDevice.
struct btOpenCLSolverStats {
    int numBodies = 0, numContactPoints = 0, numJointRows = 0, numConstraintRows = 0;
    int numCellGroups = 0, numBatchesMax = 0, numOverflowConstraints = 0, validationFailures = 0;
    double numBatchesMean = 0;
    double msGather = 0;     // host: reading Bullet's bodies, manifolds and joints into the step's records
    double msDevice = 0;     // host: from the first enqueue to the results read back (waits included)
    double msUpload = 0;     // device: copying the records over
    double msSplit = 0;      // device: the global split
    double msBatch = 0;      // device: the local batching (wide path)
    double msSetup = 0;      // device: laying constraints and rows out in solve order, setting rows up
    double msSolve = 0;      // device: the warm start and every iteration
    double msDownload = 0;   // device: copying velocities and impulses back
    double msWriteback = 0;  // host: writing them to Bullet's bodies, manifold points and joints
    double msTotal = 0;      // host: from the first solveGroup to the end of allSolved, gathering included
    int numIterationsRun = 0;
    // A small step is solved whole by one work-group in one launch, without the global split:
    // then it has one group (numCellGroups 0). Otherwise the cell groups plus the overflow group.
    bool solvedWholeStep = false;
    // The step was solved on the calling thread (hostStepMaxRows): then msSetup and msSolve are
    // the host's times of its row setup and passes, and the other device phases are 0.
    bool solvedOnHost = false;
    // Of those, a step split as the device would have it and solved in its order (splitStepsOnHost).
    bool solvedOnHostSplit = false;
    int numGroups = 0;
    // A split step solved in lanes (on the device with simdLanes; on the calling thread, 8, where
    // the CPU has AVX2): its W, 0 otherwise; the share of its slots' lanes that held a
    // constraint, and of its row blocks' places that held a row.
    int simdLanes = 0;
    double laneFill = 0, laneRowFill = 0;
    // Device memory the solver's buffers hold after the step (they are kept and grown, never
    // shrunk; the sort library's own scratch is not counted).
    double deviceBytes = 0;
    std::string lastValidationMessage;  // first invariant failure of the last step, if any
    bool solvedByBullet = false;        // fallbackToBullet solved this step (of the above, only msTotal is set)
    int numFallbackSteps = 0;           // steps solved that way so far, by this solver
    std::string lastFallbackReason;     // why the latest of them was: our solver's error
};

class BTOCL_API btOpenCLConstraintSolver : public btConstraintSolver {
public:
    btOpenCLConstraintSolver();  // default config
    explicit btOpenCLConstraintSolver(const btOpenCLSolverConfig& config);
    ~btOpenCLConstraintSolver() override;

    btOpenCLConstraintSolver(const btOpenCLConstraintSolver&) = delete;
    btOpenCLConstraintSolver& operator=(const btOpenCLConstraintSolver&) = delete;

    // A step's solveGroup calls, between prepareSolve and allSolved, are gathered and solved
    // together in allSolved. Bullet's own solver solves each call at once; so that no group is
    // lost or solved under another call's settings, the groups gathered so far are solved first
    // at a second prepareSolve and at a solveGroup whose btContactSolverInfo differs from theirs
    // in a setting the step reads. A solveGroup outside the bracket is solved at once.
    void prepareSolve(int numBodies, int numManifolds) override;
    btScalar solveGroup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds,
                        int numManifolds, btTypedConstraint** constraints, int numConstraints,
                        const btContactSolverInfo& info, btIDebugDraw* debugDrawer,
                        btDispatcher* dispatcher) override;
    void allSolved(const btContactSolverInfo& info, btIDebugDraw* debugDrawer) override;
    void reset() override;
    btConstraintSolverType getSolverType() const override;

    // Compiles now every kernel this solver can launch (what the constructor does unless
    // warmUpAtConstruction is off); a call after the first returns at once. Changes no result of
    // any step. Throws btOpenCLSolverError.
    void warmUp();

    const btOpenCLSolverStats& getLastStats() const;
    std::string getDeviceName() const;
    const btOpenCLSolverConfig& getConfig() const;
    btOpenCLSolvePath getSolvePath() const;  // the path in use (never Auto)
    // The global split's sort and scan: "chunked" (our kernels) or "boost.compute".
    const char* getSortAndScanName() const;

    struct Impl;

private:
    std::unique_ptr<Impl> m_impl;
};
