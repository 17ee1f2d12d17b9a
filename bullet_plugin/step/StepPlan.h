// How one step is laid out and launched, decided once per step (planStep, StepPolicy.h) and taken
// whole by the layout (DeviceLayout::build) and the solve (DeviceSolver). The plan holds only
// combinations that the kernels can run: a plan is made by its factories alone.
#pragma once

#include "SolveSettings.h"
#include "StepProblem.h"
#include "btocl_shared.h"

namespace btocl {

// How the iterations of a step are launched.
enum class StepMode {
    WholeStep,  // no global split: every constraint in one group, every pass in one launch of one
                // work-group (solveWholeStep; with one lane, solveStepClaimed's walk is the same)
    PerSet,     // the global split; one launch per set and pass, the groups of a set side by side
    Claimed,    // the global split; one launch of a single-lane work-group per compute unit, which
                // claim each set's groups in turn (solve.cl: solveStepClaimed)
    Host,       // no device: rows set up and passes run on the calling thread, in gather order
                // (HostSolve.h), for a step too small to repay a device launch
    HostSplit,  // no device: the global split on the host, rows set up and passes run on the
                // calling thread in the split's order, which is the claimed launch's, to its bits
                // on a CPU device; where recent steps ran faster so (SplitStepTimes, StepPolicy.h)
};

// How a group's constraints meet the lanes, fixed for a solver by its path: the serial path walks
// a group with one lane, in order, and builds no local batches; the wide path runs a work-group's
// lanes over a group's batches of independent constraints.
struct GroupLanes {
    int lanes = 1;
    bool localBatches = false;

    static GroupLanes serial() { return GroupLanes{1, false}; }
    static GroupLanes wide(int workGroupSize) { return GroupLanes{workGroupSize, true}; }
};

class StepPlan {
public:
    static StepPlan wholeStep(GroupLanes lanes, const btoclPassSchedule& passes) {
        return StepPlan(StepMode::WholeStep, lanes, passes);
    }
    static StepPlan perSet(GroupLanes lanes, const btoclPassSchedule& passes) {
        return StepPlan(StepMode::PerSet, lanes, passes);
    }
    // One lane a group: the claimed launch walks each group's constraints in order.
    static StepPlan claimed(const btoclPassSchedule& passes) {
        return StepPlan(StepMode::Claimed, GroupLanes::serial(), passes);
    }
    // Claimed likewise, the groups W at a time in the vector unit's lanes (LaneLayout.h): for a
    // step whose rows the lanes solve (StepPolicy.cpp, stepFitsLanes).
    static StepPlan claimedInLanes(const btoclPassSchedule& passes, int simdLanes) {
        StepPlan plan(StepMode::Claimed, GroupLanes::serial(), passes);
        plan.m_simdLanes = simdLanes;
        return plan;
    }
    // The calling thread walks the constraints in gather order: the order of a whole step on the
    // serial path.
    static StepPlan onHost(const btoclPassSchedule& passes) {
        return StepPlan(StepMode::Host, GroupLanes::serial(), passes);
    }
    // The calling thread walks the host's split as a claimed launch would: the same results.
    static StepPlan onHostSplit(const btoclPassSchedule& passes) {
        return StepPlan(StepMode::HostSplit, GroupLanes::serial(), passes);
    }

    StepMode mode() const { return m_mode; }
    int lanesPerGroup() const { return m_lanes.lanes; }
    // Groups ordered as batches of constraints that share no dynamic body (else one run a group).
    bool localBatches() const { return m_lanes.localBatches; }
    // Every constraint in one group (set 0), no global split.
    bool oneGroup() const { return m_mode == StepMode::WholeStep || m_mode == StepMode::Host; }
    bool onHost() const { return m_mode == StepMode::Host || m_mode == StepMode::HostSplit; }
    // The iterations run in solveStepClaimed: the claimed mode, and a whole step of one lane, whose
    // one work-group walks the one group as solveWholeStep would (so the serial path, which has
    // one lane a group, compiles one solve kernel, not two).
    bool claimedLaunch() const {
        return m_mode == StepMode::Claimed || (m_mode == StepMode::WholeStep && m_lanes.lanes == 1);
    }
    // The solve reads the split's set starts on the device, so the host does not wait for them.
    bool setStartsOnDevice() const { return claimedLaunch(); }
    const btoclPassSchedule& passes() const { return m_passes; }
    // W > 1: the groups are solved W at a time in SIMD lanes (claimedInLanes); else 1.
    int simdLanes() const { return m_simdLanes; }
    bool inLanes() const { return m_simdLanes > 1; }
    // Host or device taken by the recent steps' times (SplitStepTimes): this one's goes back to them.
    bool timed() const { return m_timed; }
    StepPlan asTimed() const {
        StepPlan plan = *this;
        plan.m_timed = true;
        return plan;
    }

private:
    StepPlan(StepMode mode, GroupLanes lanes, const btoclPassSchedule& passes)
        : m_mode(mode), m_lanes(lanes), m_passes(passes) {}

    StepMode m_mode;
    GroupLanes m_lanes;
    btoclPassSchedule m_passes;
    int m_simdLanes = 1;
    bool m_timed = false;
};

// The step's passes (btocl_shared.h): the one place that decides them. Push iterations run only
// where some contact point may get a push share (StepProblem::mayNeedPush); the velocity
// iterations are m_numIterations, or more where a joint asks (SI's maxIterations).
inline btoclPassSchedule passScheduleOf(const SolveSettings& s, const StepProblem& p) {
    btoclPassSchedule passes;
    passes.warmStart = s.warmStart ? 1 : 0;
    passes.pushIterations = s.usePush && p.mayNeedPush ? s.numIterations : 0;
    passes.numIterations = s.numIterations;
    passes.maxIterations = p.maxIterations(s.numIterations);
    passes.orderSeed = s.orderSeed;
    return passes;
}

}  // namespace btocl
