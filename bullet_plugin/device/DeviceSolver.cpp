#include "DeviceSolver.h"

#include "row_solve.h"

namespace btocl {
namespace {

constexpr size_t kLanes = 64;  // local size of the launches over constraints, rows and points
constexpr size_t kSlotsPerGroup = 8;  // local size of setupLaneSlots

}  // namespace

DeviceSolver::DeviceSolver(const OclRuntime& runtime, DevicePrimitives& primitives)
    : m_rt(runtime), m_primitives(primitives) {
    // On a CPU the program asks for software prefetch of scattered records (btocl_shared.h:
    // BTOCL_PREFETCHES): bodies in the solve and setup, constraints and impulses in the arrangement.
    const cl::Program& program = m_rt.stepProgram();
    m_passKernels[BTOCL_PASS_WARMSTART] = m_rt.makeKernel(program, "applyWarmStart");
    m_passKernels[BTOCL_PASS_PUSH] = m_rt.makeKernel(program, "solvePushRows");
    m_passKernels[BTOCL_PASS_NORMAL] = m_rt.makeKernel(program, "solveNormalRows");
    m_passKernels[BTOCL_PASS_FRICTION] = m_rt.makeKernel(program, "solveFrictionRows");
    m_endIteration = m_rt.makeKernel(program, "endIteration");
    m_wholeStep = m_rt.makeKernel(program, "solveWholeStep");
    m_claimed = m_rt.makeKernel(program, "solveStepClaimed");
    m_setupRows = m_rt.makeKernel(program, "setupContactRows");
    m_countRows = m_rt.makeKernel(program, "countRowsInSolveOrder");
    m_placeConstraints = m_rt.makeKernel(program, "placeConstraints");
    m_placeRows = m_rt.makeKernel(program, "placeRows");
    m_impulsesToGatherOrder = m_rt.makeKernel(program, "impulsesToGatherOrder");
    if (m_rt.stepProgramLanes() > 1) {
        m_inLanes = m_rt.makeKernel(program, "solveStepInLanes");
        m_setupLanes = m_rt.makeKernel(program, "setupLaneSlots");
    }
}

// The copies are enqueued without waiting (one wait for all, by the caller): p lives until the
// step is written back.
void DeviceSolver::upload(const StepProblem& p) {
    m_bodies.enqueueUpload(m_rt, p.bodies);
    // Every body starts the step with no change: the gather's zeros, handed over in place where
    // the device works in the host's memory, else cleared on the device (no copy).
    if (m_rt.hostUnifiedMemory())
        m_deltas.enqueueUpload(m_rt, p.deltas);
    else
        m_deltas.fill(m_rt, btoclBodyDelta{}, p.deltas.size());
    m_constraints.enqueueWrite(m_rt, p.constraints);
    m_control.fill(m_rt, 0, BTOCL_CONTROL_SIZE);
    if (p.rowsOnDevice) m_points.enqueueUpload(m_rt, p.points);
    m_hostRows.enqueueWrite(m_rt, p.rows);
}

void DeviceSolver::arrange(StepProblem& p, const DeviceLayoutView& layout, const HostArrangement* onHost) {
    const int n = int(p.constraints.size());
    const int numRows = p.numRows();
    m_placed.reserve(m_rt, size_t(n));
    m_rowBase.reserve(m_rt, size_t(n));
    m_frictionRowBase.reserve(m_rt, size_t(n));
    m_rowMap.reserve(m_rt, size_t(numRows));
    m_rows.reserve(m_rt, size_t(numRows));
    m_normalOfRow.reserve(m_rt, size_t(numRows));
    m_applied.reserve(m_rt, size_t(numRows));
    m_pushApplied.reserve(m_rt, size_t(numRows));
    if (n == 0) return;
    if (onHost) {
        m_placed.enqueueWrite(m_rt, onHost->placed);
        m_rowMap.enqueueWrite(m_rt, onHost->rowMap);
    } else {
        // Row offsets in solve order, per region: a count per position, then an exclusive scan.
        setArgs(m_countRows, *layout.solveOrder, m_constraints.buffer(), m_rowBase.buffer(), m_frictionRowBase.buffer(),
                n);
        m_rt.launch(m_countRows, size_t(n), kLanes, "launching countRowsInSolveOrder");
        m_primitives.exclusiveScan(m_rowBase.buffer(), m_rowBase.buffer(), size_t(n));
        m_primitives.exclusiveScan(m_frictionRowBase.buffer(), m_frictionRowBase.buffer(), size_t(n));
        const int frictionRegion = btoclFrictionRegionStart(&p.regions);
        setArgs(m_placeConstraints, *layout.solveOrder, m_constraints.buffer(), m_rowBase.buffer(),
                m_frictionRowBase.buffer(), frictionRegion, m_placed.buffer(), m_rowMap.buffer(), n);
        m_rt.launch(m_placeConstraints, size_t(n), kLanes, "launching placeConstraints");
    }

    if (!p.rows.empty()) {  // rows the host set up: every row, or the joints'
        setArgs(m_placeRows, m_hostRows.buffer(), p.hostRowBase(), m_rowMap.buffer(), m_rows.buffer(),
                m_normalOfRow.buffer(), m_applied.buffer(), m_pushApplied.buffer(), int(p.rows.size()), p.regions,
                m_bodies.buffer());
        m_rt.launch(m_placeRows, p.rows.size(), kLanes, "launching placeRows");
    }
    if (!p.rowsOnDevice || p.points.empty()) return;
    p.lateralDirs.resize(2 * p.points.size());  // written by the setup kernel
    m_lateralDirs.prepareDownload(m_rt, p.lateralDirs);
    setArgs(m_setupRows, m_points.buffer(), m_bodies.buffer(), m_rowMap.buffer(), m_rows.buffer(),
            m_normalOfRow.buffer(), m_applied.buffer(), m_pushApplied.buffer(), m_lateralDirs.buffer(), p.setupParams);
    m_rt.launch(m_setupRows, p.points.size(), kLanes, "launching setupContactRows");
}

void DeviceSolver::arrangeInLanes(StepProblem& p, const LaneLayout& lanes, const HostArray<float>& bodyPerUnit,
                                  const LaneRows* setOnHost) {
    if (lanes.lanes != m_rt.stepProgramLanes())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a lane layout of " + std::to_string(lanes.lanes) +
                                  " lanes for a program of " + std::to_string(m_rt.stepProgramLanes()));
    if (setOnHost && !m_rt.hostUnifiedMemory())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: lane rows set up on the host for a device with memory "
                                  "of its own");
    const size_t places = size_t(lanes.numBlocks) * size_t(lanes.lanes);
    m_numSlots = int(lanes.slots.size());
    m_frictionPerPoint = lanes.frictionPerPoint;
    if (bodyPerUnit.size() != p.bodies.size() * BTOCL_BODY_PER_UNIT_FLOATS)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: lanes' per-unit scales not those of the step's bodies");
    m_bodyPerUnit.enqueueUpload(m_rt, bodyPerUnit);
    if (setOnHost) {  // the host's arrays themselves
        m_wideRows.enqueueUpload(m_rt, setOnHost->rows);
        m_applied.enqueueUpload(m_rt, setOnHost->applied);
        m_pushApplied.enqueueUpload(m_rt, setOnHost->pushApplied);
    } else {
        m_wideRows.reserve(m_rt, places * BTOCL_LANE_ROW_FLOATS);
        m_applied.reserve(m_rt, places);
        m_pushApplied.reserve(m_rt, places);
    }
    m_placed.reserve(m_rt, 1);  // bound, unread
    m_rows.reserve(m_rt, 1);
    m_normalOfRow.reserve(m_rt, 1);
    m_bundles.enqueueWrite(m_rt, lanes.bundles);
    m_setBundleStart.enqueueWrite(m_rt, lanes.setBundleStart.data(), lanes.setBundleStart.size());
    m_slots.enqueueWrite(m_rt, lanes.slots);
    m_slotPushes.reserve(m_rt, std::max<size_t>(1, lanes.slots.size()));
    m_lanes.enqueueWrite(m_rt, lanes.laneInts);
    m_rowMap.enqueueWrite(m_rt, lanes.rowMap);
    if (m_numSlots == 0) return;
    p.lateralDirs.resize(2 * p.points.size());  // written by the setup kernel, or the host's
    m_lateralDirs.prepareDownload(m_rt, p.lateralDirs);
    if (setOnHost) return;
    setArgs(m_setupLanes, m_points.buffer(), m_bodies.buffer(), m_slots.buffer(), m_lanes.buffer(), m_wideRows.buffer(),
            m_applied.buffer(), m_pushApplied.buffer(), m_lateralDirs.buffer(), p.setupParams, m_numSlots);
    // Few work-items a group: a slot is many points' work.
    m_rt.launch(m_setupLanes, size_t(m_numSlots), kSlotsPerGroup, "launching setupLaneSlots");
}

