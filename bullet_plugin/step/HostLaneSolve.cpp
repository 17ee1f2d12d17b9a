#include "HostLaneSolve.h"

#include "HostArray.h"
#include "HostParallel.h"
#include "HostSplit.h"
#include "btOpenCLSolverError.h"
#include "LaneRowSetup.h"
#include "LaneVectors.h"
#include "lane_setup.h"
#include "row_solve.h"

#include <algorithm>
#include <cstddef>
#include <string>

namespace btocl {
namespace {

static_assert(HostLaneSolve::kLanes == W, "the lanes are LaneVectors.h's");

// A side's bodies of a slot's lanes, one vector per float (lane_solve.h, btoclLaneBodies).
struct LaneBodies {
    Lanes lpuX, lpuY, lpuZ, apuX, apuY, apuZ;
    Lanes linX, linY, linZ, angX, angY, angZ;
    Lanes linW, angW;  // the deltas' w floats, stored back as they were
    Lanes dynamic;
};

BTOCL_LANES_INLINE LaneBodies loadBodies(const btoclBodyDelta* deltas, const float* perUnit, const int* body,
                                         int push, int warmStart) {
    LaneBodies l;
    const float* records[W];
    Lanes v[8];
    // The velocities a pass changes: floats 0 to 7 of the body's delta, or 8 to 15 in the push pass.
    for (int i = 0; i < W; ++i) records[i] = reinterpret_cast<const float*>(deltas + body[i]) + (push ? 8 : 0);
    transpose8(records, v);
    l.linX = v[0], l.linY = v[1], l.linZ = v[2], l.linW = v[3];
    l.angX = v[4], l.angY = v[5], l.angZ = v[6], l.angW = v[7];
    // The warm start's scales: floats 0 to 7 of the body's; the other passes': 8 to 15.
    const int unitOffset = warmStart ? 0 : BTOCL_BODY_PER_UNIT_FLOATS / 2;
    for (int i = 0; i < W; ++i) records[i] = perUnit + size_t(body[i]) * BTOCL_BODY_PER_UNIT_FLOATS + unitOffset;
    transpose8(records, v);
    l.lpuX = v[0], l.lpuY = v[1], l.lpuZ = v[2], l.dynamic = v[3];
    l.apuX = v[4], l.apuY = v[5], l.apuZ = v[6];
    return l;
}

// Each dynamic lane's velocities back (others never change); lanes of a slot share no dynamic
// body. Turned back into records, each stored whole (eight floats, its w floats as loaded): a
// store a lane rather than six.
BTOCL_LANES_INLINE void storeBodies(btoclBodyDelta* deltas, const int* body, int push, const LaneBodies& l) {
    const int offset = push ? 8 : 0;
    const Lanes v[8] = {l.linX, l.linY, l.linZ, l.linW, l.angX, l.angY, l.angZ, l.angW};
    Lanes records[8];
    transpose8(v, records);
    for (int i = 0; i < W; ++i)
        if (l.dynamic[i] != 0.0f) store(records[i], reinterpret_cast<float*>(deltas + body[i]) + offset);
}

#define ROW_FIELD(f) load(row + (f) * W)

// A row's angular components lie at floats componentA and componentB: a contact row's are its
// Jacobians' (BTOCL_LANE_ROW_FLOATS: its bodies keep their angular changes scaled), a joint row's
// btoclSolveRow's own.
enum { kContactComponentA = 4, kContactComponentB = 8, kJointComponentA = 12, kJointComponentB = 16 };

BTOCL_LANES_INLINE void applyImpulse(const float* row, LaneBodies& A, LaneBodies& B, Lanes impulse, LaneMask active,
                                     int componentA, int componentB) {
    const Lanes nX = ROW_FIELD(0), nY = ROW_FIELD(1), nZ = ROW_FIELD(2);
    A.linX = select(A.linX, A.linX + (nX * A.lpuX) * impulse, active);
    A.linY = select(A.linY, A.linY + (nY * A.lpuY) * impulse, active);
    A.linZ = select(A.linZ, A.linZ + (nZ * A.lpuZ) * impulse, active);
    A.angX = select(A.angX, A.angX + (ROW_FIELD(componentA) * A.apuX) * impulse, active);
    A.angY = select(A.angY, A.angY + (ROW_FIELD(componentA + 1) * A.apuY) * impulse, active);
    A.angZ = select(A.angZ, A.angZ + (ROW_FIELD(componentA + 2) * A.apuZ) * impulse, active);
    B.linX = select(B.linX, B.linX - (nX * B.lpuX) * impulse, active);
    B.linY = select(B.linY, B.linY - (nY * B.lpuY) * impulse, active);
    B.linZ = select(B.linZ, B.linZ - (nZ * B.lpuZ) * impulse, active);
    B.angX = select(B.angX, B.angX + (ROW_FIELD(componentB) * B.apuX) * impulse, active);
    B.angY = select(B.angY, B.angY + (ROW_FIELD(componentB + 1) * B.apuY) * impulse, active);
    B.angZ = select(B.angZ, B.angZ + (ROW_FIELD(componentB + 2) * B.apuZ) * impulse, active);
}

// Returns the lanes whose impulse changed.
BTOCL_LANES_INLINE LaneMask solveRows(const float* row, float* applied, LaneBodies& A, LaneBodies& B, Lanes lower,
                                      Lanes upper, int push, LaneMask active, int componentA = kContactComponentA,
                                      int componentB = kContactComponentB) {
    const Lanes nX = ROW_FIELD(0), nY = ROW_FIELD(1), nZ = ROW_FIELD(2);
    const Lanes old = load(applied);
    const Lanes start = (push ? ROW_FIELD(BTOCL_LANE_ROW_SHARED) : ROW_FIELD(3)) - old * ROW_FIELD(7);
    const Lanes vX = (nX * A.linX - nX * B.linX) + (ROW_FIELD(4) * A.angX + ROW_FIELD(8) * B.angX);
    const Lanes vY = (nY * A.linY - nY * B.linY) + (ROW_FIELD(5) * A.angY + ROW_FIELD(9) * B.angY);
    const Lanes vZ = (nZ * A.linZ - nZ * B.linZ) + (ROW_FIELD(6) * A.angZ + ROW_FIELD(10) * B.angZ);
    const Lanes unclamped = start - (vX + vY + vZ) * ROW_FIELD(11);
    const Lanes sum = old + unclamped;
    const LaneMask below = sum < lower, above = sum > upper;
    const Lanes delta = select(select(unclamped, upper - old, above), lower - old, below);
    const Lanes next = select(select(sum, upper, above), lower, below);
    store(select(old, next, active), applied);
    applyImpulse(row, A, B, delta, active, componentA, componentB);
    return (delta != 0.0f) & active;
}

#undef ROW_FIELD


}  // namespace

// Slot after slot as setup.cl's setupLaneSlots sets them up (lane_setup.h): the same bits.
void setUpBodyPerUnit(const StepProblem& p, int flags, HostArray<float>& out) {
    out.resize(p.bodies.size() * BTOCL_BODY_PER_UNIT_FLOATS);
    parallelFor(p.bodies.size(), [&](size_t body) {
        btoclSetupBodyPerUnit(p.bodies.data(), p.deltas.data(), int(body), out.data(), flags);
    }, kRigidBodyWeight);
}

namespace {

// The points of the slot two on and the bodies of the next lie scattered, and the setup waited
// for them: asked for at `slot`, they come while it is set up. So do the lines of the points'
// friction directions, which the setup writes (a line holds two points' and is read before it is
// written, eight places at a time). Inlined: called, it cost the loop more than it saved.
inline __attribute__((always_inline)) void askForSlotInputs(const StepProblem& p, const LaneLayout& layout,
                                                            size_t slot) {
    const size_t numSlots = layout.slots.size();
    const int* ints = layout.laneInts.data() + slot * (BTOCL_LANE_INTS * W);
    if (slot + 2 < numSlots) {
        const int* later = ints + 2 * BTOCL_LANE_INTS * W;
        for (int i = 0; i < W; ++i) {
            const int firstPoint = later[BTOCL_LANE_FIRST_POINT * W + i], points = later[BTOCL_LANE_POINTS * W + i];
            prefetchBytes(p.points.data() + firstPoint, size_t(points) * sizeof(btoclContactPoint));
            prefetchBytes(p.lateralDirs.data() + 2 * size_t(firstPoint), size_t(points) * 2 * sizeof(btoclFloat4),
                          true);
        }
    }
    if (slot + 1 < numSlots) {
        const int* next = ints + BTOCL_LANE_INTS * W;
        for (int i = 0; i < 2 * W; ++i) {
            const char* body = reinterpret_cast<const char*>(p.bodies.data() + next[BTOCL_LANE_BODY_A * W + i]);
            for (int line = 0; line < int(sizeof(btoclBody)); line += 64) __builtin_prefetch(body + line);
        }
    }
}

}  // namespace

void setUpLaneRows(StepProblem& p, const LaneLayout& layout, LaneRows& out, LaneRowStores stores) {
    if (layout.lanes != W)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: the host sets up lanes of " + std::to_string(W) +
                                  ", not " + std::to_string(layout.lanes));
    const size_t numSlots = layout.slots.size();
    resizeForOverwrite(out.rows, size_t(layout.numBlocks) * BTOCL_LANE_ROW_FLOATS * W);
    resizeForOverwrite(out.applied, size_t(layout.numBlocks) * W);
    resizeForOverwrite(out.pushApplied, size_t(layout.numBlocks) * W);
    resizeForOverwrite(out.inVectors, numSlots);
    resizeForOverwrite(p.lateralDirs, 2 * p.points.size());
    // Rows larger than the caches near the cores are streamed past them: the solve reads them from
    // memory either way, and a line written whole need not be read first. Smaller ones stay, for
    // the solve's first pass.
    const bool stream =
        stores == LaneRowStores::Streamed || out.rows.size() * sizeof(float) > kStreamedArrayBytes;
    parallelFor(numSlots, [&](size_t slot) {
        const int* ints = layout.laneInts.data() + slot * (BTOCL_LANE_INTS * W);
        askForSlotInputs(p, layout, slot);
        out.inVectors[slot] = setUpSlotRowsInLanes(p.points.data(), p.bodies.data(), layout.slots[slot], ints,
                                                   out.rows.data(), out.applied.data(), out.pushApplied.data(),
                                                   p.lateralDirs.data(), p.setupParams, stream);
        if (out.inVectors[slot]) return;
        for (int lane = 0; lane < W; ++lane)
            btoclSetupLaneRows(p.points.data(), p.bodies.data(), layout.slots[slot], ints, lane, out.rows.data(),
                               out.applied.data(), out.pushApplied.data(), p.lateralDirs.data(), &p.setupParams, W);
    }, W * kContactConstraintWeight);
    if (stream) drainStreamedStores();  // the pool's threads drained theirs as they finished
}

