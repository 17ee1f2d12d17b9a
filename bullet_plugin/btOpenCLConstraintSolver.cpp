#include "btOpenCLConstraintSolver.h"

#include "LayoutValidator.h"
#include "DeviceLayout.h"
#include "DeviceFit.h"
#include "DeviceSolver.h"
#include "HostParallel.h"
#include "InputChecks.h"
#include "OclRuntime.h"
#include "PinnedHostMemory.h"
#include "SolveSettings.h"
#include "BulletFallback.h"
#include "BulletGather.h"
#include "StepWriteBack.h"

#include <BulletDynamics/ConstraintSolver/btTypedConstraint.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <cmath>
#include <limits>

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Host wall time of a step's stages, one lap each.
class StageTimer {
public:
    double lap() {
        const Clock::time_point now = Clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - m_last).count();
        m_last = now;
        return ms;
    }
    double total() const { return msSince(m_start); }

private:
    Clock::time_point m_start = Clock::now(), m_last = m_start;
};

// When a step runs whole in one launch of one work-group (no global split, no sets): when the
// split and the sets' groups solved side by side would save less than they cost.
// - Wide path (a GPU's): at most 1,024 constraints, a few batches of one work-group's lanes.
// - Serial path (a CPU's, one work-item per group): the split spreads the solve over the compute
//   units in one claimed launch (solveStepClaimed). Measured on PoCL (2 cores; btocl_bench
//   --whole-step-max-rows 0 against whole, ms a step, same runs of SI): pile 1,000 (8K rows) 3.55
//   / 2.49, pile 2,500 (20K rows) 8.2 / 7.6, block 800 (35K rows) 6.7 / 7.2, block 1,500 11.4 /
//   13.3, columns 12,000 (97K rows) 18.7 / 24.1. The crossover, about 30K rows on 2 units, falls
//   as units are added (the split saves a larger share): rows at most 16K x units / (units - 1),
//   without limit on one unit.
constexpr int kWholeStepMaxConstraintsWide = 1024;
constexpr double kWholeStepRowsPerUnitShare = 16384;

double wholeStepMaxRowsSerial(const btocl::OclRuntime& runtime) {
    const double units = double(runtime.computeUnits());
    if (units <= 1) return std::numeric_limits<double>::infinity();
    return kWholeStepRowsPerUnitShare * units / (units - 1);
}

// The path asked for, or BT_OPENCL_SOLVE_PATH's, or the device type's.
btOpenCLSolvePath resolveSolvePath(btOpenCLSolvePath asked, const btocl::OclRuntime& runtime) {
    if (asked != btOpenCLSolvePath::Auto) return asked;
    if (const char* env = std::getenv("BT_OPENCL_SOLVE_PATH"); env && *env) {
        const std::string value = env;
        if (value == "serial") return btOpenCLSolvePath::Serial;
        if (value == "wide") return btOpenCLSolvePath::Wide;
        if (value != "auto")
            throw btOpenCLSolverError("btOpenCLConstraintSolver: BT_OPENCL_SOLVE_PATH is '" + value +
                                      "'; it takes auto, serial or wide");
    }
    return runtime.isCpu() ? btOpenCLSolvePath::Serial : btOpenCLSolvePath::Wide;
}

// The sort and scan of the split. Serial path: our chunked kernels. Wide path: on a GPU the
// faster of the two there, measured (DevicePrimitives::fasterBackend); on a CPU device, which
// runs the wide path for the tests, Boost.Compute's, so that they cover what a GPU may get.
btocl::DevicePrimitives::Backend primitivesFor(btOpenCLSolvePath path, const btocl::OclRuntime& runtime) {
    using Backend = btocl::DevicePrimitives::Backend;
    if (path == btOpenCLSolvePath::Serial) return Backend::Chunked;
    return runtime.isCpu() ? Backend::BoostCompute : Backend::Auto;
}

}  // namespace