// The buffers every solve kernel takes first, arguments 0 to kSolveBufferArgs - 1, in the order
// of kernels/solve.cl's BTOCL_SOLVE_KERNEL_BUFFERS.
void DeviceSolver::bindSolveBuffers(cl::Kernel& k, const DeviceLayoutView& layout) const {
    setArgs(k, *layout.groups, *layout.batchEnd, m_placed.buffer(), m_rows.buffer(), m_normalOfRow.buffer(),
            m_applied.buffer(), m_pushApplied.buffer(), m_bodies.buffer(), m_deltas.buffer(), m_control.buffer());
}

void DeviceSolver::launchPass(const StepPlan& plan, const DeviceLayoutView& layout, int passIndex,
                              const SolveSettings& s) {
    const btoclPassStep pass = btoclPassAt(plan.passes(), passIndex);
    cl::Kernel& k = m_passKernels[size_t(pass.pass)];
    const size_t lanes = size_t(plan.lanesPerGroup());
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
        const int first = layout.setGroupStart[size_t(set)];
        const int count = layout.setGroupStart[size_t(set) + 1] - first;
        bindSolveBuffers(k, layout);
        setArgsFrom(k, kSolveBufferArgs, first, s.flags, pass.iteration, plan.passes().numIterations,
                    cl_uint(btoclPassSeed(plan.passes(), passIndex)));
        m_rt.launch(k, size_t(count) * lanes, lanes, "launching a solve pass");
    }
}