bool HostLaneSolve::contactsLead(const BatchLayout& split, const std::vector<btoclConstraint>& constraints) {
    for (const btoclGroup& g : split.groups) {
        bool joints = false;
        for (int k = 0; k < g.count; ++k) {
            const bool joint = constraints[size_t(split.solveOrder[size_t(g.offset + k)])].numRows[BTOCL_ROWS_JOINT] > 0;
            if (joints && !joint) return false;
            joints = joint;
        }
    }
    return true;
}

// The split's contacts as a split of their own (each group's leading contacts, in its cell), and
// each group's joints as a run of the split's order, walked by the share of its cell; then the
// joints' lanes (setUpJointLanes).
void HostLaneSolve::setUpJoints(const StepProblem& p, const BatchLayout& split) {
    const std::vector<int> cuts = cellCuts(split, m_shares);
    BatchLayout& c = m_contactSplit;
    c.solveOrder.clear();
    c.groups.clear();
    c.setGroupStart.fill(0);
    c.cellSize = split.cellSize;
    c.numOverflowConstraints = 0;
    c.serialRuns = true;
    m_jointRuns.clear();
    m_setJointRunStart.fill(0);
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
        c.setGroupStart[size_t(set)] = int(c.groups.size());
        m_setJointRunStart[size_t(set)] = int(m_jointRuns.size());
        for (int gi = split.setGroupStart[size_t(set)]; gi < split.setGroupStart[size_t(set) + 1]; ++gi) {
            const btoclGroup& g = split.groups[size_t(gi)];
            int contacts = 0;
            while (contacts < g.count &&
                   p.constraints[size_t(split.solveOrder[size_t(g.offset + contacts)])].numRows[BTOCL_ROWS_JOINT] == 0)
                ++contacts;
            if (contacts > 0) {
                c.groups.push_back(btoclGroup{int(c.solveOrder.size()), contacts, 1, g.cell});
                c.solveOrder.insert(c.solveOrder.end(), split.solveOrder.begin() + g.offset,
                                    split.solveOrder.begin() + g.offset + contacts);
                if (set == BTOCL_OVERFLOW_SET) c.numOverflowConstraints += contacts;
            }
            if (contacts < g.count)
                m_jointRuns.push_back(JointRun{g.offset + contacts, g.count - contacts,
                                               set < BTOCL_OVERFLOW_SET ? partOfCell(cuts, g.cell) : 0});
        }
    }
    c.setGroupStart[BTOCL_NUM_SETS + 1] = int(c.groups.size());
    m_setJointRunStart[BTOCL_NUM_SETS + 1] = int(m_jointRuns.size());
    c.batchEnd.assign(c.solveOrder.size(), 0);
    for (const btoclGroup& g : c.groups) c.batchEnd[size_t(g.offset)] = g.offset + g.count;

    m_firstJointRow = p.rowStart(BTOCL_ROWS_JOINT);  // the joints' rows come last (StepGatherer::addJointRows)
    setUpJointLanes(p);
}