struct btOpenCLConstraintSolver::Impl {
    explicit Impl(const btOpenCLSolverConfig& c)
        : config(checked(c)),
          runtime(c.device),
          path(resolveSolvePath(c.solvePath, runtime)),
          // A device with memory of its own copies the step's arrays by DMA from pinned memory.
          pinned(runtime.hostUnifiedMemory() ? nullptr : std::make_unique<btocl::PinnedHostMemory>(runtime)),
          primitives(runtime, primitivesFor(path, runtime)),
          limits(btocl::deviceLimitsOf(runtime)),
          device(runtime, primitives, wide() ? c.workGroupSize : 1),
          autoWholeStepMaxRows(wholeStepMaxRowsSerial(runtime)),
          batcher(runtime, primitives),
          fallback(c.fallbackToBullet ? std::make_unique<btocl::SequentialFallback>() : nullptr) {
        gatherer.useHostMemory(pinned.get());
    }
    // Nothing queued may outlive the host memory it reads: the step's vectors die with this.
    ~Impl() { runtime.drain(); }

    static const btOpenCLSolverConfig& checked(const btOpenCLSolverConfig& c) {
        if (c.workGroupSize < 1 || c.workGroupSize > 1024 || (c.workGroupSize & (c.workGroupSize - 1)))
            throw btOpenCLSolverError("btOpenCLConstraintSolver: workGroupSize must be a power of two in 1..1024, not " +
                                      std::to_string(c.workGroupSize));
        if (c.batchIterations < 1)
            throw btOpenCLSolverError("btOpenCLConstraintSolver: batchIterations must be at least 1");
        if (!(c.cellSize >= 0) || !std::isfinite(c.cellSize))
            throw btOpenCLSolverError("btOpenCLConstraintSolver: cellSize must be 0 (automatic) or a positive length");
        if (c.wholeStepMaxRows < -1)
            throw btOpenCLSolverError("btOpenCLConstraintSolver: wholeStepMaxRows must be -1 (automatic), 0 (never) or a "
                                      "row count, not " + std::to_string(c.wholeStepMaxRows));
        return c;
    }

    btOpenCLSolverConfig config;
    btocl::OclRuntime runtime;
    btOpenCLSolvePath path;
    std::unique_ptr<btocl::PinnedHostMemory> pinned;  // null on a device on the host's memory
    btocl::DevicePrimitives primitives;
    btocl::DeviceLimits limits;
    btocl::DeviceSolver device;
    double autoWholeStepMaxRows;  // serial path, wholeStepMaxRows -1
    btocl::DeviceLayout batcher;
    btocl::StepGatherer gatherer;
    std::unique_ptr<btocl::SequentialFallback> fallback;  // with fallbackToBullet
    btOpenCLSolverStats stats;
    bool inStep = false;       // between prepareSolve and allSolved
    bool gathering = false;    // solveGroup has begun gathering this step
    double msGatherCalls = 0;  // time spent gathering inside this step's solveGroup calls

    // After an error: what is queued finished (it reads and writes the step's host vectors), the
    // bodies gathered so far released, the step and its bracket over.
    void abandonStep() {
        runtime.drain();
        if (gathering) gatherer.releaseBodies();
        gathering = false;
        inStep = false;
    }

    // Bullet's arrays of a solveGroup call, for Bullet's solver should the step fail.
    void keepForFallback(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds, int numManifolds,
                         btTypedConstraint** constraints, int numConstraints, const btContactSolverInfo& info,
                         btIDebugDraw* debugDrawer, btDispatcher* dispatcher) {
        if (!fallback) return;
        if (!gathering) fallback->clear();
        fallback->keep(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer,
                       dispatcher);
    }

    // The failed step solved by Bullet's solver instead (the world is as it was before the step).
    void solveWithBullet(const std::string& reason, const StageTimer& timer) {
        fallback->solve();
        btOpenCLSolverStats s;
        s.solvedByBullet = true;
        s.numFallbackSteps = stats.numFallbackSteps + 1;
        s.lastFallbackReason = reason;
        s.msTotal = msGatherCalls + timer.total();
        stats = s;
    }

    void gather(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds, int numManifolds,
                btTypedConstraint** joints, int numJoints, const btContactSolverInfo& info) {
        const auto t0 = Clock::now();
        if (!gathering) {
            gatherer.begin(info);
            gathering = true;
            msGatherCalls = 0;
        }
        gatherer.addBodies(bodies, numBodies);
        gatherer.addManifolds(manifolds, numManifolds);
        gatherer.addJoints(joints, numJoints);
        msGatherCalls += msSince(t0);
    }

