// Projected Gauss-Seidel over batched constraint groups (Harada 2011, section 2.3).
// One launch solves one set for one pass: a work-group takes one group and walks its batches in
// order; constraints of a batch share no dynamic body, so its lanes run without conflicts, and
// groups of one set share none either. The row update is btSequentialImpulseConstraintSolver's
// (kernels/row_solve.h, shared with the serial host reference). One kernel per pass, so that the
// compiler folds the pass's branches away.
#include "btocl_shared.h"
#include "row_solve.h"

// One set, one pass: work-group g solves group groups[groupBase + g], batch after batch. The
// constraints are in solve order already (kernels/arrange.cl): position i holds the i-th.
inline void solveSet(__global const btoclGroup* groups, int groupBase,
                     __global const int* batchEnd, __global const btoclConstraint* constraints,
                     __global const btoclRow* rows, __global float* applied, __global float* pushApplied,
                     __global const btoclBody* bodies, __global btoclBodyDelta* deltas, __global int* control,
                     const int pass, int flags) {
    const int stopSlot = pass == BTOCL_PASS_PENETRATION ? BTOCL_CONTROL_SPLIT_STOPPED : BTOCL_CONTROL_STOPPED;
    if (control[stopSlot]) return;  // the same for every work-item: converged in an earlier iteration
    const btoclGroup g = groups[groupBase + get_group_id(0)];
    const int lane = get_local_id(0);
    const int lanes = get_local_size(0);
    const int applyFactors = flags & BTOCL_FLAG_APPLY_FACTORS;
    // No joint rows reach the device yet and every launch is one of the step's m_numIterations,
    // so each runs as iteration 0 of 1; with joints the launch will pass its iteration.
    const int iteration = 0, numIterations = 1;
    float maxResidual2 = 0.0f;
    int start = g.offset;
    for (int k = 0; k < g.numBatches; ++k) {
        const int end = batchEnd[g.offset + k];
        for (int i = start + lane; i < end; i += lanes)
            maxResidual2 = fmax(maxResidual2,
                                btoclSolveConstraint(constraints + i, rows, applied, pushApplied, bodies, deltas, pass,
                                                     applyFactors, iteration, numIterations));
        barrier(CLK_GLOBAL_MEM_FENCE);  // the next batch reads what this one wrote
        start = end;
    }
    if ((flags & BTOCL_FLAG_TRACK_RESIDUAL) && maxResidual2 > 0.0f) {
        // Non-negative floats order like their bit patterns: atomic_max is exact and order-free.
        const int slot = pass == BTOCL_PASS_PENETRATION ? BTOCL_CONTROL_SPLIT_RESIDUAL : BTOCL_CONTROL_RESIDUAL;
        atomic_max(control + slot, as_int(maxResidual2));
    }
}

#define BTOCL_SOLVE_KERNEL(name, PASS)                                                                          \
    __kernel void name(__global const btoclGroup* groups, int groupBase,                                      \
                       __global const int* batchEnd, __global const btoclConstraint* constraints,             \
                       __global const btoclRow* rows, __global float* applied, __global float* pushApplied,   \
                       __global const btoclBody* bodies, __global btoclBodyDelta* deltas,                     \
                       __global int* control, int flags) {                                                    \
        solveSet(groups, groupBase, batchEnd, constraints, rows, applied, pushApplied, bodies, deltas, control,  \
                 PASS, flags);                                                                                \
    }
BTOCL_SOLVE_KERNEL(solveVelocityRows, BTOCL_PASS_VELOCITY)
BTOCL_SOLVE_KERNEL(solvePenetrationRows, BTOCL_PASS_PENETRATION)
BTOCL_SOLVE_KERNEL(applyWarmStart, BTOCL_PASS_WARMSTART)

// After each iteration when a residual threshold is set: stop once the residual is small enough.
__kernel void endIteration(__global int* control, float threshold, int split) {
    const int stopSlot = split ? BTOCL_CONTROL_SPLIT_STOPPED : BTOCL_CONTROL_STOPPED;
    const int residualSlot = split ? BTOCL_CONTROL_SPLIT_RESIDUAL : BTOCL_CONTROL_RESIDUAL;
    if (control[stopSlot]) return;
    if (!split) control[BTOCL_CONTROL_ITERATIONS] += 1;
    if (as_float(control[residualSlot]) <= threshold) control[stopSlot] = 1;
    control[residualSlot] = 0;
}