namespace {

// A joint slot's rows (lane i's k-th at block firstBlock + k, lane i) as the one-lane walk reads
// them (btoclSolveRowOf), eight rows turned into a block's vectors at a time; zeros where a lane
// has no row (masked in the solve).
BTOCL_LANES_TARGET void placeJointRows(const btoclRow* rows, const btoclBody* bodies, const int* ints,
                                       const JointLaneSlot& slot, float* out, float* applied, int* rowMap) {
    static_assert(sizeof(btoclSolveRow) == BTOCL_SOLVE_ROW_FLOATS * sizeof(float), "a solve row's floats");
    btoclSolveRow lanes[W];
    const btoclSolveRow zero{};
    for (int k = 0; k < slot.blocks; ++k) {
        const int block = slot.firstBlock + k;
        const float* records[W];
        Lanes start{};
        for (int i = 0; i < W; ++i) {
            records[i] = reinterpret_cast<const float*>(&zero);
            if (k >= ints[BTOCL_LANE_POINTS * W + i]) continue;
            const int r = ints[BTOCL_LANE_FIRST_POINT * W + i] + k;
            lanes[i] = btoclSolveRowOf(rows[r], BTOCL_ROWS_JOINT, bodies + rows[r].bodyA, bodies + rows[r].bodyB);
            records[i] = reinterpret_cast<const float*>(&lanes[i]);
            start[i] = BTOCL_ROW_APPLIED(rows[r]);
            rowMap[r] = block * W + i;
        }
        float* to = out + size_t(block) * BTOCL_SOLVE_ROW_FLOATS * W;
        Lanes v[8];
        transpose8(records, v);  // floats 0 to 7
        for (int f = 0; f < 8; ++f) store(v[f], to + f * W);
        const float* shifted[W];
        for (int i = 0; i < W; ++i) shifted[i] = records[i] + 8;
        transpose8(shifted, v);  // floats 8 to 15
        for (int f = 0; f < 8; ++f) store(v[f], to + (8 + f) * W);
        for (int i = 0; i < W; ++i) shifted[i] = records[i] + 12;
        transpose8(shifted, v);  // floats 12 to 19: the last four
        for (int f = 4; f < 8; ++f) store(v[f], to + (12 + f) * W);
        store(start, applied + size_t(block) * W);
    }
}

}  // namespace

