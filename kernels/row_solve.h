// One constraint's rows solved by projected Gauss-Seidel, btSequentialImpulseConstraintSolver's
// row update, written once for the device (kernels/solve.cl, in parallel over a batch) and the
// serial host solve (bullet_plugin/step/HostSolve.cpp, one constraint after another).
// Arrays are __global on the device and plain memory on the host (BTOCL_GLOBAL).
#ifndef BTOCL_ROW_SOLVE_H
#define BTOCL_ROW_SOLVE_H

#include "btocl_shared.h"
#include "vec_math.h"

#ifdef __OPENCL_VERSION__
#define BTOCL_GLOBAL __global
#define BTOCL_FLT_MAX FLT_MAX
// Inlined into each kernel's call with the pass as a constant, so that the pass's branches fold
// away (PoCL's compiler kept one copy that tested the pass at every row).
#define BTOCL_SOLVE_INLINE static inline __attribute__((always_inline))
#else
// Likewise in the host's solve (HostSolve.cpp), which calls it with the pass as a constant.
#if defined(__GNUC__)
#define BTOCL_SOLVE_INLINE static inline __attribute__((always_inline))
#else
#define BTOCL_SOLVE_INLINE BTOCL_INLINE
#endif
#include <float.h>
#define BTOCL_GLOBAL
#define BTOCL_FLT_MAX FLT_MAX
#endif

// The arrays a solve pass reads and writes, one struct for every function of the solve (the
// kernels build it at their entry; the host reference from its vectors). Rows and their applied
// impulses are indexed in one order (solve order on the device); normalOfRow gives a friction or
// rolling row its normal row there.
typedef struct {
    BTOCL_GLOBAL const btoclConstraint* constraints;
    BTOCL_GLOBAL const btoclSolveRow* rows;
    BTOCL_GLOBAL const int* normalOfRow;
    BTOCL_GLOBAL float* applied;
    BTOCL_GLOBAL float* pushApplied;
    BTOCL_GLOBAL const btoclBody* bodies;
    BTOCL_GLOBAL btoclBodyDelta* deltas;
} btoclSolveBuffers;

// The randomized order (SOLVER_RANDMIZE_ORDER: BTOCL_FLAG_RANDOM_ORDER), in shuffled orders drawn
// from the pass's seed (btoclPassSeed): the same on every run, device and in the host reference,
// another in every pass and step. Both velocity passes walk each constraint's rows of a kind
// shuffled (btoclShuffledRows); the friction pass walks its constraints shuffled too: a group's
// batches, and a batch's constraints where one lane walks them (btoclShuffledConstraints). The
// normal pass keeps its constraints' order: shuffled as well, resting stacks jittered more than
// in SI's randomized order, at no less drift (docs/quality.md, "Resting stacks").
// A shuffle of [0, n) puts k -> (a k + b) mod n with a prime to n: no table, no state.
typedef struct {
    int n;      // positions
    int step;   // a, prime to n
    int start;  // b
} btoclShuffle;

