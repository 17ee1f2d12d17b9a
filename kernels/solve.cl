// Projected Gauss-Seidel over batched constraint groups (Harada 2011, section 2.3). A work-group
// takes one group and walks its batches in order; constraints of a batch share no dynamic body,
// so its lanes run without conflicts, and groups of one set share none either. On the serial
// path a group is one batch and one lane walks it. The row update is
// btSequentialImpulseConstraintSolver's (kernels/row_solve.h, shared with the serial host
// reference, bullet_plugin/reference/HostSolver.cpp).
//
// Two ways to launch: a step with many groups launches one kernel per set and pass (all groups of
// a set at once); a small step (one group) runs whole in solveWholeStep, every pass and iteration
// in one launch, since a launch costs more than solving a few hundred constraints.
#include "btocl_shared.h"
#include "row_solve.h"

// One group, one pass: batch after batch (a barrier between them, so the next batch reads what
// this one wrote), the lanes of the work-group sharing a batch. Returns this lane's largest
// squared residual. Every lane must call it: it holds barriers.
inline float solveGroup(btoclGroup g, __global const int* batchEnd, __global const btoclConstraint* constraints,
                        __global const btoclSolveRow* rows, __global const int* normalOfRow, __global float* applied,
                        __global float* pushApplied, __global const btoclBody* bodies, __global btoclBodyDelta* deltas,
                        int pass, int flags, int iteration, int numIterations) {
    const int lane = get_local_id(0);
    const int lanes = get_local_size(0);
    float maxResidual2 = 0.0f;
    for (int k = 0; k < g.numBatches; ++k) {
        const int begin = k == 0 ? g.offset : batchEnd[g.offset + k - 1];
        const int end = batchEnd[g.offset + k];
        for (int i = begin + lane; i < end; i += lanes)
            maxResidual2 = fmax(maxResidual2, btoclSolveConstraint(constraints + i, rows, normalOfRow, applied,
                                                                    pushApplied, bodies, deltas, pass, flags, iteration,
                                                                    numIterations));
        barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
    }
    return maxResidual2;
}

// One set, one pass: work-group g solves group groups[groupBase + g].
inline void solveSet(__global const btoclGroup* groups, int groupBase, __global const int* batchEnd,
                     __global const btoclConstraint* constraints, __global const btoclSolveRow* rows,
                     __global const int* normalOfRow, __global float* applied, __global float* pushApplied,
                     __global const btoclBody* bodies, __global btoclBodyDelta* deltas, __global int* control,
                     const int pass, int flags, int iteration, int numIterations) {
    const int split = pass == BTOCL_PASS_PENETRATION;
    if (control[split ? BTOCL_CONTROL_SPLIT_STOPPED : BTOCL_CONTROL_STOPPED]) return;  // uniform: converged
    const float maxResidual2 = solveGroup(groups[groupBase + get_group_id(0)], batchEnd, constraints, rows, normalOfRow,
                                          applied, pushApplied, bodies, deltas, pass, flags, iteration, numIterations);
    if ((flags & BTOCL_FLAG_TRACK_RESIDUAL) && maxResidual2 > 0.0f)
        // Non-negative floats order like their bit patterns: atomic_max is exact and order-free.
        atomic_max(control + (split ? BTOCL_CONTROL_SPLIT_RESIDUAL : BTOCL_CONTROL_RESIDUAL), as_int(maxResidual2));
}

// One kernel per pass, so that the compiler folds the pass's branches away. iteration: the
// iteration of this pass, of which contact rows take part in the first numIterations (joints
// with a larger override count go on; kernels/row_solve.h).
#define BTOCL_SOLVE_SET_KERNEL(name, PASS)                                                                      \
    __kernel void name(__global const btoclGroup* groups, int groupBase, __global const int* batchEnd,       \
                       __global const btoclConstraint* constraints, __global const btoclSolveRow* rows,    \
                       __global const int* normalOfRow, __global float* applied, __global float* pushApplied, \
                       __global const btoclBody* bodies, __global btoclBodyDelta* deltas,                   \
                       __global int* control, int flags, int iteration, int numIterations) {               \
        solveSet(groups, groupBase, batchEnd, constraints, rows, normalOfRow, applied, pushApplied, bodies,  \
                 deltas, control, PASS, flags, iteration, numIterations);                                    \
    }