// Each set's runs of a share dealt to the lanes, the longest first to the lane with the fewest
// joints (runs share no dynamic body, and each keeps its order in its lane); then the slots, and
// every joint row (p.rows: the joints' alone, set up by the gather) placed in its slot's blocks.
void HostLaneSolve::setUpJointLanes(const StepProblem& p) {
    m_jointSlots.clear();
    m_jointLaneInts.clear();
    m_jointLaneIterations.clear();
    m_laneJoints.resize(W);
    int numBlocks = 0;
    for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set)
        for (int share = 0; share < kMaxShares; ++share) {
            m_jointSlotStart[size_t(set) * kMaxShares + size_t(share)] = int(m_jointSlots.size());
            m_runOrder.clear();
            for (int ri = m_setJointRunStart[size_t(set)]; ri < m_setJointRunStart[size_t(set) + 1]; ++ri)
                if (m_jointRuns[size_t(ri)].share == share) m_runOrder.push_back(ri);
            std::stable_sort(m_runOrder.begin(), m_runOrder.end(), [&](int a, int b) {
                return m_jointRuns[size_t(a)].count > m_jointRuns[size_t(b)].count;
            });
            for (std::vector<int>& lane : m_laneJoints) lane.clear();
            size_t slots = 0;
            for (const int ri : m_runOrder) {
                const JointRun& run = m_jointRuns[size_t(ri)];
                std::vector<int>& lane = *std::min_element(
                    m_laneJoints.begin(), m_laneJoints.end(),
                    [](const std::vector<int>& a, const std::vector<int>& b) { return a.size() < b.size(); });
                lane.insert(lane.end(), m_split->solveOrder.begin() + run.offset,
                            m_split->solveOrder.begin() + run.offset + run.count);
                slots = std::max(slots, lane.size());
            }
            for (size_t t = 0; t < slots; ++t) {
                const size_t at = m_jointLaneInts.size();
                m_jointLaneInts.resize(at + BTOCL_LANE_INTS * W, 0);
                m_jointLaneIterations.resize(m_jointLaneIterations.size() + W, 0.0f);
                float* iterations = m_jointLaneIterations.data() + m_jointLaneIterations.size() - W;
                int blocks = 0;
                for (int i = 0; i < W; ++i) {
                    if (t >= m_laneJoints[size_t(i)].size()) continue;  // on the fixed body, no rows
                    const btoclConstraint& c = p.constraints[size_t(m_laneJoints[size_t(i)][t])];
                    int* ints = m_jointLaneInts.data() + at;
                    ints[BTOCL_LANE_BODY_A * W + i] = c.bodyA;
                    ints[BTOCL_LANE_BODY_B * W + i] = c.bodyB;
                    ints[BTOCL_LANE_POINTS * W + i] = c.numRows[BTOCL_ROWS_JOINT];  // its rows
                    ints[BTOCL_LANE_FIRST_POINT * W + i] = c.firstRow[BTOCL_ROWS_JOINT] - m_firstJointRow;
                    iterations[i] = BTOCL_CONSTRAINT_ITERATIONS(c);
                    blocks = std::max(blocks, c.numRows[BTOCL_ROWS_JOINT]);
                }
                m_jointSlots.push_back(JointLaneSlot{numBlocks, blocks});
                numBlocks += blocks;
            }
        }
    m_jointSlotStart[(BTOCL_NUM_SETS + 1) * kMaxShares] = int(m_jointSlots.size());
    m_jointBlocks.resize(size_t(numBlocks) * BTOCL_SOLVE_ROW_FLOATS * W);
    m_jointApplied.resize(size_t(numBlocks) * W);
    m_jointRowMap.resize(p.rows.size());
    parallelFor(m_jointSlots.size(), [&](size_t t) {
        placeJointRows(p.rows.data(), p.bodies.data(), m_jointLaneInts.data() + t * BTOCL_LANE_INTS * W,
                       m_jointSlots[t], m_jointBlocks.data(), m_jointApplied.data(), m_jointRowMap.data());
    }, W * kContactConstraintWeight);
}