BTOCL_INLINE unsigned int btoclMix(unsigned int x) {
    x ^= x >> 16;
    x *= 0x85ebca6bu;
    x ^= x >> 13;
    x *= 0xc2b2ae35u;
    x ^= x >> 16;
    return x;
}
// The seed of one part of a pass (a group, a batch, a constraint), from the seed of the whole.
BTOCL_INLINE unsigned int btoclSeedOf(unsigned int seed, int part) {
    return btoclMix(seed ^ btoclMix((unsigned int)part + 0x9e3779b9u));
}
// Whether a pass walks its constraints' rows shuffled: SI shuffles its velocity iterations' rows,
// not its push iterations' or its warm start.
BTOCL_INLINE int btoclShuffledRows(int pass, int flags) {
    return (flags & BTOCL_FLAG_RANDOM_ORDER) && (pass == BTOCL_PASS_NORMAL || pass == BTOCL_PASS_FRICTION);
}
// Whether a pass walks its constraints shuffled (a group's batches, a batch's constraints).
BTOCL_INLINE int btoclShuffledConstraints(int pass, int flags) {
    return (flags & BTOCL_FLAG_RANDOM_ORDER) && pass == BTOCL_PASS_FRICTION;
}
// The seed of the pass at `passIndex` of the step's schedule (btoclPassAt).
BTOCL_INLINE unsigned int btoclPassSeed(btoclPassSchedule s, int passIndex) {
    return btoclSeedOf(btoclMix(s.orderSeed), passIndex);
}
BTOCL_INLINE int btoclGcd(int a, int b) {
    while (b != 0) {
        const int t = a % b;
        a = b;
        b = t;
    }
    return a;
}
BTOCL_INLINE btoclShuffle btoclShuffleOf(int n, unsigned int seed) {
    btoclShuffle s;
    s.n = n;
    s.step = 1;
    s.start = 0;
    if (n < 2) return s;
    s.start = (int)(seed % (unsigned int)n);
    s.step = 1 + (int)(btoclMix(seed + 0x9e3779b9u) % (unsigned int)(n - 1));
    while (btoclGcd(s.step, n) != 1) s.step = s.step + 1 < n ? s.step + 1 : 1;
    return s;
}
// What position k of the shuffle holds.
BTOCL_INLINE int btoclShuffleAt(btoclShuffle s, int k) {
    return (int)(((long)s.step * k + s.start) % s.n);
}
// Position k of [0, n) walked in order, or shuffled by `seed` with `random`.
BTOCL_INLINE int btoclOrderAt(int n, int random, unsigned int seed, int k) {
    return random ? btoclShuffleAt(btoclShuffleOf(n, seed), k) : k;
}

// A body's part in one constraint: read once, updated by each of the constraint's rows (they all
// act on the same two bodies), written back once. What a unit impulse does to it is scaled once
// here, not at every row: a body that cannot move gets zero scales, so no row tests it.
typedef struct {
    btoclFloat4 linearPerUnit;   // xyz: inverse mass times linear factor (times it again where factors
                                 // are applied); 0 for a body that does not move
    btoclFloat4 angularPerUnit;  // xyz: scales a row's angular component: the angular factor where
                                 // factors are applied, else 1; 0 for a body that does not move
    btoclFloat4 linear, angular;  // velocity change, or push and turn velocity in the penetration pass
    float dynamic;                // BTOCL_BODY_IS_DYNAMIC: only a dynamic body's changes are stored
} btoclSolveBody;

// applyFactors: SI applies the body factors to every impulse without SOLVER_SIMD, and to the
// warm start always.
BTOCL_INLINE btoclSolveBody btoclLoadSolveBody(BTOCL_GLOBAL const btoclBody* b, BTOCL_GLOBAL const btoclBodyDelta* d,
                                               int push, int applyFactors) {
    btoclSolveBody s;
    const btoclFloat4 one = BTOCL_FLOAT4(1.0f, 1.0f, 1.0f, 0.0f);
    s.dynamic = BTOCL_BODY_IS_DYNAMIC(*b);
    s.linearPerUnit = btoclXyz(b->invMass) * (applyFactors ? btoclXyz(b->linearFactor) : one) * s.dynamic;
    s.angularPerUnit = (applyFactors ? btoclXyz(b->angularFactor) : one) * s.dynamic;
    s.linear = push ? d->pushVelocity : d->deltaLinearVelocity;
    s.angular = push ? d->turnVelocity : d->deltaAngularVelocity;
    return s;
}

BTOCL_INLINE void btoclStoreSolveBody(const btoclSolveBody* s, BTOCL_GLOBAL btoclBodyDelta* d, int push) {
    if (s->dynamic == 0.0f) return;  // static and kinematic bodies never change
    if (push) {
        d->pushVelocity = s->linear;
        d->turnVelocity = s->angular;
    } else {
        d->deltaLinearVelocity = s->linear;
        d->deltaAngularVelocity = s->angular;
    }
}

