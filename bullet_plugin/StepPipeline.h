// A gathered step through every stage after the gather, written once, in order:
//   plan       how the step runs (planStep: on the host, whole or split there, or on the device
//              whole or split, and its passes); a step on the host sets its rows up and runs its
//              passes on the calling thread (HostRowSetup.h, HostSolve.h), then goes to the
//              write-back
//   fit        every buffer checked against the device's limits, before anything is enqueued
//   upload     bodies, constraints, contact points and host rows to the device
//   layout     the global split and the local batches (DeviceLayout), or one group
//   arrange    constraints and rows in solve order, contact rows set up (DeviceSolver::arrange)
//   iterate    the plan's passes, launched as its mode says, no host round trip between them
//   download   velocity changes and impulses back: the step's one wait
//   write-back to Bullet's bodies, points and joints (the only stage that changes the world)
// The device's stages are enqueued without waits and timed by profiling events per phase.
#pragma once

#include "BulletStep.h"
#include "DeviceFit.h"
#include "DeviceLayout.h"
#include "DevicePrimitives.h"
#include "DeviceSolver.h"
#include "HostLaneSolve.h"
#include "HostSolve.h"
#include "HostSplit.h"
#include "LaneLayout.h"
#include "KernelWarmUp.h"
#include "OclRuntime.h"
#include "PinnedHostMemory.h"
#include "StepPolicy.h"
#include "StepProblem.h"
#include "btOpenCLConstraintSolver.h"

#include <memory>

namespace btocl {

class StepPipeline {
public:
    // Chooses the device and builds every program. Throws btOpenCLSolverError.
    explicit StepPipeline(const btOpenCLSolverConfig& config);
    // Nothing queued may outlive the host memory it reads (the pinned memory).
    ~StepPipeline() { m_runtime.drain(); }

    // Compiles every kernel that this solver's steps can launch, by launching each on no work in
    // the shapes the steps use (KernelWarmUp.h), and runs the sort and scan once; once per
    // pipeline (later calls return at once). Changes nothing that a step reads. With `timing`,
    // each kernel is launched and timed on its own and the times are left there. Throws
    // btOpenCLSolverError.
    void warmUp(KernelWarmUp* timing = nullptr);
    bool warmedUp() const { return m_warmedUp; }

    // Solves a gathered step and writes it back to Bullet; fills the stats' phases, layout counts
    // and host times of the solve and write-back stages. Throws btOpenCLSolverError
    // before the write-back, with nothing in the world changed.
    void run(StepProblem& p, const BulletStep& bullet, const btContactSolverInfo& info, btOpenCLSolverStats& stats);

    // Host storage for the step's arrays: pinned memory on a device with memory of its own, else
    // null (the heap; a device on the host's memory reads them in place).
    HostMemorySource* hostMemory() { return m_pinned.get(); }
    const OclRuntime& runtime() const { return m_runtime; }
    const SolverPlan& plan() const { return m_plan; }
    const char* sortAndScanName() const { return m_primitives.backendName(); }
    // The shuffled orders of SOLVER_RANDMIZE_ORDER start again from the first step's, as
    // btSequentialImpulseConstraintSolver::reset() restarts its random sequence.
    void restartOrders() { m_orderSeed = 0; }

private:
    void solveOnHost(StepProblem& p, const BulletStep& bullet, const StepPlan& step, const SolveSettings& settings,
                     btOpenCLSolverStats& s);
    void solveOnDevice(StepProblem& p, const StepPlan& step, const SolveSettings& settings, btOpenCLSolverStats& s);
    void solveSplit(StepProblem& p, const StepPlan& step, const SolveSettings& settings, btOpenCLSolverStats& s,
                    bool hostSplit, double msHostSplit, double msLaneLayout);
    void solveInLanes(StepProblem& p, const StepPlan& step, const SolveSettings& settings, btOpenCLSolverStats& s,
                      double msHostSplit, double msLayout);
    void iterateAndDownload(StepProblem& p, const StepPlan& step, const DeviceLayoutView& view,
                            const SolveSettings& settings, btOpenCLSolverStats& s);
    void fillDeviceStats(btOpenCLSolverStats& s, const StepProblem& p, const StepPlan& step) const;

    // Members in the order they are made: each reads those above it.
    const btOpenCLSolverConfig m_config;
    OclRuntime m_runtime;
    const SolverPlan m_plan;
    std::unique_ptr<PinnedHostMemory> m_pinned;  // null on a device on the host's memory
    DevicePrimitives m_primitives;
    const DeviceLimits m_limits;
    DeviceSolver m_solve;
    DeviceLayout m_layout;
    BatchLayout m_hostSplit;  // the split made on the host (splitsOnHost), read by the queue
    HostArrangement m_hostArrangement;  // and its arrangement, likewise
    HostSolve m_hostSolve;
    HostLaneSolve m_hostLanes;  // its lane layout and rows are a device step's in lanes too
    SplitStepTimes m_splitTimes;  // where split steps ran faster of late (SplitStepsOnHost::Timed)
    StepWayTimes m_laneShareTimes{true};  // whether host steps in lanes ran faster of late shared out
    int m_stepsWithoutLanes = 0;  // steps left to solve one lane a group after a layout filled too little
    bool m_warmedUp = false;
    unsigned m_orderSeed = 0;  // steps run since the solver was made or reset
};

// The global split's settings of a config.
SplitParams splitParamsOf(const btOpenCLSolverConfig& config);

}  // namespace btocl