namespace {

// Joint slots [first, end) in the normal pass: each lane's rows within their limits (a row's
// floats 15 and 19), while its joint takes part in this iteration, as btoclSolveJointRows solves
// them one joint at a time.
BTOCL_LANES_TARGET void solveJointSlotRange(const JointLaneSlot* slots, const int* laneInts,
                                            const float* laneIterations, const float* blocks, float* applied,
                                            const float* perUnit, btoclBodyDelta* deltas, int first, int end,
                                            int iteration) {
    const int blockFloats = BTOCL_SOLVE_ROW_FLOATS * W;
    const Lanes now = splat(float(iteration));
    for (int t = first; t < end; ++t) {
        const int* ints = laneInts + size_t(t) * BTOCL_LANE_INTS * W;
        const int* bodyA = ints + BTOCL_LANE_BODY_A * W;
        const int* bodyB = ints + BTOCL_LANE_BODY_B * W;
        if (t + 1 < end) {  // the next slot's bodies, A then B, asked for
            const int* next = ints + BTOCL_LANE_INTS * W;
            for (int i = 0; i < 2 * W; ++i) __builtin_prefetch(deltas + next[BTOCL_LANE_BODY_A * W + i]);
        }
        LaneBodies A = loadBodies(deltas, perUnit, bodyA, 0, 0);
        LaneBodies B = loadBodies(deltas, perUnit, bodyB, 0, 0);
        const LaneMask rows = loadInts(ints + BTOCL_LANE_POINTS * W);
        const LaneMask takesPart = now < load(laneIterations + size_t(t) * W);
        const JointLaneSlot& s = slots[t];
        for (int k = 0; k < s.blocks; ++k) {
            const float* row = blocks + size_t(s.firstBlock + k) * blockFloats;
            solveRows(row, applied + size_t(s.firstBlock + k) * W, A, B, load(row + 15 * W), load(row + 19 * W), 0,
                      (rows > k) & takesPart, kJointComponentA, kJointComponentB);
        }
        storeBodies(deltas, bodyA, 0, A);
        storeBodies(deltas, bodyB, 0, B);
    }
}

}  // namespace