// A row's impulse applied to both bodies (btSolverBody::internalApplyImpulse): per unit, A along
// the row's normal, B against it, each turned by its angular component (w lanes cleared: they
// carry the row's other values). The per-unit changes depend on the row alone, so only the
// multiply-adds wait for the rows before.
BTOCL_INLINE void btoclApplyRowImpulse(BTOCL_GLOBAL const btoclSolveRow* row, btoclSolveBody* A, btoclSolveBody* B,
                                       float impulse) {
    const btoclFloat4 n = btoclXyz(row->normal);
    A->linear = A->linear + (n * A->linearPerUnit) * impulse;
    A->angular = A->angular + (btoclXyz(row->angularComponentA) * A->angularPerUnit) * impulse;
    B->linear = B->linear - (n * B->linearPerUnit) * impulse;
    B->angular = B->angular + (btoclXyz(row->angularComponentB) * B->angularPerUnit) * impulse;
}

// One row, its impulse clamped to [lower, upper]; returns the impulse change (btoclResidual2
// makes SI's residual of it). The row is read only; its applied impulse lives in a compact array,
// so a pass writes 4 bytes per row, not a cache line. B's linear Jacobian is the negative of A's
// (btoclSolveRow).
// A constraint's rows form one chain (each reads the velocities the row before wrote), and on a
// CPU the chain's length is the solve's speed: the velocity along the row is summed as vectors,
// linear parts and angular parts, and reduced once, and what depends on the row alone is computed
// off the chain, rather than two dot products per body reduced one after the other
// (docs/performance.md). Its rounding differs from that form's, and resting figures move with it
// as with any reordering of the sums (docs/quality.md, "Resting stacks").
BTOCL_INLINE float btoclSolveRowImpulse(BTOCL_GLOBAL const btoclSolveRow* row, BTOCL_GLOBAL float* appliedImpulse,
                                 btoclSolveBody* A, btoclSolveBody* B, float lower, float upper, int push) {
    const float jacDiagABInv = BTOCL_SOLVE_ROW_JAC_DIAG_INV(*row);
    const float applied = *appliedImpulse;
    const float start =
        (push ? BTOCL_SOLVE_ROW_RHS_PENETRATION(*row) : BTOCL_SOLVE_ROW_RHS(*row)) - applied * BTOCL_SOLVE_ROW_CFM(*row);
    const btoclFloat4 n = btoclXyz(row->normal);
    const btoclFloat4 v = (n * A->linear - n * B->linear) +
                          (row->relpos1CrossNormal * A->angular + row->relpos2CrossNormal * B->angular);
    float deltaImpulse = start - btoclSum3(v) * jacDiagABInv;
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
    btoclApplyRowImpulse(row, A, B, deltaImpulse);
    return deltaImpulse;
}

// The squared residual of a row's impulse change as SI reports it (the change over the row's
// effective mass). Only a residual threshold reads it: without one, no row pays its divide.
BTOCL_INLINE float btoclResidual2(BTOCL_GLOBAL const btoclSolveRow* row, float deltaImpulse) {
    const float residual = deltaImpulse * (1.0f / BTOCL_SOLVE_ROW_JAC_DIAG_INV(*row));
    return residual * residual;
}

