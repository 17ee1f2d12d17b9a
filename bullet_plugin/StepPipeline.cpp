#include "StepPipeline.h"

#include "BulletConversions.h"
#include "BulletGather.h"
#include "HostParallel.h"
#include "HostRowSetup.h"
#include "LaneLayout.h"
#include "LayoutValidator.h"
#include "StepWriteBack.h"

#include <chrono>

namespace btocl {
namespace {

// How long the host's threads wait awake for a host split step's row loop: the split before it
// takes some tens of microseconds; a thread still waiting after this sleeps again.
constexpr std::chrono::microseconds kHostSplitPrewake{500};
// How long at most the host's threads wait awake for the host's loops of a device step (the
// split, the lanes' layout and rows), or through a host step in lanes (whose passes run on them
// too): a dense block's take some milliseconds between them.
constexpr std::chrono::milliseconds kHostWorkPrewake{50};
// A lane layout whose row places are filled less than this is solved one lane a group instead:
// pile 1,000's (0.43) was no faster in lanes, block's, columns' and the 3D pyramid's (0.68 to
// 0.76) were (docs/performance.md, "Lanes set up by the host").
constexpr double kMinLaneRowFill = 0.6;
// After a layout filled less, the steps that follow go without one for this many steps (making it
// costs a pile's step a few per cent): a scene's manifolds change slowly.
constexpr int kStepsWithoutLanes = 32;

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A layout's broken invariant (config.validate), counted in the stats: "" is none.
void noteInvariants(btOpenCLSolverStats& s, const std::string& failure) {
    if (failure.empty()) return;
    s.validationFailures += 1;
    s.lastValidationMessage = failure;
}

// The plan of a solver on `runtime`, whose step program is then built for its lanes.
SolverPlan planAndSetLanes(const btOpenCLSolverConfig& config, OclRuntime& runtime) {
    const SolverPlan plan = planSolver(config, runtime);
    runtime.setStepProgramLanes(plan.simdLanes);
    return plan;
}

}  // namespace

SplitParams splitParamsOf(const btOpenCLSolverConfig& config) {
    SplitParams params;
    params.cellSize = float(config.cellSize);
    params.batchIterations = config.batchIterations;
    params.workGroupSize = config.workGroupSize;
    return params;
}

StepPipeline::StepPipeline(const btOpenCLSolverConfig& config)
    : m_config(config),
      m_runtime(config.device, config.pinPoclThreads, config.kernelBinaries, config.kernelBinaryDir),
      m_plan(planAndSetLanes(config, m_runtime)),
      // A device with memory of its own copies the step's arrays by DMA from pinned memory.
      m_pinned(m_runtime.hostUnifiedMemory() ? nullptr : std::make_unique<PinnedHostMemory>(m_runtime)),
      m_primitives(m_runtime, m_plan.sortAndScan, false),  // warmed up by warmUp()
      m_limits(deviceLimitsOf(m_runtime)),
      m_solve(m_runtime, m_primitives),
      m_layout(m_runtime, m_primitives) {}

void StepPipeline::warmUp(KernelWarmUp* timing) {
    if (m_warmedUp) return;
    KernelWarmUp untimed(m_runtime);
    KernelWarmUp& warm = timing ? *timing : untimed;
    m_primitives.warmUp();
    m_solve.warmUp(warm, m_plan.lanes);
    m_layout.warmUp(warm, m_plan.lanes);
    warm.finish();
    m_warmedUp = true;
}

void StepPipeline::run(StepProblem& p, const BulletStep& bullet, const btContactSolverInfo& info,
                       btOpenCLSolverStats& s) {
    const auto t0 = std::chrono::steady_clock::now();
    const SolveSettings settings = solveSettingsOf(info, m_config.rotatePoints, m_orderSeed++);
    const StepPlan step = planStep(m_plan, p, settings, &m_splitTimes);
    if (!step.oneGroup()) addSplitGeometry(p, bullet);
    if (step.onHost())
        solveOnHost(p, bullet, step, settings, s);
    else
        solveOnDevice(p, step, settings, s);
    s.msDevice = msSince(t0);
    if (step.timed()) m_splitTimes.record(step.onHost(), s.msDevice, p.numRows());

    const auto t1 = std::chrono::steady_clock::now();
    writeBackStep(p, bullet, info);
    s.msWriteback = msSince(t1);
    s.deviceBytes = double(m_runtime.bufferBytes());
    s.numBodies = p.numBodies();
    s.numContactPoints = p.numContactPoints();
    s.numConstraintRows = p.numRows();
    s.numJointRows = p.numJointRows();
    restHostThreads();  // the step's loops are over
}

// Every row set up on the calling thread (the contact rows from the points, as the setup kernel
// does), then the passes in gather order, or in the order of the split made here: no device
// command at all.
void StepPipeline::solveOnHost(StepProblem& p, const BulletStep& bullet, const StepPlan& step,
                               const SolveSettings& settings, btOpenCLSolverStats& s) {
    const BatchLayout* layout = nullptr;
    const bool split = step.mode() == StepMode::HostSplit;
    if (split) {
        // The rows' loop that follows the split runs on the host's threads: they wake meanwhile.
        prewakeHostThreads(kHostSplitPrewake);
        const auto t0 = std::chrono::steady_clock::now();
        splitHostInto(p.constraints.data(), p.constraints.size(), p.splitBodies, splitParamsOf(m_config), true,
                      m_hostSplit);
        s.msSplit = msSince(t0);
        layout = &m_hostSplit;
        if (m_config.validate) noteInvariants(s, validateBatchLayout(m_hostSplit, p.constraints));
    }
    const auto t0 = std::chrono::steady_clock::now();
    // Contact rows alone, in passes that pair: eight groups at a time in the vector unit's lanes.
    const bool lanes = split && HostLaneSolve::available() && stepFitsHostLanes(p, settings, step.passes()) &&
                       (p.numJointRows() == 0 || HostLaneSolve::contactsLead(m_hostSplit, p.constraints));
    // Rows the gather left to a device go straight into the host solve's arrays.
    const bool setHere = p.rowsOnDevice;
    // Its passes shared out to the host's threads (a share of each set a thread), or on this one
    // alone, as the recent steps' times say: with another process busy on a core, a share waits
    // on that core's thread. The same bits either way.
    // Both ways are timed only where split steps stay on the host (always, or as their own times
    // chose): a step the device's way is trying here takes the way preferred so far, shared out
    // at first, so that the host is tried at its pace. A step past the host split's own bound
    // (lanes split on the host at any size) is not tried on one thread: a dense block's step
    // took twice as long there.
    const bool oneThreadTried = p.constraints.size() <= m_plan.hostSplitMaxConstraints;
    const bool timesShares = oneThreadTried && (!step.timed() || m_splitTimes.prefersSecond());
    const bool shared = lanes && (!oneThreadTried || (timesShares ? m_laneShareTimes.nextIsSecond()
                                                                   : m_laneShareTimes.prefersSecond()));
    const int shares =
        shared ? std::min(threadsForLoop(p.constraints.size(), kContactConstraintWeight), HostLaneSolve::kMaxShares) : 1;
    if (shares > 1) prewakeHostThreads(kHostWorkPrewake);  // the threads wait awake until the step ends
    if (lanes)
        m_hostLanes.setUp(p, m_hostSplit, settings.flags, shares);
    else if (setHere)
        setupRowsOnHost(p, bullet, &m_hostSolve, split);
    s.msSetup = msSince(t0);
    if (lanes && m_config.validate)
        noteInvariants(s, validateLaneLayout(m_hostLanes.layout(), m_hostLanes.laneSplit(), p.constraints));
    const auto t1 = std::chrono::steady_clock::now();
    s.numIterationsRun = lanes     ? m_hostLanes.solve(p, step.passes())
                         : setHere ? m_hostSolve.solveRowsSet(p, step.passes(), settings, layout)
                                   : m_hostSolve.solve(p, step.passes(), settings, layout);
    s.msSolve = msSince(t1);
    if (lanes && timesShares) m_laneShareTimes.record(shared, s.msSetup + s.msSolve, p.numRows());
    s.solvedOnHost = true;
    s.solvedOnHostSplit = layout != nullptr;
    s.numCellGroups = layout ? layout->setGroupStart[BTOCL_NUM_SETS] : 0;
    s.numGroups = layout ? layout->setGroupStart[BTOCL_NUM_SETS + 1] : p.constraints.empty() ? 0 : 1;
    s.numOverflowConstraints = layout ? layout->numOverflowConstraints : 0;
    s.numBatchesMax = s.numGroups > 0 ? 1 : 0;  // one run a group, as the claimed launch walks it
    s.numBatchesMean = s.numBatchesMax;
    if (lanes) {
        s.simdLanes = m_hostLanes.layout().lanes;
        s.laneFill = m_hostLanes.layout().laneFill();
        s.laneRowFill = m_hostLanes.layout().rowFill();
    }
}

void StepPipeline::solveOnDevice(StepProblem& p, const StepPlan& step, const SolveSettings& settings,
                                 btOpenCLSolverStats& s) {
    checkStepFitsDevice(countsOf(p), m_limits);

    m_runtime.clearPhases();
    // Serial path: the step's commands enqueued whole before PoCL starts them (OclRuntime.h);
    // the wide path's sort and scan (Boost.Compute) may wait on the queue themselves.
    if (!m_plan.wide()) m_runtime.holdQueue();
    m_runtime.beginPhase(DevicePhase::Upload);
    m_solve.upload(p);

    // The global split on the host where it costs less than the device's launches, else with the
    // local batches on the device, from the constraints just uploaded.
    double msHostSplit = 0;
    const bool hostSplit = splitsOnHost(m_plan, p, step);
    // The host's loops before the device starts (the split, the lanes' layout and rows) have the
    // cores to themselves while the queue is held: the pool waits awake for them, and rests once
    // the step is handed over (iterateAndDownload).
    if (hostSplit && !m_plan.wide())
        prewakeHostThreads(kHostWorkPrewake);
    else
        restHostThreads();  // the device's threads take the cores now
    if (hostSplit) {
        const auto t0 = std::chrono::steady_clock::now();
        splitHostInto(p.constraints.data(), p.constraints.size(), p.splitBodies, splitParamsOf(m_config), true,
                      m_hostSplit);
        msHostSplit = msSince(t0);
    }
    if (step.inLanes()) {
        // Lanes mostly empty (manifolds of unlike point counts side by side) solve no faster than
        // one lane: the claimed launch over the same split, to the same bits.
        const StepPlan oneLane = StepPlan::claimed(step.passes());
        if (m_stepsWithoutLanes > 0) {
            --m_stepsWithoutLanes;
            return solveSplit(p, oneLane, settings, s, true, msHostSplit, 0);
        }
        const auto t0 = std::chrono::steady_clock::now();
        LaneLayout& laneLayout = m_hostLanes.sharedLayout();
        layOutLanes(m_hostSplit, p.constraints.data(), p.regions, step.simdLanes(), p.frictionRowsPerPoint(),
                    int(m_runtime.computeUnits()), laneLayout);
        const double msLayout = msSince(t0);
        if (!m_plan.lanesWhereTheyFill || laneLayout.rowFill() >= kMinLaneRowFill)
            return solveInLanes(p, step, settings, s, msHostSplit, msLayout);
        m_stepsWithoutLanes = kStepsWithoutLanes;
        return solveSplit(p, oneLane, settings, s, true, msHostSplit, msLayout);
    }
    solveSplit(p, step, settings, s, hostSplit, msHostSplit, 0);
}

// A split step on the device once its constraints are uploaded (and split, with hostSplit):
// the layout, the rows placed and set up, the passes.
void StepPipeline::solveSplit(StepProblem& p, const StepPlan& step, const SolveSettings& settings,
                              btOpenCLSolverStats& s, bool hostSplit, double msHostSplit, double msLaneLayout) {
    double msHostArrange = 0;
    if (hostSplit) {
        m_layout.upload(m_hostSplit, step);
    } else {
        m_layout.build(m_solve.constraints(), int(p.constraints.size()), p.splitBodies, splitParamsOf(m_config), step);
    }
    DeviceLayoutView view;
    view.groups = &m_layout.groups().buffer();
    view.solveOrder = &m_layout.solveOrder().buffer();
    view.batchEnd = &m_layout.batchEnd().buffer();
    view.setGroupStartOnDevice = &m_layout.setGroupStartBuffer().buffer();
    if (!step.setStartsOnDevice()) view.setGroupStart = m_layout.setGroupStart();
    if (m_config.validate) {
        m_runtime.endPhases();  // the validation's read-back is not a part of the step
        noteInvariants(s, validateBatchLayout(m_layout.download(), p.constraints));
    }

    m_runtime.beginPhase(DevicePhase::Setup);
    if (hostSplit) {  // its arrangement too: a few loops on the host against a dozen launches
        const auto t0 = std::chrono::steady_clock::now();
        arrangeOnHost(m_hostSplit.solveOrder.data(), p.constraints.data(), int(p.constraints.size()), p.regions,
                      m_hostArrangement);
        msHostArrange = msSince(t0);
    }
    m_solve.arrange(p, view, hostSplit ? &m_hostArrangement : nullptr);
    iterateAndDownload(p, step, view, settings, s);
    s.msSplit += msHostSplit;
    s.msSetup += msHostArrange + msLaneLayout;
}

// The passes and the step's one wait, once the rows are set up; the device's phases to the stats.
void StepPipeline::iterateAndDownload(StepProblem& p, const StepPlan& step, const DeviceLayoutView& view,
                                      const SolveSettings& settings, btOpenCLSolverStats& s) {
    restHostThreads();  // the device's threads take the cores now
    m_runtime.beginPhase(DevicePhase::Solve);
    m_solve.iterate(p, step, view, settings);
    m_runtime.beginPhase(DevicePhase::Download);
    s.numIterationsRun = m_solve.download(p, step, settings);  // the one wait
    m_runtime.endPhases();
    fillDeviceStats(s, p, step);
}

// A step in lanes, split on the host (msHostSplit) and laid out in lanes (msLayout): the rows set
// up in the layout's blocks, the passes in one launch.
void StepPipeline::solveInLanes(StepProblem& p, const StepPlan& step, const SolveSettings& settings,
                                btOpenCLSolverStats& s, double msHostSplit, double msLayout) {
    const LaneLayout& laneLayout = m_hostLanes.sharedLayout();
    LaneRows& laneRows = m_hostLanes.sharedRows();
    if (m_config.validate) {
        std::string failure = validateBatchLayout(m_hostSplit, p.constraints);
        if (failure.empty()) failure = validateLaneLayout(laneLayout, m_hostSplit, p.constraints);
        noteInvariants(s, failure);
    }
    // On a CPU device in the host's memory, eight lanes' rows are set up by the host's vector
    // code on both cores, in place (the setup kernel runs a slot a work-item, scalar).
    const bool rowsOnHost = hostSetsUpLaneRows(laneLayout.lanes, m_runtime);
    const auto t1 = std::chrono::steady_clock::now();
    if (rowsOnHost) setUpLaneRows(p, laneLayout, laneRows);
    setUpBodyPerUnit(p, settings.flags, laneRows.perUnit);
    const double msRowsOnHost = msSince(t1);
    m_runtime.beginPhase(DevicePhase::Setup);
    m_solve.arrangeInLanes(p, laneLayout, laneRows.perUnit, rowsOnHost ? &laneRows : nullptr);
    iterateAndDownload(p, step, DeviceLayoutView{}, settings, s);
    s.msSplit += msHostSplit;
    s.msSetup += msLayout + msRowsOnHost;
    s.numCellGroups = m_hostSplit.setGroupStart[BTOCL_NUM_SETS];
    s.numGroups = m_hostSplit.setGroupStart[BTOCL_NUM_SETS + 1];
    s.numOverflowConstraints = m_hostSplit.numOverflowConstraints;
    s.numBatchesMax = s.numGroups > 0 ? 1 : 0;
    s.numBatchesMean = s.numBatchesMax;
    s.simdLanes = laneLayout.lanes;
    s.laneFill = laneLayout.laneFill();
    s.laneRowFill = laneLayout.rowFill();
}

// What the device did: its phases' times (profiling events), the layout's counts, the step's.
void StepPipeline::fillDeviceStats(btOpenCLSolverStats& s, const StepProblem& p, const StepPlan& step) const {
    s.msUpload = m_runtime.phaseMs(DevicePhase::Upload);
    s.msSplit = m_runtime.phaseMs(DevicePhase::Split);
    s.msBatch = m_runtime.phaseMs(DevicePhase::Batch);
    s.msSetup = m_runtime.phaseMs(DevicePhase::Setup);
    s.msSolve = m_runtime.phaseMs(DevicePhase::Solve);
    s.msDownload = m_runtime.phaseMs(DevicePhase::Download);
    const DeviceLayoutStats& layoutStats = m_layout.stats();
    s.numCellGroups = layoutStats.numCellGroups;
    s.numGroups = m_layout.numGroups();
    s.solvedWholeStep = step.oneGroup() && !p.constraints.empty();
    s.numBatchesMax = layoutStats.numBatchesMax;
    s.numBatchesMean = layoutStats.numBatchesMean;
    s.numOverflowConstraints = layoutStats.numOverflowConstraints;
}

}  // namespace btocl