// A set's joints of `share` in one pass (the normal pass: joints take no other).
void HostLaneSolve::solveJointSlots(StepProblem& p, const SetStep& step, int share) {
    const size_t at = size_t(step.set) * kMaxShares + size_t(share);
    solveJointSlotRange(m_jointSlots.data(), m_jointLaneInts.data(), m_jointLaneIterations.data(), m_jointBlocks.data(),
                        m_jointApplied.data(), m_rows.perUnit.data(), p.deltas.data(), m_jointSlotStart[at],
                        m_jointSlotStart[at + 1], step.iteration);
}

void HostLaneSolve::setUp(StepProblem& p, const BatchLayout& split, int flags, int shares) {
    m_shares = std::max(1, std::min(shares, kMaxShares));
    m_split = &split;
    m_hasJoints = p.numJointRows() > 0;
    if (m_hasJoints) setUpJoints(p, split);
    layOutLanes(laneSplit(), p.constraints.data(), p.regions, W, p.frictionRowsPerPoint(), m_shares, m_layout);
    setUpLaneRows(p, m_layout, m_rows);
    setUpBodyPerUnit(p, flags, m_rows.perUnit);
}

namespace {

// The rows stream from memory, a block read once a pass: a block asks for the one
// kRowsAhead blocks on, a line at a time, as lane_solve.h's BTOCL_PREFETCH_ROWS.
constexpr int kRowsAhead = 12;
BTOCL_LANES_INLINE void askForRowsAhead(const float* row) {
    const int blockFloats = BTOCL_LANE_ROW_FLOATS * W;
    const float* ahead = row + kRowsAhead * blockFloats;
    for (int line = 0; line < blockFloats; line += 16) __builtin_prefetch(ahead + line);
}

// lane_solve.h's btoclSolveLaneSlot, for every slot of one bundle. Returns whether a push pass
// changed any push impulse. pushSlots: the pass's part in noting the slots with a push share in
// slotPushes (btoclPushSlotsPart), as lane_solve.h's. Inlined into a build for each target below.
BTOCL_LANES_INLINE bool solveLaneBundle(const LaneLayout& layout, const LaneRows& lanes, float* applied,
                                        float* pushApplied, btoclBodyDelta* deltas, int pass, int pushSlots,
                                        unsigned char* slotPushes, int bundleIndex) {
    const int push = pass == BTOCL_PASS_PUSH, warmStart = pass == BTOCL_PASS_WARMSTART;
    const int perPoint = layout.frictionPerPoint;
    const int blockFloats = BTOCL_LANE_ROW_FLOATS * W;
    const float* rows = lanes.rows.data();
    const float* perUnit = lanes.perUnit.data();
    const btoclGroup& bundle = layout.bundles[size_t(bundleIndex)];
    LaneMask pushChanged{};
    for (int slot = bundle.offset; slot < bundle.offset + bundle.count; ++slot) {
        if (pushSlots == BTOCL_PUSH_SLOTS_SKIP && !slotPushes[slot]) continue;
        const btoclLaneSlot& s = layout.slots[size_t(slot)];
        const int* ints = layout.laneInts.data() + size_t(slot) * (BTOCL_LANE_INTS * W);
        const int* bodyA = ints + BTOCL_LANE_BODY_A * W;
        const int* bodyB = ints + BTOCL_LANE_BODY_B * W;
        const LaneMask numPoints = loadInts(ints + BTOCL_LANE_POINTS * W);
        // The next slot's bodies asked for: on two threads, a body the other thread moved last
        // comes from its core's cache, a wait the slot's solve hides.
        if (slot + 1 < bundle.offset + bundle.count) {
            const int* next = ints + BTOCL_LANE_INTS * W;  // its A bodies, then its B bodies
            for (int i = 0; i < 2 * W; ++i) {
                const int body = next[BTOCL_LANE_BODY_A * W + i];
                __builtin_prefetch(deltas + body);
                __builtin_prefetch(perUnit + size_t(body) * BTOCL_BODY_PER_UNIT_FLOATS);
            }
        }
        LaneBodies A = loadBodies(deltas, perUnit, bodyA, push, warmStart);
        LaneBodies B = loadBodies(deltas, perUnit, bodyB, push, warmStart);
        LaneMask pushes{};
        if (pass == BTOCL_PASS_FRICTION) {
            for (int k = 0; k < s.frictionBlocks; ++k) {
                const int block = s.frictionBlock + k;
                const float* row = rows + size_t(block) * blockFloats;
                askForRowsAhead(row);
                const Lanes total = load(applied + size_t(s.normalBlock + k / perPoint) * W);
                const Lanes limit = load(row + BTOCL_LANE_ROW_SHARED * W) * total;
                const LaneMask active = (numPoints * perPoint > k) & (total > 0.0f);
                solveRows(row, applied + size_t(block) * W, A, B, -limit, limit, 0, active);
            }
        } else {
            for (int k = 0; k < s.normalBlocks; ++k) {
                const int block = s.normalBlock + k;
                const float* row = rows + size_t(block) * blockFloats;
                askForRowsAhead(row);
                LaneMask active = numPoints > k;
                if (warmStart) {
                    applyImpulse(row, A, B, load(applied + size_t(block) * W), active, kContactComponentA,
                                 kContactComponentB);
                    if (pushSlots == BTOCL_PUSH_SLOTS_NOTE)
                        pushes |= active & (load(row + BTOCL_LANE_ROW_SHARED * W) != 0.0f);
                } else if (push) {
                    active &= load(row + BTOCL_LANE_ROW_SHARED * W) != 0.0f;  // no push share: skipped
                    pushes |= active;
                    pushChanged |= solveRows(row, pushApplied + size_t(block) * W, A, B, splat(0.0f),
                                             splat(BTOCL_FLT_MAX), 1, active);
                } else {
                    solveRows(row, applied + size_t(block) * W, A, B, splat(0.0f), splat(BTOCL_FLT_MAX), 0,
                              active);
                }
            }
        }
        storeBodies(deltas, bodyA, push, A);
        storeBodies(deltas, bodyB, push, B);
        if (pushSlots == BTOCL_PUSH_SLOTS_NOTE) slotPushes[slot] = anyLane(pushes);
    }
    return anyLane(pushChanged);
}

// The same operations either way, so the same bits (tests/test_lanes.cpp).
BTOCL_LANES_TARGET bool solveLaneBundleAvx2(const LaneLayout& layout, const LaneRows& lanes, float* applied,
                                            float* pushApplied, btoclBodyDelta* deltas, int pass, int pushSlots,
                                            unsigned char* slotPushes, int bundleIndex) {
    return solveLaneBundle(layout, lanes, applied, pushApplied, deltas, pass, pushSlots, slotPushes, bundleIndex);
}
BTOCL_LANES_WIDE_REGISTERS_TARGET bool solveLaneBundleWideRegisters(const LaneLayout& layout, const LaneRows& lanes,
                                                                    float* applied, float* pushApplied,
                                                                    btoclBodyDelta* deltas, int pass, int pushSlots,
                                                                    unsigned char* slotPushes, int bundleIndex) {
    return solveLaneBundle(layout, lanes, applied, pushApplied, deltas, pass, pushSlots, slotPushes, bundleIndex);
}

}  // namespace

