// Projected Gauss-Seidel over batched constraint groups (Harada 2011, section 2.3). A work-group
// takes one group and walks its batches in order; constraints of a batch share no dynamic body,
// so its lanes run without conflicts, and groups of one set share none either. On the serial
// path a group is one batch and one lane walks it. The row update is
// btSequentialImpulseConstraintSolver's (kernels/row_solve.h, shared with the serial host
// reference, bullet_plugin/step/HostSolve.cpp).
//
// Three launch modes (StepMode, StepPlan.h), each walking the step's passes (btoclPassAt):
// - per set: one launch per set and pass, the groups of a set side by side (solveNormalRows, ...);
// - whole step: one group, every pass in one launch of one work-group (solveWholeStep), where a
//   launch costs more than solving the step's constraints;
// - claimed: every pass in one launch of a single-lane work-group per compute unit, which claim
//   each set's groups in turn (solveStepClaimed, the serial path's).
#include "btocl_shared.h"
#include "lane_solve.h"
#include "row_solve.h"

// The buffers of every solve kernel, first among its parameters and in this order
// (DeviceSolver::bindSolveBuffers sets them): the layout (groups, batch ends), what the rows read
// and write (btoclSolveBuffers), and the control block.
#define BTOCL_SOLVE_KERNEL_BUFFERS                                                                              \
    __global const btoclGroup *groups, __global const int *batchEnd, __global const btoclConstraint *constraints, \
        __global const btoclSolveRow *rows, __global const int *normalOfRow, __global float *applied,            \
        __global float *pushApplied, __global const btoclBody *bodies, __global btoclBodyDelta *deltas,          \
        __global int *control
// ... bundled at the kernel's entry.
#define BTOCL_SOLVE_BUFFERS_OF_PARAMS {constraints, rows, normalOfRow, applied, pushApplied, bodies, deltas}

// Batch k of group g, its constraints taken by `lanes` lanes from `lane` on, in a pass that
// shuffles its rows (row_solve.h): one lane walks the constraints shuffled where the pass shuffles
// them; several solve them side by side in any order (they share no dynamic body).
// groupSeed: btoclSeedOf(passSeed, g.offset), the seed of the group's orders.
inline float solveShuffledBatch(const btoclSolveBuffers* b, btoclGroup g, __global const int* batchEnd, int k, int lane,
                                int lanes, int pass, int flags, int iteration, int numIterations,
                                unsigned int groupSeed) {
    const int begin = k == 0 ? g.offset : batchEnd[g.offset + k - 1];
    const int end = batchEnd[g.offset + k];
    const unsigned int batchSeed = btoclSeedOf(groupSeed, k);
    const int oneLaneShuffles = lanes == 1 && btoclShuffledConstraints(pass, flags);
    float maxResidual2 = 0.0f;
    for (int j = lane; j < end - begin; j += lanes) {
        const int i = begin + btoclOrderAt(end - begin, oneLaneShuffles, batchSeed, j);
        maxResidual2 = fmax(maxResidual2, btoclSolveConstraint(b, b->constraints + i, pass, flags, iteration,
                                                               numIterations, btoclSeedOf(batchSeed, i)));
    }
    return maxResidual2;
}

// One group, one pass: batch after batch (a barrier between them, so the next batch reads what
// this one wrote), the lanes of the work-group sharing a batch. Where the pass shuffles its rows,
// the batches come in a shuffled order where it shuffles its constraints, and each batch as
// solveShuffledBatch walks it: a loop of its own, so that the fixed order's stays as PoCL
// compiled it (one loop for both made the wide path's solve slower). Returns this lane's largest
// squared residual. Every lane must call it: it holds barriers.
inline float solveCellGroup(const btoclSolveBuffers* b, btoclGroup g, __global const int* batchEnd, int pass, int flags,
                            int iteration, int numIterations, unsigned int passSeed) {
    const int lane = get_local_id(0);
    const int lanes = get_local_size(0);
    float maxResidual2 = 0.0f;
    if (btoclShuffledRows(pass, flags)) {  // uniform: every lane takes the same branch
        const unsigned int groupSeed = btoclSeedOf(passSeed, g.offset);
        const int shuffled = btoclShuffledConstraints(pass, flags);
        for (int kk = 0; kk < g.numBatches; ++kk) {
            maxResidual2 = fmax(maxResidual2, solveShuffledBatch(b, g, batchEnd,
                                                                 btoclOrderAt(g.numBatches, shuffled, groupSeed, kk),
                                                                 lane, lanes, pass, flags, iteration, numIterations,
                                                                 groupSeed));
            barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
        }
        return maxResidual2;
    }
    for (int k = 0; k < g.numBatches; ++k) {
        const int begin = k == 0 ? g.offset : batchEnd[g.offset + k - 1];
        const int end = batchEnd[g.offset + k];
        for (int i = begin + lane; i < end; i += lanes)
            maxResidual2 = fmax(maxResidual2,
                                btoclSolveConstraint(b, b->constraints + i, pass, flags, iteration, numIterations, 0u));
        barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
    }
    return maxResidual2;
}