    bool wide() const { return path == btOpenCLSolvePath::Wide; }
    // A split step on the serial path runs in one launch of a lane per compute unit (the per-set
    // launches, about a hundred a step, cost PoCL some 40 us each); the wide path keeps one
    // launch per set and pass until it is measured on a GPU.
    btocl::SolveLaunch splitLaunch() const {
        return wide() ? btocl::SolveLaunch::PerSet : btocl::SolveLaunch::Claimed;
    }
    bool solveWhole(const btocl::StepProblem& p) const {
        if (config.wholeStepMaxRows >= 0) return p.numRows() <= config.wholeStepMaxRows;
        return wide() ? int(p.constraints.size()) <= kWholeStepMaxConstraintsWide : double(p.numRows()) <= autoWholeStepMaxRows;
    }

    void run() {
        if (!gathering) return;
        StageTimer timer;
        btOpenCLSolverStats s;
        try {
            btocl::StepProblem& p = gatherer.finish();
            const btContactSolverInfo& info = gatherer.info();
            btocl::SolveSettings settings = btocl::SolveSettings::from(info, config.rotatePoints);
            settings.maxIterations = p.maxIterations(settings.numIterations);
            s.msGather = msGatherCalls + timer.lap();
            btocl::checkStepFitsDevice(btocl::countsOf(p), limits);  // before the first enqueue

            // The device's part: enqueued without waits but for the split's group counts, timed by
            // profiling events per phase, waited for once at the read-back.
            runtime.clearPhases();
            // Serial path: the step's commands enqueued whole before PoCL starts them (OclRuntime.h);
            // the wide path's sort and scan (Boost.Compute) may wait on the queue themselves.
            if (!wide()) runtime.holdQueue();
            runtime.beginPhase(btocl::DevicePhase::Upload);
            device.upload(p);

            // Global split and local batches on the device, from the constraints just uploaded.
            btocl::SplitParams params;
            params.cellSize = float(config.cellSize);
            params.batchIterations = config.batchIterations;
            params.workGroupSize = config.workGroupSize;
            btocl::LayoutOptions layout;
            layout.oneGroup = solveWhole(p);
            layout.localBatches = wide();
            btocl::DeviceLayoutView view;
            view.launch = layout.oneGroup ? btocl::SolveLaunch::WholeStep : splitLaunch();
            // The claimed launch reads the set starts on the device: no wait for the split.
            layout.setStartsOnDevice = view.launch == btocl::SolveLaunch::Claimed;
            batcher.build(device.constraints(), int(p.constraints.size()), p.splitBodies, params, layout);
            view.groups = &batcher.groups().buffer();
            view.solveOrder = &batcher.solveOrder().buffer();
            view.batchEnd = &batcher.batchEnd().buffer();
            view.setGroupStartOnDevice = &batcher.setGroupStartBuffer().buffer();
            if (!layout.setStartsOnDevice) view.setGroupStart = batcher.setGroupStart();
            if (config.validate) {
                runtime.endPhases();  // the validation's read-back is not a part of the step
                const std::string failure = btocl::validateBatchLayout(batcher.download(), p.constraints);
                if (!failure.empty()) {
                    s.validationFailures += 1;
                    s.lastValidationMessage = failure;
                }
            }
            runtime.beginPhase(btocl::DevicePhase::Setup);
            device.arrange(p, view);
            runtime.beginPhase(btocl::DevicePhase::Solve);
            device.iterate(p, view, settings);
            runtime.beginPhase(btocl::DevicePhase::Download);
            s.numIterationsRun = device.download(p, settings);  // the one wait
            runtime.endPhases();
            s.msDevice = timer.lap();
            fillDeviceStats(s, p, layout.oneGroup);

            btocl::writeBackStep(p, info);
            s.msWriteback = timer.lap();
            s.deviceBytes = double(runtime.bufferBytes());

            fillCounts(s, p);
        } catch (const btOpenCLSolverError& e) {
            abandonStep();  // leave the world as it was before the step's solve
            // Bad input is the caller's to fix; what failed on our side, Bullet's solver can do.
            if (!fallback || dynamic_cast<const btocl::InputError*>(&e)) throw;
            solveWithBullet(e.what(), timer);
            return;
        } catch (...) {
            abandonStep();
            throw;
        }
        gathering = false;
        s.msTotal = msGatherCalls + timer.total();
        s.numFallbackSteps = stats.numFallbackSteps;
        s.lastFallbackReason = stats.lastFallbackReason;
        stats = s;
    }

