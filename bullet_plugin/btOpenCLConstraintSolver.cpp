// The adapter: Bullet's calls to btConstraintSolver mapped to a step (prepareSolve opens it,
// solveGroup gathers, allSolved runs it through StepPipeline), the config checked, a failed step
// handed to Bullet's solver where the config asks.
#include "btOpenCLConstraintSolver.h"

#include "BulletConversions.h"
#include "BulletFallback.h"
#include "BulletGather.h"
#include "HostParallel.h"
#include "InputChecks.h"
#include "StepPipeline.h"

#include <chrono>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

const btOpenCLSolverConfig& checked(const btOpenCLSolverConfig& c) {
    if (c.workGroupSize < 1 || c.workGroupSize > 1024 || (c.workGroupSize & (c.workGroupSize - 1)))
        throw btOpenCLSolverError("btOpenCLConstraintSolver: workGroupSize must be a power of two in 1..1024, not " +
                                  std::to_string(c.workGroupSize));
    btocl::checkSplitParams(btocl::splitParamsOf(c));
    if (c.wholeStepMaxRows < -1)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: wholeStepMaxRows must be -1 (automatic), 0 (never) or a "
                                  "row count, not " + std::to_string(c.wholeStepMaxRows));
    if (c.hostStepMaxRows < -1)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: hostStepMaxRows must be -1 (automatic), 0 (never) or a "
                                  "row count, not " + std::to_string(c.hostStepMaxRows));
    if (c.splitStepsOnHost < -1 || c.splitStepsOnHost > 1)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: splitStepsOnHost must be -1 (automatic), 0 (never) or 1 "
                                  "(always), not " + std::to_string(c.splitStepsOnHost));
    return c;
}

}  // namespace

struct btOpenCLConstraintSolver::Impl {
    explicit Impl(const btOpenCLSolverConfig& c)
        : config(checked(c)),
          pipeline(config),
          fallback(c.fallbackToBullet ? std::make_unique<btocl::SequentialFallback>() : nullptr) {
        gatherer.useHostMemory(pipeline.hostMemory());
        if (config.warmUpAtConstruction) pipeline.warmUp();
    }
    // Nothing queued may outlive the host memory it reads: the gatherer's arrays die first.
    ~Impl() { pipeline.runtime().drain(); }

    btOpenCLSolverConfig config;
    btocl::StepPipeline pipeline;
    btocl::StepGatherer gatherer;  // after the pipeline: its arrays live in the pipeline's host memory
    std::unique_ptr<btocl::SequentialFallback> fallback;  // with fallbackToBullet
    btOpenCLSolverStats stats;
    bool inStep = false;       // between prepareSolve and allSolved
    bool gathering = false;    // solveGroup has begun gathering this step
    double msGatherCalls = 0;  // time spent gathering inside this step's solveGroup calls

    // After an error: what is queued finished (it reads and writes the step's host arrays), the
    // bodies gathered so far released, the step and its bracket over.
    void abandonStep() {
        pipeline.runtime().drain();
        btocl::restHostThreads();  // a step's pre-wake ends with it
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
    void solveWithBullet(const std::string& reason, Clock::time_point t0) {
        fallback->solve();
        btOpenCLSolverStats s;
        s.solvedByBullet = true;
        s.numFallbackSteps = stats.numFallbackSteps + 1;
        s.lastFallbackReason = reason;
        s.msTotal = msGatherCalls + msSince(t0);
        stats = s;
    }

    // One solveGroup call's share of the step: its objects named, their records read at run().
    void collect(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds, int numManifolds,
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

    // The step's records gathered (every call's at once), then solved and written back.
    void run() {
        if (!gathering) return;
        const auto t0 = Clock::now();
        btOpenCLSolverStats s;
        try {
            btocl::StepProblem& p = gatherer.finish();
            s.msGather = msGatherCalls + msSince(t0);
            pipeline.run(p, gatherer.bullet(), gatherer.info(), s);
        } catch (const btOpenCLSolverError& e) {
            abandonStep();  // leave the world as it was before the step's solve
            // Bad input is the caller's to fix; what failed on our side, Bullet's solver can do.
            if (!fallback || dynamic_cast<const btocl::InputError*>(&e)) throw;
            solveWithBullet(e.what(), t0);
            return;
        } catch (...) {
            abandonStep();
            throw;
        }
        gathering = false;
        s.msTotal = msGatherCalls + msSince(t0);
        s.numFallbackSteps = stats.numFallbackSteps;
        s.lastFallbackReason = stats.lastFallbackReason;
        stats = s;
    }
};

btOpenCLConstraintSolver::btOpenCLConstraintSolver() : btOpenCLConstraintSolver(btOpenCLSolverConfig{}) {}
btOpenCLConstraintSolver::btOpenCLConstraintSolver(const btOpenCLSolverConfig& config)
    : m_impl(std::make_unique<Impl>(config)) {}
btOpenCLConstraintSolver::~btOpenCLConstraintSolver() = default;

void btOpenCLConstraintSolver::prepareSolve(int numBodies, int numManifolds) {
    // A prepareSolve inside a step: the groups gathered so far are solved first, as Bullet's
    // solver solved each at its solveGroup call (none is dropped).
    m_impl->run();
    // The gather's loops start once the world has built its islands: a step large enough to run
    // them in parallel wakes the host's threads now.
    if (size_t(numManifolds) * btocl::kManifoldWeight + size_t(numBodies) * btocl::kRigidBodyWeight >=
        btocl::minParallelItems())
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
        // Groups gathered under other settings are solved with theirs first: Bullet's solver
        // solves each call with its own.
        if (impl.gathering && !btocl::sameStepSettings(impl.gatherer.info(), info)) impl.run();
        impl.keepForFallback(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info, debugDrawer,
                             dispatcher);
        impl.collect(bodies, numBodies, manifolds, numManifolds, constraints, numConstraints, info);
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

void btOpenCLConstraintSolver::warmUp() { m_impl->pipeline.warmUp(); }

void btOpenCLConstraintSolver::reset() { m_impl->pipeline.restartOrders(); }
btConstraintSolverType btOpenCLConstraintSolver::getSolverType() const { return BT_SEQUENTIAL_IMPULSE_SOLVER; }
const btOpenCLSolverStats& btOpenCLConstraintSolver::getLastStats() const { return m_impl->stats; }
std::string btOpenCLConstraintSolver::getDeviceName() const { return m_impl->pipeline.runtime().deviceName(); }
const btOpenCLSolverConfig& btOpenCLConstraintSolver::getConfig() const { return m_impl->config; }
btOpenCLSolvePath btOpenCLConstraintSolver::getSolvePath() const { return m_impl->pipeline.plan().path; }

const char* btOpenCLConstraintSolver::getSortAndScanName() const { return m_impl->pipeline.sortAndScanName(); }