// The `count` friction or rolling rows from `first` on, in order or shuffled by `seed` with
// `random`: the limit follows the normal row's impulse of this iteration (normalOfRow[r]: its
// index), and a rolling row's limit is capped at its own coefficient (SI's solveSingleIteration).
BTOCL_SOLVE_INLINE float btoclSolveFrictionRows(const btoclSolveBuffers* b, int first, int count, int random,
                                                unsigned int seed, int rolling, btoclSolveBody* A, btoclSolveBody* B,
                                                int track) {
    const btoclShuffle order = btoclShuffleOf(random ? count : 0, seed);
    float maxResidual2 = 0.0f;
    for (int k = 0; k < count; ++k) {
        const int r = first + (random ? btoclShuffleAt(order, k) : k);
        BTOCL_GLOBAL const btoclSolveRow* row = b->rows + r;
        const float total = b->applied[b->normalOfRow[r]];
        if (!(total > 0.0f)) continue;
        const float friction = BTOCL_SOLVE_ROW_FRICTION(*row);
        float limit = friction * total;
        if (rolling && limit > friction) limit = friction;
        const float delta = btoclSolveRowImpulse(row, b->applied + r, A, B, -limit, limit, 0);
        if (track) maxResidual2 = fmax(maxResidual2, btoclResidual2(row, delta));
    }
    return maxResidual2;
}

// Joint rows, each within its own limits (motors and joint limits live there), while the joint
// still takes part: SI solves a joint's rows while iteration < its override count.
// With `random`, in an order shuffled by `seed`.
BTOCL_INLINE float btoclSolveJointRows(const btoclSolveBuffers* b, BTOCL_GLOBAL const btoclConstraint* c,
                                       btoclSolveBody* A, btoclSolveBody* B, int track, int iteration, int random,
                                       unsigned int seed) {
    float maxResidual2 = 0.0f;
    const int first = c->firstRow[BTOCL_ROWS_JOINT];
    const int count = c->numRows[BTOCL_ROWS_JOINT];
    if (count == 0 || (float)iteration >= BTOCL_CONSTRAINT_ITERATIONS(*c)) return 0.0f;
    const btoclShuffle order = btoclShuffleOf(random ? count : 0, seed);
    for (int k = 0; k < count; ++k) {
        const int r = first + (random ? btoclShuffleAt(order, k) : k);
        BTOCL_GLOBAL const btoclSolveRow* row = b->rows + r;
        const float delta = btoclSolveRowImpulse(row, b->applied + r, A, B, BTOCL_SOLVE_ROW_LOWER(*row),
                                                 BTOCL_SOLVE_ROW_UPPER(*row), 0);
        if (track) maxResidual2 = fmax(maxResidual2, btoclResidual2(row, delta));
    }
    return maxResidual2;
}