// One set, one pass: work-group g solves group groups[groupBase + g].
inline void solveSet(const btoclSolveBuffers* b, __global const btoclGroup* groups, int groupBase,
                     __global const int* batchEnd, __global int* control, const int pass, int flags, int iteration,
                     int numIterations, unsigned int passSeed) {
    const int push = pass == BTOCL_PASS_PUSH;
    if (control[push ? BTOCL_CONTROL_PUSH_STOPPED : BTOCL_CONTROL_STOPPED]) return;  // uniform: converged
    const float maxResidual2 = solveCellGroup(b, groups[groupBase + get_group_id(0)], batchEnd, pass, flags, iteration,
                                              numIterations, passSeed);
    if ((flags & BTOCL_FLAG_TRACK_RESIDUAL) && maxResidual2 > 0.0f)
        // Non-negative floats order like their bit patterns: atomic_max is exact and order-free.
        atomic_max(control + (push ? BTOCL_CONTROL_PUSH_RESIDUAL : BTOCL_CONTROL_RESIDUAL), as_int(maxResidual2));
}

// One kernel per pass, so that the compiler folds the pass's branches away. iteration: the
// iteration of this pass, of which contact rows take part in the first numIterations (joints
// with a larger override count go on; kernels/row_solve.h). passSeed: btoclPassSeed's.
#define BTOCL_SOLVE_SET_KERNEL(name, PASS)                                                                  \
    __kernel void name(BTOCL_SOLVE_KERNEL_BUFFERS, int groupBase, int flags, int iteration, int numIterations, \
                       uint passSeed) {                                                                     \
        const btoclSolveBuffers b = BTOCL_SOLVE_BUFFERS_OF_PARAMS;                                          \
        solveSet(&b, groups, groupBase, batchEnd, control, PASS, flags, iteration, numIterations, passSeed); \
    }
BTOCL_SOLVE_SET_KERNEL(applyWarmStart, BTOCL_PASS_WARMSTART)
BTOCL_SOLVE_SET_KERNEL(solvePushRows, BTOCL_PASS_PUSH)
BTOCL_SOLVE_SET_KERNEL(solveNormalRows, BTOCL_PASS_NORMAL)
BTOCL_SOLVE_SET_KERNEL(solveFrictionRows, BTOCL_PASS_FRICTION)

// After each iteration of the per-set launches when a residual threshold is set: stop once the
// iteration's residual is small enough.
__kernel void endIteration(__global int* control, float threshold, int push) {
    const int stopSlot = push ? BTOCL_CONTROL_PUSH_STOPPED : BTOCL_CONTROL_STOPPED;
    const int residualSlot = push ? BTOCL_CONTROL_PUSH_RESIDUAL : BTOCL_CONTROL_RESIDUAL;
    if (control[stopSlot]) return;
    if (!push) control[BTOCL_CONTROL_ITERATIONS] += 1;
    if (as_float(control[residualSlot]) <= threshold) control[stopSlot] = 1;
    control[residualSlot] = 0;
}

// Every group of one pass, in order (one work-group); returns this lane's largest squared residual.
inline float solveAllGroups(const btoclSolveBuffers* b, __global const btoclGroup* groups, int numGroups,
                            __global const int* batchEnd, int pass, int flags, int iteration, int numIterations,
                            unsigned int passSeed) {
    float maxResidual2 = 0.0f;
    for (int g = 0; g < numGroups; ++g)
        maxResidual2 = fmax(maxResidual2,
                            solveCellGroup(b, groups[g], batchEnd, pass, flags, iteration, numIterations, passSeed));
    return maxResidual2;
}

// The work-group's largest residual of an iteration, the same in every lane: did it converge?
inline int iterationConverged(__local int* groupResidual, float laneResidual2, float threshold) {
    atomic_max(groupResidual, as_int(laneResidual2));
    barrier(CLK_LOCAL_MEM_FENCE);
    const int converged = as_float(*groupResidual) <= threshold;
    barrier(CLK_LOCAL_MEM_FENCE);  // every lane has read it before it is cleared
    if (get_local_id(0) == 0) *groupResidual = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    return converged;
}