// A launch per set and pass; with a residual threshold, a kernel after each iteration stops the
// rest of its kind on the device once it has converged (endIteration).
void DeviceSolver::launchPerSet(const StepPlan& plan, const DeviceLayoutView& layout, const SolveSettings& s) {
    const bool track = (s.flags & BTOCL_FLAG_TRACK_RESIDUAL) != 0;
    const int numPasses = btoclPassCount(plan.passes());
    for (int i = 0; i < numPasses; ++i) {
        const btoclPassStep pass = btoclPassAt(plan.passes(), i);
        launchPass(plan, layout, i, s);
        if (!track || !pass.endsIteration) continue;
        setArgs(m_endIteration, m_control.buffer(), s.residualThreshold, pass.pass == BTOCL_PASS_PUSH ? 1 : 0);
        m_rt.launch(m_endIteration, 1, 1, "launching endIteration");
    }
}

void DeviceSolver::launchWholeStep(const StepPlan& plan, const DeviceLayoutView& layout, const SolveSettings& s) {
    bindSolveBuffers(m_wholeStep, layout);
    setArgsFrom(m_wholeStep, kSolveBufferArgs, layout.setGroupStart[BTOCL_NUM_SETS + 1], s.flags, s.residualThreshold,
                plan.passes());
    const size_t lanes = size_t(plan.lanesPerGroup());
    m_rt.launch(m_wholeStep, lanes, lanes, "launching solveWholeStep");
}