    // What the device did: its phases' times (profiling events) and the layout's counts.
    void fillDeviceStats(btOpenCLSolverStats& s, const btocl::StepProblem& p, bool wholeStep) const {
        s.msUpload = runtime.phaseMs(btocl::DevicePhase::Upload);
        s.msSplit = runtime.phaseMs(btocl::DevicePhase::Split);
        s.msBatch = runtime.phaseMs(btocl::DevicePhase::Batch);
        s.msSetup = runtime.phaseMs(btocl::DevicePhase::Setup);
        s.msSolve = runtime.phaseMs(btocl::DevicePhase::Solve);
        s.msDownload = runtime.phaseMs(btocl::DevicePhase::Download);
        const btocl::DeviceLayoutStats& batchStats = batcher.stats();
        s.numCellGroups = batchStats.numCellGroups;
        s.numGroups = batcher.numGroups();
        s.solvedWholeStep = wholeStep && !p.constraints.empty();
        s.numBatchesMax = batchStats.numBatchesMax;
        s.numBatchesMean = batchStats.numBatchesMean;
        s.numOverflowConstraints = batchStats.numOverflowConstraints;
    }

    static void fillCounts(btOpenCLSolverStats& s, const btocl::StepProblem& p) {
        s.numBodies = int(p.original.size()) - 1;
        s.numContactPoints = p.numContactPoints();
        s.numConstraintRows = p.numRows();
        s.numJointRows = p.numJointRows();
    }
};

btOpenCLConstraintSolver::btOpenCLConstraintSolver() : btOpenCLConstraintSolver(btOpenCLSolverConfig{}) {}
btOpenCLConstraintSolver::btOpenCLConstraintSolver(const btOpenCLSolverConfig& config)
    : m_impl(std::make_unique<Impl>(config)) {}
btOpenCLConstraintSolver::~btOpenCLConstraintSolver() = default;

void btOpenCLConstraintSolver::prepareSolve(int numBodies, int numManifolds) {
    // The gather's loops start once the world has built its islands: a step large enough to run
    // them in parallel wakes the host's threads now.
    if (size_t(numManifolds) + size_t(numBodies) * btocl::kRigidBodyWeight >= btocl::minParallelItems())
        btocl::prewakeHostThreads(std::chrono::milliseconds(5));
    m_impl->inStep = true;
    m_impl->gathering = false;
}

btScalar btOpenCLConstraintSolver::solveGroup(btCollisionObject** bodies, int numBodies,
                                              btPersistentManifold** manifolds, int numManifolds,
                                              btTypedConstraint** constraints, int numConstraints,
                                              const btContactSolverInfo& info, btIDebugDraw* debugDrawer,
                                              btDispatcher* dispatcher) {
    Impl& impl = *m_impl;
    try {
        btocl::checkSolveGroupArguments(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints);
        btocl::checkSolverInfo(info);
        impl.keepForFallback(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer,
                             dispatcher);
        impl.gather(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info);
    } catch (...) {
        impl.abandonStep();
        throw;
    }
    if (!impl.inStep) impl.run();  // called outside a prepareSolve/allSolved bracket: solve now
    return 0;
}

void btOpenCLConstraintSolver::allSolved(const btContactSolverInfo&, btIDebugDraw*) {
    m_impl->inStep = false;
    m_impl->run();
}

void btOpenCLConstraintSolver::reset() {}
btConstraintSolverType btOpenCLConstraintSolver::getSolverType() const { return BT_SEQUENTIAL_IMPULSE_SOLVER; }
const btOpenCLSolverStats& btOpenCLConstraintSolver::getLastStats() const { return m_impl->stats; }
std::string btOpenCLConstraintSolver::getDeviceName() const { return m_impl->runtime.deviceName(); }
const btOpenCLSolverConfig& btOpenCLConstraintSolver::getConfig() const { return m_impl->config; }
btOpenCLSolvePath btOpenCLConstraintSolver::getSolvePath() const { return m_impl->path; }

const char* btOpenCLConstraintSolver::getSortAndScanName() const { return m_impl->primitives.backendName(); }