// The pass as a constant in each call, so that the compiler folds its branches away.
#define BTOCL_BY_PASS(pass, CALL)                                \
    ((pass) == BTOCL_PASS_NORMAL     ? CALL(BTOCL_PASS_NORMAL)   \
     : (pass) == BTOCL_PASS_FRICTION ? CALL(BTOCL_PASS_FRICTION) \
     : (pass) == BTOCL_PASS_PUSH     ? CALL(BTOCL_PASS_PUSH)     \
                                     : CALL(BTOCL_PASS_WARMSTART))

// A whole step in one launch of one work-group: the passes of the schedule in turn, an iteration
// of push or velocity passes ending that kind early once its residual is under the threshold
// (when one is set). Leaves the velocity iterations run in control[BTOCL_CONTROL_ITERATIONS].
__kernel void solveWholeStep(BTOCL_SOLVE_KERNEL_BUFFERS, int numGroups, int flags, float threshold,
                             btoclPassSchedule schedule) {
    const btoclSolveBuffers b = BTOCL_SOLVE_BUFFERS_OF_PARAMS;
    __local int groupResidual;
    if (get_local_id(0) == 0) groupResidual = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    const int track = flags & BTOCL_FLAG_TRACK_RESIDUAL;
    const int numPasses = btoclPassCount(schedule);
    int iterations = 0;
    float residual2 = 0.0f;
    for (int i = 0; i < numPasses; ++i) {
        const btoclPassStep p = btoclPassAt(schedule, i);
        const unsigned int passSeed = btoclPassSeed(schedule, i);
#define BTOCL_SOLVE_ALL(PASS) \
    solveAllGroups(&b, groups, numGroups, batchEnd, PASS, flags, p.iteration, schedule.numIterations, passSeed)
        residual2 = fmax(residual2, BTOCL_BY_PASS(p.pass, BTOCL_SOLVE_ALL));
#undef BTOCL_SOLVE_ALL
        if (!p.endsIteration) continue;
        if (p.pass != BTOCL_PASS_PUSH) ++iterations;
        if (track && iterationConverged(&groupResidual, residual2, threshold)) {
            if (p.pass != BTOCL_PASS_PUSH) break;
            i = btoclFirstVelocityPass(schedule) - 1;  // the push iterations have converged
        }
        residual2 = 0.0f;
    }
    if (get_local_id(0) == 0) control[BTOCL_CONTROL_ITERATIONS] = iterations;
}

// On a CPU (BTOCL_PREFETCHES) the bodies of the constraint a few ahead are asked for: they lie
// scattered over more than the cores' caches hold, and the loads at a constraint's start waited
// for them (4 ahead measured best; docs/performance.md).
#define BTOCL_PREFETCH_AHEAD (BTOCL_PREFETCHES ? 4 : 0)

// One group, one pass, one lane: its batches one after another are its constraints in order
// (where the pass shuffles anything, in the orders solveCellGroup walks with one lane).
BTOCL_SOLVE_INLINE float solveCellGroupOneLane(const btoclSolveBuffers* b, btoclGroup g, __global const int* batchEnd,
                                               int pass, int flags, int iteration, int numIterations,
                                               unsigned int passSeed) {
    float maxResidual2 = 0.0f;
    if (btoclShuffledRows(pass, flags)) {
        const unsigned int groupSeed = btoclSeedOf(passSeed, g.offset);
        const int shuffled = btoclShuffledConstraints(pass, flags);
        for (int kk = 0; kk < g.numBatches; ++kk)
            maxResidual2 = fmax(maxResidual2, solveShuffledBatch(b, g, batchEnd,
                                                                 btoclOrderAt(g.numBatches, shuffled, groupSeed, kk), 0,
                                                                 1, pass, flags, iteration, numIterations, groupSeed));
        return maxResidual2;
    }
    for (int i = g.offset; i < g.offset + g.count; ++i) {
        if (BTOCL_PREFETCH_AHEAD > 0 && i + BTOCL_PREFETCH_AHEAD < g.offset + g.count) {
            const btoclConstraint ahead = b->constraints[i + BTOCL_PREFETCH_AHEAD];
            BTOCL_PREFETCH(b->bodies + ahead.bodyA);
            BTOCL_PREFETCH(b->deltas + ahead.bodyA);
            BTOCL_PREFETCH(b->bodies + ahead.bodyB);
            BTOCL_PREFETCH(b->deltas + ahead.bodyB);
        }
        maxResidual2 =
            fmax(maxResidual2, btoclSolveConstraint(b, b->constraints + i, pass, flags, iteration, numIterations, 0u));
    }
    return maxResidual2;
}