// The rows of one constraint for one pass (BTOCL_PASS_*); returns the largest squared residual
// (0 unless flags has BTOCL_FLAG_TRACK_RESIDUAL).
// iteration: the velocity iteration, from 0. A step runs max(numIterations, every joint's
// BTOCL_CONSTRAINT_ITERATIONS) of them (SI's maxIterations); contact rows take part while
// iteration < numIterations (m_numIterations), joint rows as btoclSolveJointRows says. Joint rows
// come first, as in SI's iteration (a constraint holds either kind: a joint or a contact manifold).
// random: each kind of its rows walked in a shuffled order drawn from `seed` (btoclShuffledRows).
// interleave (BTOCL_FLAG_INTERLEAVE_FRICTION: SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS):
// each point's friction rows follow its normal row in the normal pass, and the friction pass
// keeps the rolling rows alone (as SI's iteration).
BTOCL_SOLVE_INLINE float btoclSolveConstraintInOrder(const btoclSolveBuffers* b, BTOCL_GLOBAL const btoclConstraint* c,
                                                     int pass, int flags, int iteration, int numIterations,
                                                     unsigned int seed, int random, int interleave) {
    const int push = pass == BTOCL_PASS_PUSH;
    // SI applies the factors to the warm start as it sets the rows up, whatever its mode.
    const int applyFactors = pass == BTOCL_PASS_WARMSTART || (flags & BTOCL_FLAG_APPLY_FACTORS) != 0;
    const int track = (flags & BTOCL_FLAG_TRACK_RESIDUAL) != 0;
    // Contact rows take part while iteration < numIterations; joint rows come first, as in SI's
    // iteration, while the joint's own count allows (btoclSolveJointRows).
    const int contacts = (pass != BTOCL_PASS_NORMAL && pass != BTOCL_PASS_FRICTION) || iteration < numIterations;
    const int jointRows = (float)iteration < BTOCL_CONSTRAINT_ITERATIONS(*c) ? c->numRows[BTOCL_ROWS_JOINT] : 0;
    // A pass with no row of this constraint leaves its bodies as they are: their loads and stores
    // are skipped (a joint in the friction pass, a manifold past m_numIterations).
    const int frictionRows = interleave ? 0 : c->numRows[BTOCL_ROWS_FRICTION];  // else in the normal pass
    const int rowsOfPass = pass == BTOCL_PASS_FRICTION
                               ? (contacts ? frictionRows + c->numRows[BTOCL_ROWS_ROLLING] : 0)
                           : pass == BTOCL_PASS_NORMAL ? (contacts ? c->numRows[BTOCL_ROWS_NORMAL] : 0) + jointRows
                                                       : c->numRows[BTOCL_ROWS_NORMAL];
    if (rowsOfPass == 0) return 0.0f;
    btoclSolveBody A = btoclLoadSolveBody(b->bodies + c->bodyA, b->deltas + c->bodyA, push, applyFactors);
    btoclSolveBody B = btoclLoadSolveBody(b->bodies + c->bodyB, b->deltas + c->bodyB, push, applyFactors);
    float maxResidual2 = 0.0f;
    if (pass == BTOCL_PASS_FRICTION) {
        if (contacts) {
            if (!interleave)
                maxResidual2 = btoclSolveFrictionRows(b, c->firstRow[BTOCL_ROWS_FRICTION], c->numRows[BTOCL_ROWS_FRICTION],
                                                      random, btoclSeedOf(seed, BTOCL_ROWS_FRICTION), 0, &A, &B, track);
            maxResidual2 = fmax(maxResidual2, btoclSolveFrictionRows(b, c->firstRow[BTOCL_ROWS_ROLLING],
                                                                     c->numRows[BTOCL_ROWS_ROLLING], random,
                                                                     btoclSeedOf(seed, BTOCL_ROWS_ROLLING), 1, &A, &B,
                                                                     track));
        }
    } else {
        // Joints are neither warm-started nor part of the push iterations (SI's neither).
        if (pass == BTOCL_PASS_NORMAL)
            maxResidual2 = btoclSolveJointRows(b, c, &A, &B, track, iteration, random, btoclSeedOf(seed, BTOCL_ROWS_JOINT));
        const int first = c->firstRow[BTOCL_ROWS_NORMAL];
        const int count = contacts ? c->numRows[BTOCL_ROWS_NORMAL] : 0;
        // With BTOCL_FLAG_ROTATE_POINTS the velocity iterations start the manifold's points at
        // another one each time (the same in every run): no point always goes first and takes
        // the largest share, which is what makes a resting stack creep in one fixed order.
        const int start = (pass == BTOCL_PASS_NORMAL && (flags & BTOCL_FLAG_ROTATE_POINTS) && count > 1)
                              ? iteration % count
                              : 0;
        const btoclShuffle points = btoclShuffleOf(random ? count : 0, btoclSeedOf(seed, BTOCL_ROWS_NORMAL));
        // A point's friction rows, when they follow it: one or two (SOLVER_USE_2_FRICTION_DIRECTIONS).
        const int frictionPerPoint =
            interleave && pass == BTOCL_PASS_NORMAL && count > 0 ? c->numRows[BTOCL_ROWS_FRICTION] / count : 0;
        for (int k = 0; k < count; ++k) {
            const int point = random ? btoclShuffleAt(points, k) : (start + k < count ? start + k : start + k - count);
            const int r = first + point;
            BTOCL_GLOBAL const btoclSolveRow* row = b->rows + r;
            float delta;
            if (pass == BTOCL_PASS_WARMSTART) {
                // SI applies each normal row's starting impulse to both bodies as it sets the row up.
                const float start = b->applied[r];
                btoclApplyRowImpulse(row, &A, &B, start);
                continue;
            } else if (pass == BTOCL_PASS_PUSH) {
                if (BTOCL_SOLVE_ROW_RHS_PENETRATION(*row) == 0.0f) continue;  // no push share
                delta = btoclSolveRowImpulse(row, b->pushApplied + r, &A, &B, 0.0f, BTOCL_FLT_MAX, 1);
            } else {
                delta = btoclSolveRowImpulse(row, b->applied + r, &A, &B, 0.0f, BTOCL_FLT_MAX, 0);
            }
            if (track) maxResidual2 = fmax(maxResidual2, btoclResidual2(row, delta));
            if (frictionPerPoint > 0)
                maxResidual2 = fmax(maxResidual2, btoclSolveFrictionRows(
                                                      b, c->firstRow[BTOCL_ROWS_FRICTION] + point * frictionPerPoint,
                                                      frictionPerPoint, 0, 0u, 0, &A, &B, track));
        }
    }
    btoclStoreSolveBody(&A, b->deltas + c->bodyA, push);
    btoclStoreSolveBody(&B, b->deltas + c->bodyB, push);
    return maxResidual2;
}

