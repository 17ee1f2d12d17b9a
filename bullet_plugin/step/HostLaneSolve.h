// A split step on the host with its groups eight at a time in the vector unit's lanes: the lane
// layout (LaneLayout.h) of the host's split, the contact rows set up into its blocks, and each
// slot's eight constraints solved as kernels/lane_solve.h solves them, operation for operation,
// so that each lane's results are the one-lane walk's to the bit (HostSolve, the claimed launch);
// each set's bundles shared out to the host's threads, the calling one among them. Contact rows
// alone, in a pass that pairs (stepFitsLanes, StepPolicy.h).
#pragma once

#include "BatchLayout.h"
#include "LaneLayout.h"
#include "StepProblem.h"
#include "row_setup.h"

#include <vector>

namespace btocl {

// Every body's per-unit scales for the lanes (lane_setup.h's btoclSetupBodyPerUnit) into `out`,
// on the host's threads: what a lanes solve reads beside its rows, on any device.
void setUpBodyPerUnit(const StepProblem& p, int flags, HostArray<float>& out);

// Every contact row of `layout` (eight lanes: HostLaneSolve::kLanes) set up from p.points into
// `out` (all but its perUnit, setUpBodyPerUnit's) and p.lateralDirs, as setup.cl's setupLaneSlots
// sets them up (the same bits), on the host's threads. Called only where HostLaneSolve::available().
void setUpLaneRows(StepProblem& p, const LaneLayout& layout, LaneRows& out);

class HostLaneSolve {
public:
    // AVX2's width: the solve's functions are built for AVX2 alone and run where the CPU has it.
    static constexpr int kLanes = 8;
    // The most threads a solve runs on (a share each).
    static constexpr int kMaxShares = 8;
    // Whether this CPU runs them (x86-64 with AVX2).
    static bool available();

    // The lane layout of `split`, each set's groups in bundles for `shares` threads (at most
    // kMaxShares), then every contact row set up from p.points into its blocks (and
    // p.lateralDirs), as the setup kernel sets them up, on the host's threads.
    void setUp(StepProblem& p, const BatchLayout& split, int flags, int shares = 1);
    // The passes of `passes` over the layout, a share of each set on each of the host's threads
    // (onPool; else every share on the calling thread); leaves p.deltas and p.appliedImpulses
    // (gather order) as HostSolve does, the same bits either way. Returns the velocity iterations run.
    int solve(StepProblem& p, const btoclPassSchedule& passes, bool onPool = true);
    // The threads setUp laid the sets out for.
    int shares() const { return m_shares; }

    const LaneLayout& layout() const { return m_layout; }
    // What setUp wrote (the tests hold it to lane_setup.h's one-lane setup).
    const LaneRows& rows() const { return m_rows; }
    // The slots whose rows setUp wrote eight points at a time (the others one lane at a time).
    size_t slotsInVectors() const;

private:
    // One set of one pass: its bundles.
    struct SetStep {
        int pass, firstBundle, endBundle;
    };

    LaneLayout m_layout;
    std::vector<SetStep> m_steps;
    int m_shares = 1;
    LaneRows m_rows;
};

}  // namespace btocl
