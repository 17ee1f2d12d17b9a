// The device's part of a step's solve, in its stages: uploads the step's bodies and constraints,
// lays constraints and rows out in the layout's solve order and sets the rows up (arrange),
// launches the plan's passes with no host round trip between them (iterate), and reads back the
// velocity changes and applied impulses (download). Buffers are kept and grown from step to step.
#pragma once

#include "DeviceBuffer.h"
#include "DevicePrimitives.h"
#include "HostArrange.h"
#include "LaneLayout.h"
#include "KernelWarmUp.h"
#include "SolveSettings.h"
#include "StepPlan.h"
#include "StepProblem.h"

#include <array>

namespace btocl {

// Where the solve finds the split/batch layout: the device batcher's buffers or uploaded ones.
struct DeviceLayoutView {
    const cl::Buffer* groups = nullptr;
    const cl::Buffer* solveOrder = nullptr;
    const cl::Buffer* batchEnd = nullptr;
    std::array<int, BTOCL_NUM_SETS + 2> setGroupStart{};  // per-set and whole-step launches
    const cl::Buffer* setGroupStartOnDevice = nullptr;    // the same on the device: claimed launches
};

class DeviceSolver {
public:
    // `runtime` and `primitives` (the scan) must outlive this object.
    DeviceSolver(const OclRuntime& runtime, DevicePrimitives& primitives);

    // Hands bodies, deltas, constraints and contact points (or host-built rows) to the device
    // (bodies, points and deltas in place where it works in the host's memory). p.deltas must
    // be all zero, as the gather leaves them: the solve adds to them.
    void upload(const StepProblem& p);
    // Places constraints and rows in the layout's solve order and sets the rows up there
    // (kernels/arrange.cl, kernels/setup.cl). With `onHost`, the places are that arrangement's,
    // uploaded (it must live, unchanged, until the queue has finished).
    void arrange(StepProblem& p, const DeviceLayoutView& layout, const HostArrangement* onHost = nullptr);
    // For a step in lanes (StepPlan::inLanes): the lane layout and the bodies' per-unit scales
    // (setUpBodyPerUnit) uploaded (both must live, unchanged, until the queue has finished) and
    // the rows set up in its blocks (kernels/setup.cl), or, with `setOnHost` (a device in the
    // host's memory alone), the rows the host set up there, handed over in place (they too must
    // live until the queue has finished; p.lateralDirs already written).
    void arrangeInLanes(StepProblem& p, const LaneLayout& lanes, const HostArray<float>& bodyPerUnit,
                        const LaneRows* setOnHost = nullptr);
    // Enqueues the plan's passes, launched as its mode says.
    void iterate(const StepProblem& p, const StepPlan& plan, const DeviceLayoutView& layout, const SolveSettings& settings);
    // Reads back p.deltas, p.appliedImpulses (every row, gather order) and, with
    // rows set up on the device, p.lateralDirs. Returns the velocity iterations the device ran.
    int download(StepProblem& p, const StepPlan& plan, const SolveSettings& settings);
    const DeviceBuffer<btoclConstraint>& constraints() const { return m_constraints; }

    // Launches every kernel that steps on `lanes` use, in their launch shapes, on no work
    // (KernelWarmUp.h). Touches none of this object's buffers.
    void warmUp(KernelWarmUp& warm, const GroupLanes& lanes);

private:
    friend class DeviceSolveProbe;  // the tests' read-back of the rows (reference/DeviceSolveProbe.h)

    static constexpr cl_uint kSolveBufferArgs = 10;
    void bindSolveBuffers(cl::Kernel& kernel, const DeviceLayoutView& layout) const;
    void launchPerSet(const StepPlan& plan, const DeviceLayoutView& layout, const SolveSettings& settings);
    void launchPass(const StepPlan& plan, const DeviceLayoutView& layout, int passIndex, const SolveSettings& settings);
    void launchWholeStep(const StepPlan& plan, const DeviceLayoutView& layout, const SolveSettings& settings);
    void launchClaimed(const StepProblem& p, const StepPlan& plan, const DeviceLayoutView& layout,
                       const SolveSettings& settings, int workGroups);
    void launchInLanes(const StepPlan& plan, const SolveSettings& settings);
    void clearProgress(const btoclPassSchedule& passes, int workGroups);

    const OclRuntime& m_rt;
    DevicePrimitives& m_primitives;
    std::array<cl::Kernel, BTOCL_NUM_PASSES> m_passKernels;  // by BTOCL_PASS_*
    // solveStepInLanes and setupLaneSlots, where the program has lanes (OclRuntime::stepProgramLanes)
    cl::Kernel m_inLanes, m_setupLanes;
    cl::Kernel m_endIteration, m_wholeStep, m_claimed, m_setupRows, m_countRows, m_placeConstraints, m_placeRows, m_impulsesToGatherOrder;
    DeviceBuffer<btoclBody> m_bodies;
    DeviceBuffer<btoclBodyDelta> m_deltas;
    DeviceBuffer<btoclConstraint> m_constraints, m_placed;
    DeviceBuffer<btoclSolveRow> m_rows;  // in solve order, as the iterations read them
    DeviceBuffer<btoclRow> m_hostRows;   // rows the host set up, in gather order
    DeviceBuffer<int> m_normalOfRow;     // friction and rolling rows: their normal row, in solve order
    DeviceBuffer<btoclContactPoint> m_points;
    DeviceBuffer<btoclFloat4> m_lateralDirs;
    DeviceBuffer<int> m_control, m_rowBase, m_frictionRowBase, m_rowMap;
    DeviceBuffer<float> m_applied, m_pushApplied;  // per row in solve order: what the iterations update
    DeviceBuffer<float> m_impulses;
    DeviceBuffer<int> m_progress;  // solveStepClaimed's finished counts, residuals and claim counters
    // A step in lanes: its bundles (as groups), their set starts, slots, lanes and rows in blocks.
    DeviceBuffer<btoclGroup> m_bundles;
    DeviceBuffer<int> m_setBundleStart;
    DeviceBuffer<btoclLaneSlot> m_slots;
    DeviceBuffer<int> m_lanes;
    DeviceBuffer<float> m_bodyPerUnit;
    DeviceBuffer<float> m_wideRows;
    DeviceBuffer<int> m_slotPushes;  // per slot: a row with a push share (btoclPushSlotsPart)
    int m_numSlots = 0, m_frictionPerPoint = 1;
    std::array<int, BTOCL_CONTROL_SIZE> m_controlEnd{};  // the control block as read back
};

}  // namespace btocl