BTOCL_SOLVE_SET_KERNEL(applyWarmStart, BTOCL_PASS_WARMSTART)
BTOCL_SOLVE_SET_KERNEL(solvePenetrationRows, BTOCL_PASS_PENETRATION)
BTOCL_SOLVE_SET_KERNEL(solveNormalRows, BTOCL_PASS_NORMAL)
BTOCL_SOLVE_SET_KERNEL(solveFrictionRows, BTOCL_PASS_FRICTION)

// After each iteration of the per-set launches when a residual threshold is set: stop once the
// iteration's residual is small enough.
__kernel void endIteration(__global int* control, float threshold, int split) {
    const int stopSlot = split ? BTOCL_CONTROL_SPLIT_STOPPED : BTOCL_CONTROL_STOPPED;
    const int residualSlot = split ? BTOCL_CONTROL_SPLIT_RESIDUAL : BTOCL_CONTROL_RESIDUAL;
    if (control[stopSlot]) return;
    if (!split) control[BTOCL_CONTROL_ITERATIONS] += 1;
    if (as_float(control[residualSlot]) <= threshold) control[stopSlot] = 1;
    control[residualSlot] = 0;
}

// Every group of one pass, in order (one work-group); returns this lane's largest squared residual.
inline float solveAllGroups(__global const btoclGroup* groups, int numGroups, __global const int* batchEnd,
                            __global const btoclConstraint* constraints, __global const btoclSolveRow* rows,
                            __global const int* normalOfRow, __global float* applied, __global float* pushApplied,
                            __global const btoclBody* bodies, __global btoclBodyDelta* deltas, int pass, int flags,
                            int iteration, int numIterations) {
    float maxResidual2 = 0.0f;
    for (int g = 0; g < numGroups; ++g)
        maxResidual2 = fmax(maxResidual2, solveGroup(groups[g], batchEnd, constraints, rows, normalOfRow, applied,
                                                     pushApplied, bodies, deltas, pass, flags, iteration, numIterations));
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

// A whole step in one launch of one work-group: the warm start, the split-impulse iterations
// (when some row has a share: control[BTOCL_CONTROL_HAS_PENETRATION]), then the velocity
// iterations (maxIterations: m_numIterations, or more for joints that ask for more), each stopped
// on the device by the residual threshold when one is set. Leaves the velocity iterations run in
// control[BTOCL_CONTROL_ITERATIONS].
__kernel void solveWholeStep(__global const btoclGroup* groups, int numGroups, __global const int* batchEnd,
                             __global const btoclConstraint* constraints, __global const btoclSolveRow* rows,
                             __global const int* normalOfRow, __global float* applied, __global float* pushApplied,
                             __global const btoclBody* bodies, __global btoclBodyDelta* deltas, __global int* control,
                             int flags, int numIterations, int maxIterations, float threshold, int warmStart,
                             int splitImpulse) {
    __local int groupResidual;
    if (get_local_id(0) == 0) groupResidual = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    const int track = flags & BTOCL_FLAG_TRACK_RESIDUAL;
    if (warmStart)
        solveAllGroups(groups, numGroups, batchEnd, constraints, rows, normalOfRow, applied, pushApplied, bodies,
                       deltas, BTOCL_PASS_WARMSTART, flags, 0, numIterations);
    if (splitImpulse && control[BTOCL_CONTROL_HAS_PENETRATION])
        for (int it = 0; it < numIterations; ++it) {
            const float r = solveAllGroups(groups, numGroups, batchEnd, constraints, rows, normalOfRow, applied,
                                           pushApplied, bodies, deltas, BTOCL_PASS_PENETRATION, flags, it,
                                           numIterations);
            if (track && iterationConverged(&groupResidual, r, threshold)) break;
        }
    int iterations = 0;
    for (int it = 0; it < maxIterations; ++it) {
        float r = solveAllGroups(groups, numGroups, batchEnd, constraints, rows, normalOfRow, applied, pushApplied,
                                 bodies, deltas, BTOCL_PASS_NORMAL, flags, it, numIterations);
        r = fmax(r, solveAllGroups(groups, numGroups, batchEnd, constraints, rows, normalOfRow, applied, pushApplied,
                                   bodies, deltas, BTOCL_PASS_FRICTION, flags, it, numIterations));
        ++iterations;
        if (track && iterationConverged(&groupResidual, r, threshold)) break;
    }
    if (get_local_id(0) == 0) control[BTOCL_CONTROL_ITERATIONS] = iterations;
}
