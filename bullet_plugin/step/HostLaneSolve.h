// A split step on the host with its groups eight at a time in the vector unit's lanes: the lane
// layout (LaneLayout.h) of the host's split, the contact rows set up into its blocks, and each
// slot's eight constraints solved as kernels/lane_solve.h solves them, operation for operation,
// so that each lane's results are the one-lane walk's to the bit (HostSolve, the claimed launch);
// each set's bundles shared out to the host's threads, the calling one among them. Contact rows
// in passes that pair, and joints' rows beside them (stepFitsHostLanes, StepPolicy.h): a group
// holds its contacts first, so each set's contacts go through the lanes and its joints follow in
// lanes of their own, each lane walking some of its groups' joints one group after another.
#pragma once

#include "BatchLayout.h"
#include "LaneLayout.h"
#include "StepProblem.h"
#include "row_setup.h"

#include <array>
#include <vector>

namespace btocl {

// Every body's per-unit scales for the lanes (lane_setup.h's btoclSetupBodyPerUnit) into `out`,
// on the host's threads: what a lanes solve reads beside its rows, on any device.
void setUpBodyPerUnit(const StepProblem& p, int flags, HostArray<float>& out);

// How setUpLaneRows stores its blocks: past the caches where they outgrow those near the cores,
// or always (the same bits either way).
enum class LaneRowStores { BySize, Streamed };

// Every contact row of `layout` (eight lanes: HostLaneSolve::kLanes) set up from p.points into
// `out` (all but its perUnit, setUpBodyPerUnit's) and p.lateralDirs, as setup.cl's setupLaneSlots
// sets them up (the same bits), on the host's threads. Called only where HostLaneSolve::available().
void setUpLaneRows(StepProblem& p, const LaneLayout& layout, LaneRows& out,
                   LaneRowStores stores = LaneRowStores::BySize);

// A slot of joints in the host's lanes (HostLaneSolve): each lane's next joint, their rows in
// `blocks` blocks of W rows (btoclSolveRow's floats, each float of the W rows together) from firstBlock.
struct JointLaneSlot {
    int firstBlock, blocks;
};

class HostLaneSolve {
public:
    // AVX2's width: the solve's functions are built for AVX2 (and again for AVX-512VL's registers,
    // lanesUseWideRegisters) and run where the CPU has it.
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
    // The same arrays, for a device step in lanes to lay out and set up in (StepPipeline): either
    // way, a step finds them sized and touched by the steps before, and they are held once.
    LaneLayout& sharedLayout() { return m_layout; }
    LaneRows& sharedRows() { return m_rows; }
    // The slots whose rows setUp wrote eight points at a time (the others one lane at a time).
    size_t slotsInVectors() const;

    // Whether a split's groups each hold their contacts first and their joints after (as the
    // host's split keeps gather order, where the joints come last): a set's contacts may then go
    // through the lanes before its joints, to the bits of each group walked in order.
    static bool contactsLead(const BatchLayout& split, const std::vector<btoclConstraint>& constraints);
    // The split the lanes were laid out from: the step's, or its contacts alone where it has joints.
    const BatchLayout& laneSplit() const { return m_hasJoints ? m_contactSplit : *m_split; }

private:
    // One set of one pass: its bundles, or (joints) its joints' slots.
    struct SetStep {
        int pass, firstBundle, endBundle;
        int set, iteration;
        int pushSlots;  // btoclPushSlotsPart
        bool joints;
    };
    // A group's joints: a run of the step's solve order, and the share that walks it.
    struct JointRun {
        int offset, count, share;
    };
    void setUpJoints(const StepProblem& p, const BatchLayout& split);
    void setUpJointLanes(const StepProblem& p);
    void solveJointSlots(StepProblem& p, const SetStep& step, int share);

    LaneLayout m_layout;
    std::vector<SetStep> m_steps;
    std::vector<unsigned char> m_pushChanged;  // per push iteration and share: a push impulse changed
    std::vector<unsigned char> m_slotPushes;   // per slot: a row with a push share (btoclPushSlotsPart)
    int m_shares = 1;
    LaneRows m_rows;
    // A step with joints: the split's contacts (m_contactSplit) go through the lanes as above;
    // each set's joints of a share follow them in lanes of their own: every lane walks some of
    // the share's runs one after another, and slot t holds each lane's t-th joint.
    const BatchLayout* m_split = nullptr;
    bool m_hasJoints = false;
    BatchLayout m_contactSplit;
    std::vector<JointRun> m_jointRuns;  // by set, in the split's order
    std::array<int, BTOCL_NUM_SETS + 2> m_setJointRunStart{};
    int m_firstJointRow = 0;  // the first joint row (p.rows holds the joints' rows alone, from 0)
    std::vector<JointLaneSlot> m_jointSlots;
    std::array<int, (BTOCL_NUM_SETS + 1) * kMaxShares + 1> m_jointSlotStart{};  // of set * kMaxShares + share
    std::vector<int> m_jointLaneInts;          // per slot, as a contact slot's (BTOCL_LANE_*): rows, first row
    std::vector<float> m_jointLaneIterations;  // per slot and lane: its joint's iterations (0: none)
    HostArray<float> m_jointBlocks;            // the joints' rows, blocks of W
    std::vector<float> m_jointApplied;         // their impulses, by wide row (block * W + lane)
    std::vector<int> m_jointRowMap;            // per joint row (from 0): its wide row
    std::vector<int> m_runOrder;               // scratch: a set's runs of a share, longest first
    std::vector<std::vector<int>> m_laneJoints;  // scratch: each lane's joints
};

}  // namespace btocl
