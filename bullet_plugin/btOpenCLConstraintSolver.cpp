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
#include "StepPolicy.h"
#include "BulletConversions.h"
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

}  // namespace

struct btOpenCLConstraintSolver::Impl {
    explicit Impl(const btOpenCLSolverConfig& c)
        : config(checked(c)),
          runtime(c.device),
          plan(btocl::planSolver(config, runtime)),
          // A device with memory of its own copies the step's arrays by DMA from pinned memory.
          pinned(runtime.hostUnifiedMemory() ? nullptr : std::make_unique<btocl::PinnedHostMemory>(runtime)),
          primitives(runtime, plan.sortAndScan),
          limits(btocl::deviceLimitsOf(runtime)),
          solve(runtime, primitives),
          layout(runtime, primitives),
          fallback(c.fallbackToBullet ? std::make_unique<btocl::SequentialFallback>() : nullptr) {
        gatherer.useHostMemory(pinned.get());
    }
    // Nothing queued may outlive the host memory it reads: the step's vectors die with this.
    ~Impl() { runtime.drain(); }

    static const btOpenCLSolverConfig& checked(const btOpenCLSolverConfig& c) {
        if (c.workGroupSize < 1 || c.workGroupSize > 1024 || (c.workGroupSize & (c.workGroupSize - 1)))
            throw btOpenCLSolverError("btOpenCLConstraintSolver: workGroupSize must be a power of two in 1..1024, not " +
                                      std::to_string(c.workGroupSize));
        btocl::checkSplitParams(splitParamsOf(c));
        if (c.wholeStepMaxRows < -1)
            throw btOpenCLSolverError("btOpenCLConstraintSolver: wholeStepMaxRows must be -1 (automatic), 0 (never) or a "
                                      "row count, not " + std::to_string(c.wholeStepMaxRows));
        return c;
    }

    static btocl::SplitParams splitParamsOf(const btOpenCLSolverConfig& c) {
        btocl::SplitParams params;
        params.cellSize = float(c.cellSize);
        params.batchIterations = c.batchIterations;
        params.workGroupSize = c.workGroupSize;
        return params;
    }

    // Members in the order they are made: each reads those above it.
    btOpenCLSolverConfig config;
    btocl::OclRuntime runtime;
    btocl::SolverPlan plan;
    std::unique_ptr<btocl::PinnedHostMemory> pinned;  // null on a device on the host's memory
    btocl::DevicePrimitives primitives;
    btocl::DeviceLimits limits;
    btocl::DeviceSolver solve;
    btocl::DeviceLayout layout;
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

    void run() {
        if (!gathering) return;
        StageTimer timer;
        btOpenCLSolverStats s;
        try {
            btocl::StepProblem& p = gatherer.finish();
            const btContactSolverInfo& info = gatherer.info();
            const btocl::SolveSettings settings = btocl::solveSettingsOf(info, config.rotatePoints);
            const btocl::StepPlan step = btocl::planStep(plan, p, settings);
            s.msGather = msGatherCalls + timer.lap();
            btocl::checkStepFitsDevice(btocl::countsOf(p), limits);  // before the first enqueue

            // The device's part: enqueued without waits but for the split's group counts, timed by
            // profiling events per phase, waited for once at the read-back.
            runtime.clearPhases();
            // Serial path: the step's commands enqueued whole before PoCL starts them (OclRuntime.h);
            // the wide path's sort and scan (Boost.Compute) may wait on the queue themselves.
            if (!plan.wide()) runtime.holdQueue();
            runtime.beginPhase(btocl::DevicePhase::Upload);
            solve.upload(p);
            // The global split and local batches on the device, from the constraints just uploaded.
            layout.build(solve.constraints(), int(p.constraints.size()), p.splitBodies, splitParamsOf(config), step);
            btocl::DeviceLayoutView view;
            view.groups = &layout.groups().buffer();
            view.solveOrder = &layout.solveOrder().buffer();
            view.batchEnd = &layout.batchEnd().buffer();
            view.setGroupStartOnDevice = &layout.setGroupStartBuffer().buffer();
            if (!step.setStartsOnDevice()) view.setGroupStart = layout.setGroupStart();
            if (config.validate) {
                runtime.endPhases();  // the validation's read-back is not a part of the step
                const std::string failure = btocl::validateBatchLayout(layout.download(), p.constraints);
                if (!failure.empty()) {
                    s.validationFailures += 1;
                    s.lastValidationMessage = failure;
                }
            }
            runtime.beginPhase(btocl::DevicePhase::Setup);
            solve.arrange(p, view);
            runtime.beginPhase(btocl::DevicePhase::Solve);
            solve.iterate(p, step, view, settings);
            runtime.beginPhase(btocl::DevicePhase::Download);
            s.numIterationsRun = solve.download(p, step, settings);  // the one wait
            runtime.endPhases();
            s.msDevice = timer.lap();
            fillDeviceStats(s, p, step.oneGroup());

            btocl::writeBackStep(p, gatherer.bullet(), info);
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
        const btocl::DeviceLayoutStats& batchStats = layout.stats();
        s.numCellGroups = batchStats.numCellGroups;
        s.numGroups = layout.numGroups();
        s.solvedWholeStep = wholeStep && !p.constraints.empty();
        s.numBatchesMax = batchStats.numBatchesMax;
        s.numBatchesMean = batchStats.numBatchesMean;
        s.numOverflowConstraints = batchStats.numOverflowConstraints;
    }

    static void fillCounts(btOpenCLSolverStats& s, const btocl::StepProblem& p) {
        s.numBodies = p.numBodies();
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
btOpenCLSolvePath btOpenCLConstraintSolver::getSolvePath() const { return m_impl->plan.path; }

const char* btOpenCLConstraintSolver::getSortAndScanName() const { return m_impl->primitives.backendName(); }