// Single-lane work-groups, for a split step one per compute unit: the device runs them side by
// side (more would wait for a free unit and buy nothing; fewer would leave units idle). The
// progress block is cleared on the device, in order before the launch; a single work-group (a
// whole step) clears it itself, which saves the fill command.
void DeviceSolver::launchClaimed(const StepProblem& p, const StepPlan& plan, const DeviceLayoutView& layout,
                                 const SolveSettings& s, int workGroups) {
    const btoclPassSchedule& passes = plan.passes();
    clearProgress(passes, workGroups);
    bindSolveBuffers(m_claimed, layout);
    setArgsFrom(m_claimed, kSolveBufferArgs, *layout.setGroupStartOnDevice, m_progress.buffer(),
                int(p.constraints.size()), s.flags, s.residualThreshold, passes);
    m_rt.launch(m_claimed, size_t(workGroups), 1, "launching solveStepClaimed");
}

void DeviceSolver::clearProgress(const btoclPassSchedule& passes, int workGroups) {
    const size_t progressInts =
        size_t(btoclProgressSize(workGroups, btoclPassCount(passes), passes.pushIterations, passes.maxIterations));
    if (workGroups > 1)
        m_progress.fill(m_rt, 0, progressInts);
    else
        m_progress.reserve(m_rt, progressInts);
}

// As launchClaimed, over the bundles of arrangeInLanes, one work-group per compute unit.
void DeviceSolver::launchInLanes(const StepPlan& plan, const SolveSettings& s) {
    const btoclPassSchedule& passes = plan.passes();
    const int workGroups = int(m_rt.computeUnits());
    clearProgress(passes, workGroups);
    DeviceLayoutView bundles;  // the bundles in the groups' place; batchEnd is unread
    bundles.groups = bundles.batchEnd = &m_bundles.buffer();
    bindSolveBuffers(m_inLanes, bundles);
    setArgsFrom(m_inLanes, kSolveBufferArgs, m_setBundleStart.buffer(), m_progress.buffer(), m_numSlots, s.flags,
                s.residualThreshold, passes, m_slots.buffer(), m_lanes.buffer(), m_bodyPerUnit.buffer(),
                m_wideRows.buffer(), m_frictionPerPoint, m_slotPushes.buffer());
    m_rt.launch(m_inLanes, size_t(workGroups), 1, "launching solveStepInLanes");
}

void DeviceSolver::iterate(const StepProblem& p, const StepPlan& plan, const DeviceLayoutView& layout,
                           const SolveSettings& s) {
    if (p.constraints.empty()) return;
    if (plan.onHost())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: a step planned for the host was sent to the device");
    if (plan.inLanes()) return launchInLanes(plan, s);
    if (plan.claimedLaunch()) return launchClaimed(p, plan, layout, s, plan.oneGroup() ? 1 : int(m_rt.computeUnits()));
    if (plan.mode() == StepMode::PerSet) return launchPerSet(plan, layout, s);
    launchWholeStep(plan, layout, s);
}