// Two constraints side by side. A constraint's rows form one chain (each row reads the velocities
// the row before wrote), and a manifold has few rows, often one or two a pass: solved one after
// the other, a core waits on the latency of each chain in turn. Two constraints that share no
// dynamic body touch nothing of each other's (a body that cannot move is read, never written), so
// solving their rows in lockstep, two chains at once, gives the bits of solving one, then the
// other, in less of the wait. Taken where a pass walks constraints in a fixed order with nothing
// but contact rows in it: the velocity passes within the contacts' iterations, in no randomized
// order, without interleaved friction, rotated points or a residual to track. The host's solve
// walks so (HostSolve.cpp); the claimed kernel's walk measured slower with it on PoCL
// (docs/performance.md, "Two constraints side by side").
BTOCL_INLINE int btoclPassPairs(int pass, int flags, int iteration, int numIterations) {
    return (pass == BTOCL_PASS_NORMAL || pass == BTOCL_PASS_FRICTION) && iteration < numIterations &&
           (flags & (BTOCL_FLAG_RANDOM_ORDER | BTOCL_FLAG_INTERLEAVE_FRICTION | BTOCL_FLAG_ROTATE_POINTS |
                     BTOCL_FLAG_TRACK_RESIDUAL)) == 0;
}

// Whether c1 and c2 may be solved side by side (btoclSolveContactPair): contact rows alone (no
// joint rows, no rolling rows), no dynamic body of one in the other.
BTOCL_INLINE int btoclPairable(BTOCL_GLOBAL const btoclConstraint* c1, BTOCL_GLOBAL const btoclConstraint* c2) {
    if (c1->numRows[BTOCL_ROWS_JOINT] + c1->numRows[BTOCL_ROWS_ROLLING] + c2->numRows[BTOCL_ROWS_JOINT] +
            c2->numRows[BTOCL_ROWS_ROLLING] != 0)
        return 0;
    const int aShared = c1->dynamicA && (c1->bodyA == c2->bodyA || c1->bodyA == c2->bodyB);
    const int bShared = c1->dynamicB && (c1->bodyB == c2->bodyA || c1->bodyB == c2->bodyB);
    return !aShared && !bShared;
}

// Row r of a contact in the normal pass (pass 0 to FLT_MAX) or the friction pass (within the
// friction coefficient times its normal row's impulse, skipped while that is not positive), as
// btoclSolveConstraintInOrder and btoclSolveFrictionRows solve it in a fixed order.
BTOCL_SOLVE_INLINE void btoclSolveContactRow(const btoclSolveBuffers* b, int r, int pass, btoclSolveBody* A,
                                             btoclSolveBody* B) {
    BTOCL_GLOBAL const btoclSolveRow* row = b->rows + r;
    if (pass == BTOCL_PASS_NORMAL) {
        btoclSolveRowImpulse(row, b->applied + r, A, B, 0.0f, BTOCL_FLT_MAX, 0);
        return;
    }
    const float total = b->applied[b->normalOfRow[r]];
    if (!(total > 0.0f)) return;
    const float limit = BTOCL_SOLVE_ROW_FRICTION(*row) * total;
    btoclSolveRowImpulse(row, b->applied + r, A, B, -limit, limit, 0);
}