// The groups of one set are split into one contiguous range per work-group. A work-group takes
// the groups of its own range first, then what is left of the others' (a unit that is late or
// busy elsewhere holds nothing up). Its own range covers about the same cells in every set and
// pass, so the bodies it writes stay in its core's cache (one shared counter instead scattered
// them over the cores; docs/performance.md).
inline int2 claimRange(int first, int count, int range, int numRanges) {
    return (int2)(first + (int)((long)count * range / numRanges), first + (int)((long)count * (range + 1) / numRanges));
}

// Groups finished so far by every work-group.
inline int finishedGroups(__global int* progress, int numRanges) {
    int sum = 0;
    for (int w = 0; w < numRanges; ++w) sum += *(volatile __global int*)(progress + w * BTOCL_PROGRESS_LINE);
    return sum;
}

// A whole step in one launch of a few single-lane work-groups (one per compute unit: the serial
// path). Set after set of every pass, the work-groups take the set's groups from claim
// counters, and none starts a set before every group of the sets before has finished (the sum
// of their counts of finished groups): groups of one set share no dynamic body, so they run side
// by side, and a set sees everything the sets before it wrote. The result is that of one launch
// per set and pass, without the launches (about a hundred a step, each a fixed cost on PoCL).
// It cannot deadlock, however few work-groups the device runs at once: a work-group waits only
// once it has found every group of the set taken, and a group is taken only by a running
// work-group, which finishes it without waiting on anything (one that never starts takes none).
// setGroupStart: BTOCL_NUM_SETS + 2 ints, read here so that the host need not wait for the
// split. progress: btoclProgressSize ints, laid out as btocl_shared.h says, all zero (a single
// work-group clears them itself).
// With `lb` (a step in lanes, solveStepInLanes), the groups are bundles and each is solved in
// lanes (kernels/lane_solve.h); `numConstraints` then counts slots. lanes: a constant at each call,
// so that each kernel keeps its own walk alone.
BTOCL_SOLVE_INLINE void claimedStep(const btoclSolveBuffers* bp, const btoclLaneBuffers* lb, const int lanes,
                                    __global const btoclGroup* groups, __global const int* batchEnd,
                                    __global int* control, __global const int* setGroupStart, __global int* progress,
                                    int numConstraints, int flags, float threshold, btoclPassSchedule schedule) {
    const btoclSolveBuffers b = *bp;
    int setStart[BTOCL_NUM_SETS + 2];
    for (int s = 0; s < BTOCL_NUM_SETS + 2; ++s) setStart[s] = setGroupStart[s];
    const int numGroups = setStart[BTOCL_NUM_SETS + 1];
    // Groups taken by one claim (an atomic add on a counter the others may touch): about 64
    // constraints' worth (groups hold from about 15 constraints to a few hundred).
    const int groupsPerClaim = max(1, 64 / max(1, numConstraints / max(1, numGroups)));
    const int self = get_group_id(0), numRanges = get_num_groups(0);
    const int track = flags & BTOCL_FLAG_TRACK_RESIDUAL;
    const int numPasses = btoclPassCount(schedule);
    __global int* finished = progress + self * BTOCL_PROGRESS_LINE;
    __global int* residuals = progress + btoclProgressResiduals(numRanges);
    __global int* claims = progress + btoclProgressClaims(numRanges, schedule.pushIterations, schedule.maxIterations);
    const int claimsPerGroup = btoclProgressClaimsPerGroup(numPasses);
    if (numRanges == 1)  // a whole step: the block is this work-group's alone, and not cleared by the host
        for (int k = btoclProgressSize(1, numPasses, schedule.pushIterations, schedule.maxIterations) - 1; k >= 0; --k)
            progress[k] = 0;
    int finishedHere = 0, iterationsRun = schedule.maxIterations;
    for (int passIndex = 0; passIndex < numPasses; ++passIndex) {
        const btoclPassStep p = btoclPassAt(schedule, passIndex);
        const unsigned int passSeed = btoclPassSeed(schedule, passIndex);
        for (int set = 0; set <= BTOCL_OVERFLOW_SET; ++set) {
            const int first = setStart[set], count = setStart[set + 1] - first;
            if (count == 0) continue;
            while (finishedGroups(progress, numRanges) < passIndex * numGroups + first) {
            }
            mem_fence(CLK_GLOBAL_MEM_FENCE);  // what the sets before wrote, read after their counts
            // Every group of the iteration before has finished: its residual is final. A converged
            // iteration stops its loop; the iterations after it stay at 0, so they read as
            // converged. Their groups are still taken and counted, so the counts stay whole.
            const int previousConverged = track && p.residual >= 0 && p.iteration > 0 &&
                                          as_float(atomic_or(residuals + p.residual - 1, 0)) <= threshold;
            if (previousConverged && p.pass != BTOCL_PASS_PUSH) iterationsRun = min(iterationsRun, p.iteration);
            const int solve = !previousConverged;
            for (int k = 0; k < numRanges; ++k) {
                const int range = self + k < numRanges ? self + k : self + k - numRanges;
                const int2 r = claimRange(first, count, range, numRanges);
                __global int* counter = claims + range * claimsPerGroup + passIndex * (BTOCL_OVERFLOW_SET + 1) + set;
                for (int claimed = r.x + atomic_add(counter, groupsPerClaim); claimed < r.y;
                     claimed = r.x + atomic_add(counter, groupsPerClaim))
                    for (int group = claimed; group < min(claimed + groupsPerClaim, r.y); ++group) {
                        if (solve) {
                            const btoclGroup g = groups[group];
#if defined(BTOCL_LANES) && BTOCL_LANES > 1
#define BTOCL_SOLVE_CLAIMED(PASS)                                                                         \
    (lanes > 1 ? btoclSolveLaneBundle(&b, lb, g, PASS, btoclPushSlotsPart(schedule, p))                  \
               : solveCellGroupOneLane(&b, g, batchEnd, PASS, flags, p.iteration, schedule.numIterations, \
                                       passSeed))
#else
#define BTOCL_SOLVE_CLAIMED(PASS) \
    solveCellGroupOneLane(&b, g, batchEnd, PASS, flags, p.iteration, schedule.numIterations, passSeed)
#endif
                            const float groupResidual2 = BTOCL_BY_PASS(p.pass, BTOCL_SOLVE_CLAIMED);
#undef BTOCL_SOLVE_CLAIMED
                            // Before the group counts as finished: whoever sees it finished sees this.
                            if (track && p.residual >= 0 && groupResidual2 > 0.0f)
                                atomic_max(residuals + p.residual, as_int(groupResidual2));
                        }
                        ++finishedHere;
                    }
            }
            // Every group of the set is taken, and those taken here are finished: published once
            // a set (a count written for each group would bounce its cache line between the
            // cores as the others read it).
            mem_fence(CLK_GLOBAL_MEM_FENCE);  // this work-group's writes, before its count
            *(volatile __global int*)finished = finishedHere;
        }
    }
    // Every work-group saw the same residuals at the same places, so any one can tell.
    if (self == 0) control[BTOCL_CONTROL_ITERATIONS] = iterationsRun;
}