void DeviceSolver::warmUp(KernelWarmUp& warm, const GroupLanes& lanes) {
    constexpr size_t grid = KernelWarmUp::kGrid;
    const cl::Buffer z = warm.zeros(4096);
    const int none = 0;
    setArgs(m_countRows, z, z, z, z, none);
    warm.launch(m_countRows, grid, kLanes);
    setArgs(m_placeConstraints, z, z, z, z, none, z, z, none);
    warm.launch(m_placeConstraints, grid, kLanes);
    setArgs(m_placeRows, z, none, z, z, z, z, z, none, btoclRowRegionsOf(0, 0, 0, 0), z);
    warm.launch(m_placeRows, grid, kLanes);
    btoclSetupParams noPoints{};
    noPoints.numPoints = 0;
    setArgs(m_setupRows, z, z, z, z, z, z, z, z, noPoints);
    warm.launch(m_setupRows, grid, kLanes);
    setArgs(m_impulsesToGatherOrder, z, z, z, none);
    warm.launch(m_impulsesToGatherOrder, grid, kLanes);

    // The solve: no groups, no passes (the set starts in `z` are all 0).
    const btoclPassSchedule noPasses{};
    const float noThreshold = 0;
    auto bindScratch = [&](cl::Kernel& k, const cl::Buffer& control) {
        setArgs(k, z, z, z, z, z, z, z, z, z, control);
    };
    // Whole steps of one lane, and the serial path's split steps, are claimed (StepPlan::claimedLaunch).
    const size_t wg = size_t(lanes.lanes);
    if (wg == 1 || !lanes.localBatches) {
        bindScratch(m_claimed, z);
        setArgsFrom(m_claimed, kSolveBufferArgs, z, z, none, none, noThreshold, noPasses);
        warm.launch(m_claimed, m_rt.computeUnits(), 1);
    }
    if (m_inLanes()) {
        bindScratch(m_inLanes, z);
        setArgsFrom(m_inLanes, kSolveBufferArgs, z, z, none, none, noThreshold, noPasses, z, z, z, z, 1, z);
        warm.launch(m_inLanes, m_rt.computeUnits(), 1);
        setArgs(m_setupLanes, z, z, z, z, z, z, z, z, noPoints, none);
        warm.launch(m_setupLanes, grid, kSlotsPerGroup);
    }
    if (!lanes.localBatches) return;
    if (wg > 1) {
        bindScratch(m_wholeStep, z);
        setArgsFrom(m_wholeStep, kSolveBufferArgs, none, none, noThreshold, noPasses);
        warm.launch(m_wholeStep, wg, wg);
    }
    // A pass kernel returns at once when its kind of iterations has stopped.
    std::array<int, BTOCL_CONTROL_SIZE> stopped{};
    stopped[BTOCL_CONTROL_STOPPED] = stopped[BTOCL_CONTROL_PUSH_STOPPED] = 1;
    const cl::Buffer control = warm.zeros(sizeof stopped);
    checkCl(m_rt.queue().enqueueWriteBuffer(control, CL_TRUE, 0, sizeof stopped, stopped.data()),
            "writing a warm-up buffer");
    for (cl::Kernel& k : m_passKernels) {
        bindScratch(k, control);
        setArgsFrom(k, kSolveBufferArgs, none, none, none, none, 0u);
        warm.launch(k, grid, wg);
    }
    setArgs(m_endIteration, control, noThreshold, none);
    warm.launch(m_endIteration, 1, 1);
}

int DeviceSolver::download(StepProblem& p, const StepPlan& plan, const SolveSettings& s) {
    // Every copy enqueued, then one wait.
    m_deltas.enqueueDownload(m_rt, p.deltas);
    const int n = p.numRows();
    p.appliedImpulses.resize(size_t(n));
    if (n > 0) {
        m_impulses.prepareDownload(m_rt, p.appliedImpulses);
        setArgs(m_impulsesToGatherOrder, m_applied.buffer(), m_rowMap.buffer(), m_impulses.buffer(), n);
        m_rt.launch(m_impulsesToGatherOrder, size_t(n), kLanes, "launching impulsesToGatherOrder");
        m_impulses.enqueueDownload(m_rt, p.appliedImpulses);
    }
    if (p.rowsOnDevice) {
        p.lateralDirs.resize(2 * p.points.size());  // as arrange sized them (none where it set no row up)
        m_lateralDirs.enqueueDownload(m_rt, p.lateralDirs);
    }
    int iterations = p.constraints.empty() ? 0 : plan.passes().maxIterations;
    const bool counted = (s.flags & BTOCL_FLAG_TRACK_RESIDUAL) != 0 && !p.constraints.empty();
    if (counted) m_control.enqueueRead(m_rt, m_controlEnd.data(), m_controlEnd.size());
    m_rt.finish("reading the results back");
    if (counted) iterations = m_controlEnd[BTOCL_CONTROL_ITERATIONS];
    return iterations;
}

}  // namespace btocl