// c1 and c2 (btoclPairable) in a pass that pairs (btoclPassPairs): row k of one beside row k of
// the other, with the bits of solving c1, then c2, with btoclSolveConstraint.
BTOCL_SOLVE_INLINE void btoclSolveContactPair(const btoclSolveBuffers* b, BTOCL_GLOBAL const btoclConstraint* c1,
                                              BTOCL_GLOBAL const btoclConstraint* c2, int pass, int flags) {
    const int applyFactors = (flags & BTOCL_FLAG_APPLY_FACTORS) != 0;
    btoclSolveBody A1 = btoclLoadSolveBody(b->bodies + c1->bodyA, b->deltas + c1->bodyA, 0, applyFactors);
    btoclSolveBody B1 = btoclLoadSolveBody(b->bodies + c1->bodyB, b->deltas + c1->bodyB, 0, applyFactors);
    btoclSolveBody A2 = btoclLoadSolveBody(b->bodies + c2->bodyA, b->deltas + c2->bodyA, 0, applyFactors);
    btoclSolveBody B2 = btoclLoadSolveBody(b->bodies + c2->bodyB, b->deltas + c2->bodyB, 0, applyFactors);
    const int kind = pass == BTOCL_PASS_NORMAL ? BTOCL_ROWS_NORMAL : BTOCL_ROWS_FRICTION;
    const int first1 = c1->firstRow[kind], count1 = c1->numRows[kind];
    const int first2 = c2->firstRow[kind], count2 = c2->numRows[kind];
    const int both = count1 < count2 ? count1 : count2;
    for (int k = 0; k < both; ++k) {
        btoclSolveContactRow(b, first1 + k, pass, &A1, &B1);
        btoclSolveContactRow(b, first2 + k, pass, &A2, &B2);
    }
    for (int k = both; k < count1; ++k) btoclSolveContactRow(b, first1 + k, pass, &A1, &B1);
    for (int k = both; k < count2; ++k) btoclSolveContactRow(b, first2 + k, pass, &A2, &B2);
    btoclStoreSolveBody(&A1, b->deltas + c1->bodyA, 0);
    btoclStoreSolveBody(&B1, b->deltas + c1->bodyB, 0);
    btoclStoreSolveBody(&A2, b->deltas + c2->bodyA, 0);
    btoclStoreSolveBody(&B2, b->deltas + c2->bodyB, 0);
}

// seed: the constraint's in this pass (btoclSeedOf), read with BTOCL_FLAG_RANDOM_ORDER: the
// velocity passes then walk each kind of its rows in a shuffled order (SI shuffles its rows
// likewise; its push iterations and the warm start keep their order, and so do these). Two copies
// of the walk: the fixed order's has no reordering left in it (one copy for all orders made the
// wide path's solve slower on PoCL).
BTOCL_SOLVE_INLINE float btoclSolveConstraint(const btoclSolveBuffers* b, BTOCL_GLOBAL const btoclConstraint* c,
                                              int pass, int flags, int iteration, int numIterations,
                                              unsigned int seed) {
    if (flags & (BTOCL_FLAG_RANDOM_ORDER | BTOCL_FLAG_INTERLEAVE_FRICTION))
        return btoclSolveConstraintInOrder(b, c, pass, flags, iteration, numIterations, seed,
                                           btoclShuffledRows(pass, flags),
                                           (flags & BTOCL_FLAG_INTERLEAVE_FRICTION) != 0);
    return btoclSolveConstraintInOrder(b, c, pass, flags, iteration, numIterations, 0u, 0, 0);
}

#endif