__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void solveStepClaimed(
    BTOCL_SOLVE_KERNEL_BUFFERS, __global const int* setGroupStart, __global int* progress, int numConstraints, int flags,
    float threshold, btoclPassSchedule schedule) {
    const btoclSolveBuffers b = BTOCL_SOLVE_BUFFERS_OF_PARAMS;
    claimedStep(&b, 0, 1, groups, batchEnd, control, setGroupStart, progress, numConstraints, flags, threshold,
                schedule);
}

#if defined(BTOCL_LANES) && BTOCL_LANES > 1
// A step in lanes (a CPU's vector unit; kernels/lane_solve.h), claimed as solveStepClaimed claims
// groups: `groups` are the bundles, setGroupStart the sets' bundles, numSlots every bundle's
// slots. The warm start and every pass of a step that the lanes take (StepPolicy.cpp: contact
// rows alone, in a fixed order). Of the solve buffers, rows, normalOfRow (a friction row's normal
// is at its place / frictionPerPoint), constraints and batchEnd go unread. slotPushes: an int a
// slot, written by the warm start or the first push pass, read by the push passes after it
// (btoclPushSlotsPart).
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void solveStepInLanes(
    BTOCL_SOLVE_KERNEL_BUFFERS, __global const int* setGroupStart, __global int* progress, int numSlots, int flags,
    float threshold, btoclPassSchedule schedule, __global const btoclLaneSlot* slots, __global const int* lanes,
    __global const float* bodyPerUnit, __global const float* wideRows, int frictionPerPoint,
    __global int* slotPushes) {
    const btoclSolveBuffers b = BTOCL_SOLVE_BUFFERS_OF_PARAMS;
    const btoclLaneBuffers lb = {slots, lanes, bodyPerUnit, wideRows, slotPushes, frictionPerPoint};
    claimedStep(&b, &lb, BTOCL_LANES, groups, batchEnd, control, setGroupStart, progress, numSlots, flags, threshold,
                schedule);
}
#endif