size_t HostLaneSolve::slotsInVectors() const {
    return size_t(std::count(m_rows.inVectors.begin(), m_rows.inVectors.end(), 1));
}

bool HostLaneSolve::available() { return lanesAvailable(); }

int HostLaneSolve::solve(StepProblem& p, const btoclPassSchedule& passes, bool onPool) {
    const int numPasses = p.constraints.empty() ? 0 : btoclPassCount(passes);
    int iterations = 0;
    m_steps.clear();
    for (int i = 0; i < numPasses; ++i) {
        const btoclPassStep step = btoclPassAt(passes, i);
        for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
            const int first = m_layout.setBundleStart[size_t(set)], end = m_layout.setBundleStart[size_t(set) + 1];
            if (end > first)
                m_steps.push_back(
                    SetStep{step.pass, first, end, set, step.iteration, btoclPushSlotsPart(passes, step), false});
            // The set's joints after its contacts (a group's come after its contacts): in the
            // velocity passes alone, as the one-lane walk solves them.
            if (step.pass == BTOCL_PASS_NORMAL && m_hasJoints &&
                m_setJointRunStart[size_t(set) + 1] > m_setJointRunStart[size_t(set)])
                m_steps.push_back(SetStep{step.pass, 0, 0, set, step.iteration, BTOCL_PUSH_SLOTS_NONE, true});
        }
        if (step.endsIteration && step.pass != BTOCL_PASS_PUSH) ++iterations;
    }
    // A set's bundles share no dynamic body: thread i runs bundle i (its share) of every set, and
    // whichever thread runs a share, the bits are one thread's. The layout deals a set's groups
    // to its bundles by place, so a body mostly stays on one core from set to set.
    float* applied = m_rows.applied.data();
    float* pushApplied = m_rows.pushApplied.data();
    btoclBodyDelta* deltas = p.deltas.data();
    // SI ends its push iterations after one that changed no push impulse (its residual 0, at its
    // threshold): the rest would change nothing. Each share notes whether its bundles changed
    // one, and an iteration whose previous changed none passes (the notes are read once every
    // part of that iteration has run, so every thread passes alike). The same bits.
    m_pushChanged.assign(size_t(passes.pushIterations) * size_t(m_shares), 0);
    m_slotPushes.resize(m_layout.slots.size());
    const auto pushChangedIn = [&](int iteration) {
        for (int share = 0; share < m_shares; ++share)
            if (m_pushChanged[size_t(iteration) * size_t(m_shares) + size_t(share)]) return true;
        return false;
    };
    const auto solveBundle = lanesUseWideRegisters() ? solveLaneBundleWideRegisters : solveLaneBundleAvx2;
    shareSteps(int(m_steps.size()), m_shares, onPool, [&](int k, int share) {
        const SetStep& step = m_steps[size_t(k)];
        if (step.joints) {
            solveJointSlots(p, step, share);
            return;
        }
        const bool push = step.pass == BTOCL_PASS_PUSH;
        if (push && step.iteration > 0 && !pushChangedIn(step.iteration - 1)) return;
        bool changed = false;
        for (int b = step.firstBundle + share; b < step.endBundle; b += m_shares)
            changed |= solveBundle(m_layout, m_rows, applied, pushApplied, deltas, step.pass, step.pushSlots,
                                   m_slotPushes.data(), b);
        if (push && changed) m_pushChanged[size_t(step.iteration) * size_t(m_shares) + size_t(share)] = 1;
    });
    // Every row's impulse back in gather order, as the write-back reads them (a dense block has
    // 600K rows).
    const std::vector<int>& rowMap = m_layout.rowMap;
    resizeForOverwrite(p.appliedImpulses, rowMap.size());
    const size_t contactRows = m_hasJoints ? size_t(m_firstJointRow) : rowMap.size();
    parallelFor(contactRows, [&](size_t r) { p.appliedImpulses[r] = m_rows.applied[size_t(rowMap[r])]; });
    for (size_t r = contactRows; r < rowMap.size(); ++r)
        p.appliedImpulses[r] = m_jointApplied[size_t(m_jointRowMap[r - contactRows])];
    return iterations;
}

}  // namespace btocl
