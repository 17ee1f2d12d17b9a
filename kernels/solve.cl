// Projected Gauss-Seidel over batched constraint groups (Harada 2011, section 2.3).
// One launch solves one set for one pass: a work-group takes one group and walks its batches in
// order; constraints of a batch share no dynamic body, so its lanes run without conflicts, and
// groups of one set share none either. The row update is btSequentialImpulseConstraintSolver's.
// One kernel per pass, so that the compiler folds the pass's branches away.
#include "btOclShared.h"

inline float dot3(float4 a, float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Adds an impulse to a body's velocity change (or push/turn velocity for split impulse).
inline void applyImpulse(__global btoclBodyDelta* d, __global const btoclBody* b, float4 linear, float4 angular,
                         float impulse, int applyFactors, int push) {
    if (b->invMass.w == 0.0f) return;  // static and kinematic bodies never change
    float4 dl = linear * impulse;
    float4 da = angular * impulse;
    if (applyFactors) {
        dl *= b->linearFactor;
        da *= b->angularFactor;
    }
    if (push) {
        d->pushVelocity.xyz += dl.xyz;
        d->turnVelocity.xyz += da.xyz;
    } else {
        d->deltaLinearVelocity.xyz += dl.xyz;
        d->deltaAngularVelocity.xyz += da.xyz;
    }
}

// One row, clamped to [lower, upper]; returns the residual as SI reports it. The row is read
// only: its applied impulse lives in a compact array, so a pass writes 4 bytes per row, not a
// cache line.
inline float solveRow(__global const btoclRow* row, __global float* appliedImpulse, __global const btoclBody* bodies,
                      __global btoclBodyDelta* deltas, float lower, float upper, int applyFactors, int push) {
    __global btoclBodyDelta* dA = deltas + row->bodyA;
    __global btoclBodyDelta* dB = deltas + row->bodyB;
    __global const btoclBody* bA = bodies + row->bodyA;
    __global const btoclBody* bB = bodies + row->bodyB;
    const float jacDiagABInv = row->relpos2CrossNormal.w;
    const float cfm = row->contactNormal2.w;
    const float applied = *appliedImpulse;
    const float rhs = push ? row->relpos1CrossNormal.w : row->contactNormal1.w;
    float deltaImpulse = rhs - applied * cfm;
    const float4 vA0 = push ? dA->pushVelocity : dA->deltaLinearVelocity;
    const float4 wA0 = push ? dA->turnVelocity : dA->deltaAngularVelocity;
    const float4 vB0 = push ? dB->pushVelocity : dB->deltaLinearVelocity;
    const float4 wB0 = push ? dB->turnVelocity : dB->deltaAngularVelocity;
    const float deltaVel1Dotn = dot3(row->contactNormal1, vA0) + dot3(row->relpos1CrossNormal, wA0);
    const float deltaVel2Dotn = dot3(row->contactNormal2, vB0) + dot3(row->relpos2CrossNormal, wB0);
    deltaImpulse -= deltaVel1Dotn * jacDiagABInv;
    deltaImpulse -= deltaVel2Dotn * jacDiagABInv;
    const float sum = applied + deltaImpulse;
    float newApplied = sum;
    if (sum < lower) {
        deltaImpulse = lower - applied;
        newApplied = lower;
    } else if (sum > upper) {
        deltaImpulse = upper - applied;
        newApplied = upper;
    }
    *appliedImpulse = newApplied;
    applyImpulse(dA, bA, row->contactNormal1 * bA->invMass, row->angularComponentA, deltaImpulse, applyFactors, push);
    applyImpulse(dB, bB, row->contactNormal2 * bB->invMass, row->angularComponentB, deltaImpulse, applyFactors, push);
    return deltaImpulse * (1.0f / jacDiagABInv);
}

// The rows of one constraint for one pass; returns the largest squared residual.
inline float solveConstraintPass(__global const btoclConstraint* c, __global const btoclRow* rows,
                                 __global float* applied, __global float* pushApplied,
                                 __global const btoclBody* bodies, __global btoclBodyDelta* deltas, int pass,
                                 int applyFactors) {
    float maxResidual2 = 0.0f;
    if (pass == BTOCL_PASS_WARMSTART) {
        // SI applies each normal row's starting impulse to both bodies as it sets the row up.
        for (int r = c->firstRow[BTOCL_PASS_NORMAL]; r < c->firstRow[BTOCL_PASS_NORMAL] + c->numRows[BTOCL_PASS_NORMAL]; ++r) {
            __global const btoclRow* row = rows + r;
            const float start = applied[r];
            __global const btoclBody* bA = bodies + row->bodyA;
            __global const btoclBody* bB = bodies + row->bodyB;
            applyImpulse(deltas + row->bodyA, bA, row->contactNormal1 * bA->invMass, row->angularComponentA, start, 1, 0);
            applyImpulse(deltas + row->bodyB, bB, row->contactNormal2 * bB->invMass, row->angularComponentB, start, 1, 0);
        }
        return 0.0f;
    }
    const int rowPass = pass == BTOCL_PASS_PENETRATION ? BTOCL_PASS_NORMAL : pass;
    const int first = c->firstRow[rowPass];
    const int end = first + c->numRows[rowPass];
    for (int r = first; r < end; ++r) {
        __global const btoclRow* row = rows + r;
        float residual = 0.0f;
        if (pass == BTOCL_PASS_NORMAL) {
            residual = solveRow(row, applied + r, bodies, deltas, row->angularComponentA.w, FLT_MAX, applyFactors, 0);
        } else if (pass == BTOCL_PASS_PENETRATION) {
            if (row->relpos1CrossNormal.w == 0.0f) continue;  // no split-impulse share
            residual = solveRow(row, pushApplied + r, bodies, deltas, row->angularComponentA.w, FLT_MAX, applyFactors, 1);
        } else {
            const float total = applied[row->frictionIndex];
            if (!(total > 0.0f)) continue;
            float limit = row->impulses.z * total;
            if (pass == BTOCL_PASS_ROLLING && limit > row->impulses.z) limit = row->impulses.z;
            residual = solveRow(row, applied + r, bodies, deltas, -limit, limit, applyFactors, 0);
        }
        maxResidual2 = fmax(maxResidual2, residual * residual);
    }
    return maxResidual2;
}

// One set, one pass: work-group g solves group groups[groupBase + g], batch after batch. The
// constraints are in solve order already (kernels/arrange.cl): position i holds the i-th.
inline void solveSet(__global const btoclGroup* groups, int groupBase,
                     __global const int* batchEnd, __global const btoclConstraint* constraints,
                     __global const btoclRow* rows, __global float* applied, __global float* pushApplied,
                     __global const btoclBody* bodies, __global btoclBodyDelta* deltas, __global int* control,
                     const int pass, int flags) {
    const int stopSlot = pass == BTOCL_PASS_PENETRATION ? BTOCL_CONTROL_SPLIT_STOPPED : BTOCL_CONTROL_STOPPED;
    if (control[stopSlot]) return;  // the same for every work-item: converged in an earlier iteration
    // No row has a split-impulse share: the pass would change nothing (rows without one are skipped).
    if (pass == BTOCL_PASS_PENETRATION && !control[BTOCL_CONTROL_HAS_PENETRATION]) return;
    const btoclGroup g = groups[groupBase + get_group_id(0)];
    const int lane = get_local_id(0);
    const int lanes = get_local_size(0);
    const int applyFactors = flags & BTOCL_FLAG_APPLY_FACTORS;
    float maxResidual2 = 0.0f;
    int start = g.offset;
    for (int k = 0; k < g.numBatches; ++k) {
        const int end = batchEnd[g.offset + k];
        for (int i = start + lane; i < end; i += lanes)
            maxResidual2 = fmax(maxResidual2,
                                solveConstraintPass(constraints + i, rows, applied, pushApplied, bodies, deltas, pass,
                                                    applyFactors));
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
BTOCL_SOLVE_KERNEL(solveNormalRows, BTOCL_PASS_NORMAL)
BTOCL_SOLVE_KERNEL(solveFrictionRows, BTOCL_PASS_FRICTION)
BTOCL_SOLVE_KERNEL(solveRollingRows, BTOCL_PASS_ROLLING)
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
