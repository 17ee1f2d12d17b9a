// Projected Gauss-Seidel over batched constraint groups (Harada 2011, section 2.3).
// One launch solves one set for one pass: a work-group takes one group and walks its batches in
// order; constraints of a batch share no dynamic body, so its lanes run without conflicts, and
// groups of one set share none either. The row update is btSequentialImpulseConstraintSolver's.
// One kernel per pass, so that the compiler folds the pass's branches away.
#include "btocl_shared.h"

inline float dot3(float4 a, float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// A body's part in one constraint: read once, updated by each of the constraint's rows (they all
// act on the same two bodies), written back once.
typedef struct {
    float4 invMass;        // xyz: inverse mass times linear factor; w: 1 if dynamic
    float4 linearFactor, angularFactor;
    float4 linear, angular;  // velocity change, or push and turn velocity in the split-impulse pass
} SolveBody;

inline SolveBody loadBody(__global const btoclBody* b, __global const btoclBodyDelta* d, int push) {
    SolveBody s;
    s.invMass = b->invMass;
    s.linearFactor = b->linearFactor;
    s.angularFactor = b->angularFactor;
    s.linear = push ? d->pushVelocity : d->deltaLinearVelocity;
    s.angular = push ? d->turnVelocity : d->deltaAngularVelocity;
    return s;
}

inline void storeBody(const SolveBody* s, __global btoclBodyDelta* d, int push) {
    if (BTOCL_BODY_IS_DYNAMIC(*s) == 0.0f) return;  // static and kinematic bodies never change
    if (push) {
        d->pushVelocity = s->linear;
        d->turnVelocity = s->angular;
    } else {
        d->deltaLinearVelocity = s->linear;
        d->deltaAngularVelocity = s->angular;
    }
}

// Adds an impulse to a body's velocity change (btSolverBody::internalApplyImpulse).
inline void applyImpulse(SolveBody* s, float4 linear, float4 angular, float impulse, int applyFactors) {
    if (BTOCL_BODY_IS_DYNAMIC(*s) == 0.0f) return;
    float4 dl = linear * impulse;
    float4 da = angular * impulse;
    if (applyFactors) {
        dl *= s->linearFactor;
        da *= s->angularFactor;
    }
    s->linear.xyz += dl.xyz;
    s->angular.xyz += da.xyz;
}

// One row, clamped to [lower, upper]; returns the residual as SI reports it. The row is read
// only: its applied impulse lives in a compact array, so a pass writes 4 bytes per row, not a
// cache line.
inline float solveRow(__global const btoclRow* row, __global float* appliedImpulse, SolveBody* A, SolveBody* B,
                      float lower, float upper, int applyFactors, int push) {
    const float jacDiagABInv = BTOCL_ROW_JAC_DIAG_INV(*row);
    const float cfm = BTOCL_ROW_CFM(*row);
    const float applied = *appliedImpulse;
    const float rhs = push ? BTOCL_ROW_RHS_PENETRATION(*row) : BTOCL_ROW_RHS(*row);
    float deltaImpulse = rhs - applied * cfm;
    const float deltaVel1Dotn = dot3(row->contactNormal1, A->linear) + dot3(row->relpos1CrossNormal, A->angular);
    const float deltaVel2Dotn = dot3(row->contactNormal2, B->linear) + dot3(row->relpos2CrossNormal, B->angular);
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
    applyImpulse(A, row->contactNormal1 * A->invMass, row->angularComponentA, deltaImpulse, applyFactors);
    applyImpulse(B, row->contactNormal2 * B->invMass, row->angularComponentB, deltaImpulse, applyFactors);
    return deltaImpulse * (1.0f / jacDiagABInv);
}

// Friction and rolling rows: the limit follows the normal row's impulse of this iteration.
inline float solveFrictionRows(__global const btoclConstraint* c, int kind, __global const btoclRow* rows,
                               __global float* applied, SolveBody* A, SolveBody* B, int applyFactors) {
    float maxResidual2 = 0.0f;
    for (int r = c->firstRow[kind]; r < c->firstRow[kind] + c->numRows[kind]; ++r) {
        __global const btoclRow* row = rows + r;
        const float total = applied[row->frictionIndex];
        if (!(total > 0.0f)) continue;
        float limit = BTOCL_ROW_FRICTION(*row) * total;
        if (kind == BTOCL_ROWS_ROLLING && limit > BTOCL_ROW_FRICTION(*row)) limit = BTOCL_ROW_FRICTION(*row);
        const float residual = solveRow(row, applied + r, A, B, -limit, limit, applyFactors, 0);
        maxResidual2 = fmax(maxResidual2, residual * residual);
    }
    return maxResidual2;
}

// The rows of one constraint for one pass; returns the largest squared residual.
inline float solveConstraintPass(__global const btoclConstraint* c, __global const btoclRow* rows,
                                 __global float* applied, __global float* pushApplied,
                                 __global const btoclBody* bodies, __global btoclBodyDelta* deltas, int pass,
                                 int applyFactors) {
    const int push = pass == BTOCL_PASS_PENETRATION;
    SolveBody A = loadBody(bodies + c->bodyA, deltas + c->bodyA, push);
    SolveBody B = loadBody(bodies + c->bodyB, deltas + c->bodyB, push);
    float maxResidual2 = 0.0f;
    const int first = c->firstRow[BTOCL_ROWS_NORMAL];
    const int end = first + c->numRows[BTOCL_ROWS_NORMAL];
    for (int r = first; r < end; ++r) {
        __global const btoclRow* row = rows + r;
        float residual = 0.0f;
        if (pass == BTOCL_PASS_WARMSTART) {
            // SI applies each normal row's starting impulse to both bodies as it sets the row up.
            const float start = applied[r];
            applyImpulse(&A, row->contactNormal1 * A.invMass, row->angularComponentA, start, 1);
            applyImpulse(&B, row->contactNormal2 * B.invMass, row->angularComponentB, start, 1);
            continue;
        } else if (pass == BTOCL_PASS_PENETRATION) {
            if (BTOCL_ROW_RHS_PENETRATION(*row) == 0.0f) continue;  // no split-impulse share
            residual = solveRow(row, pushApplied + r, &A, &B, BTOCL_ROW_LOWER(*row), FLT_MAX, applyFactors, 1);
        } else {
            residual = solveRow(row, applied + r, &A, &B, BTOCL_ROW_LOWER(*row), FLT_MAX, applyFactors, 0);
        }
        maxResidual2 = fmax(maxResidual2, residual * residual);
    }
    if (pass == BTOCL_PASS_VELOCITY) {
        // Friction right after the constraint's normal rows: one sweep per iteration, the two
        // bodies read and written once (measured: the solve 2.4x faster than three passes).
        maxResidual2 = fmax(maxResidual2, solveFrictionRows(c, BTOCL_ROWS_FRICTION, rows, applied, &A, &B, applyFactors));
        maxResidual2 = fmax(maxResidual2, solveFrictionRows(c, BTOCL_ROWS_ROLLING, rows, applied, &A, &B, applyFactors));
    }
    storeBody(&A, deltas + c->bodyA, push);
    storeBody(&B, deltas + c->bodyB, push);
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
