// A bundle's slots solved W constraints at a time, one per lane of the vector unit
// (btocl_shared.h, btoclLaneSlot; docs/architecture.md, "Lanes"). OpenCL C only: the program is
// built with -DBTOCL_LANES=W (4, 8 or 16: btOpenCLSolverConfig::simdLanes) where the solver runs in lanes.
// Each lane does what btoclSolveConstraint does for its constraint, operation for operation, so
// a lane's results are those of the one-lane walk to the bit (tests/test_lanes.cpp); a lane with
// no row at some place is masked, never computed with zeros (that could turn a -0 velocity to +0).
// A slot's velocities are read W records at a time and turned into one vector per float (a
// transpose the compiler makes of shuffles), rather than lane by lane through memory.
#ifndef BTOCL_LANE_SOLVE_H
#define BTOCL_LANE_SOLVE_H

#include "row_solve.h"

// The arrays a lanes pass reads and writes besides btoclSolveBuffers (whose impulses are by wide row
// index there): the slots, their lanes, the rows in blocks (btoclWideRowFloat).
typedef struct {
    __global const btoclLaneSlot* slots;
    __global const int* lanes;             // BTOCL_LANE_INTS * W ints a slot
    __global const float* bodyPerUnit;  // per body, BTOCL_BODY_PER_UNIT_FLOATS (set by the host)
    __global const float* rows;
    __global int* slotPushes;  // per slot: a row with a push share (btoclPushSlotsPart)
    int frictionPerPoint;
} btoclLaneBuffers;

#if defined(BTOCL_LANES) && BTOCL_LANES > 1

#define BTOCL_CAT_(a, b) a##b
#define BTOCL_CAT(a, b) BTOCL_CAT_(a, b)
typedef BTOCL_CAT(float, BTOCL_LANES) btoclLanesF;
typedef BTOCL_CAT(int, BTOCL_LANES) btoclLanesI;
#define btoclLoadLanes(p) BTOCL_CAT(vload, BTOCL_LANES)(0, p)
#define btoclStoreLanes(v, p) BTOCL_CAT(vstore, BTOCL_LANES)(v, 0, p)

// Lane lists: M(i) for every lane i (a hex digit, as OpenCL names a vector's components).
#if BTOCL_LANES == 4
#define BTOCL_EACH_LANE(M) M(0) M(1) M(2) M(3)
#define BTOCL_LANES_VECTOR(M, field) ((btoclLanesF)(M(0, field), M(1, field), M(2, field), M(3, field)))
#elif BTOCL_LANES == 8
#define BTOCL_EACH_LANE(M) M(0) M(1) M(2) M(3) M(4) M(5) M(6) M(7)
#define BTOCL_LANES_VECTOR(M, field) \
    ((btoclLanesF)(M(0, field), M(1, field), M(2, field), M(3, field), M(4, field), M(5, field), M(6, field), M(7, field)))
#elif BTOCL_LANES == 16
#define BTOCL_EACH_LANE(M) \
    M(0) M(1) M(2) M(3) M(4) M(5) M(6) M(7) M(8) M(9) M(a) M(b) M(c) M(d) M(e) M(f)
#define BTOCL_LANES_VECTOR(M, field)                                                                     \
    ((btoclLanesF)(M(0, field), M(1, field), M(2, field), M(3, field), M(4, field), M(5, field), M(6, field), M(7, field), M(8, field), \
                   M(9, field), M(a, field), M(b, field), M(c, field), M(d, field), M(e, field), M(f, field)))
#else
#error "BTOCL_LANES must be 4, 8 or 16"
#endif

// A side's bodies of a slot's lanes: their per-unit scales (BTOCL_BODY_PER_UNIT_FLOATS) and the velocities the
// rows change (linear and angular, or push and turn), one vector per float.
typedef struct {
    btoclLanesF lpuX, lpuY, lpuZ, apuX, apuY, apuZ;  // linearPerUnit, angularPerUnit
    btoclLanesF linX, linY, linZ, angX, angY, angZ;  // linear, angular
    btoclLanesF dynamic;                             // 1: the lane's body is stored back
} btoclLaneBodies;

// Lane i's 8 floats at float index at.si of `base`, as a vector named record<i>; a float of each.
#define BTOCL_LOAD_RECORD(i) const float8 record##i = vload8(0, base + at.s##i);
#define BTOCL_RECORD_FLOAT(i, f) record##i.s##f

// W records of 8 floats, lane i's at float index at.si of `base`, turned into vectors: s<f> holds
// float f of every lane's record.
typedef struct {
    btoclLanesF s0, s1, s2, s3, s4, s5, s6;  // float 7 of a record is never read
} btoclLaneRecords;
BTOCL_SOLVE_INLINE btoclLaneRecords btoclLoadLaneRecords(__global const float* base, btoclLanesI at) {
    BTOCL_EACH_LANE(BTOCL_LOAD_RECORD)
    btoclLaneRecords r;
    r.s0 = BTOCL_LANES_VECTOR(BTOCL_RECORD_FLOAT, 0);
    r.s1 = BTOCL_LANES_VECTOR(BTOCL_RECORD_FLOAT, 1);
    r.s2 = BTOCL_LANES_VECTOR(BTOCL_RECORD_FLOAT, 2);
    r.s3 = BTOCL_LANES_VECTOR(BTOCL_RECORD_FLOAT, 3);
    r.s4 = BTOCL_LANES_VECTOR(BTOCL_RECORD_FLOAT, 4);
    r.s5 = BTOCL_LANES_VECTOR(BTOCL_RECORD_FLOAT, 5);
    r.s6 = BTOCL_LANES_VECTOR(BTOCL_RECORD_FLOAT, 6);
    return r;
}

// A side's bodies of a slot's lanes: the velocities from the deltas and the per-unit scales from
// the bodies' own (bodyPerUnit), W records of each turned into vectors.
BTOCL_SOLVE_INLINE btoclLaneBodies btoclLoadLaneBodies(const btoclSolveBuffers* b, const btoclLaneBuffers* lb,
                                                       btoclLanesI body, int push, int warmStart) {
    btoclLaneBodies l;
    // The velocities a pass changes: floats 0 to 7 of the body's delta, or 8 to 15 in the push pass.
    const btoclLaneRecords v = btoclLoadLaneRecords((__global const float*)b->deltas, body * 16 + (push ? 8 : 0));
    l.linX = v.s0, l.linY = v.s1, l.linZ = v.s2;
    l.angX = v.s4, l.angY = v.s5, l.angZ = v.s6;
    // The warm start's scales: floats 0 to 7 of the body's; the other passes': 8 to 15.
    const btoclLaneRecords u = btoclLoadLaneRecords(
        lb->bodyPerUnit, body * BTOCL_BODY_PER_UNIT_FLOATS + (warmStart ? 0 : BTOCL_BODY_PER_UNIT_FLOATS / 2));
    l.lpuX = u.s0, l.lpuY = u.s1, l.lpuZ = u.s2, l.dynamic = u.s3;
    l.apuX = u.s4, l.apuY = u.s5, l.apuZ = u.s6;
    return l;
}

// The velocities back to each lane's dynamic body (btoclStoreSolveBody: others never change),
// their w lanes untouched. Lanes of a slot share no dynamic body, so no store overwrites another's.
#define BTOCL_STORE_LANE(i)                                                                              \
    if (l->dynamic.s##i != 0.0f) {                                                                       \
        vstore3((float3)(l->linX.s##i, l->linY.s##i, l->linZ.s##i), 0, base + body.s##i * 16 + offset);     \
        vstore3((float3)(l->angX.s##i, l->angY.s##i, l->angZ.s##i), 0, base + body.s##i * 16 + offset + 4); \
    }
BTOCL_SOLVE_INLINE void btoclStoreLaneBodies(const btoclSolveBuffers* b, btoclLanesI body, int push,
                                             const btoclLaneBodies* l) {
    __global float* base = (__global float*)b->deltas;
    const int offset = push ? 8 : 0;
    BTOCL_EACH_LANE(BTOCL_STORE_LANE)
}

#define BTOCL_ROW_FIELD(f) btoclLoadLanes(row + (f) * BTOCL_LANES)
// A block's impulses applied to its lanes' bodies where `active` (btoclApplyRowImpulse, lane by lane),
// each side's angular component its Jacobian (BTOCL_LANE_ROW_FLOATS).
BTOCL_SOLVE_INLINE void btoclApplyLaneImpulse(__global const float* row, btoclLaneBodies* A, btoclLaneBodies* B,
                                              btoclLanesF impulse, btoclLanesI active) {
    const btoclLanesF nX = BTOCL_ROW_FIELD(0), nY = BTOCL_ROW_FIELD(1), nZ = BTOCL_ROW_FIELD(2);
#define BTOCL_APPLY(v, change) v = select(v, v + (change) * impulse, active)
    BTOCL_APPLY(A->linX, nX * A->lpuX);
    BTOCL_APPLY(A->linY, nY * A->lpuY);
    BTOCL_APPLY(A->linZ, nZ * A->lpuZ);
    BTOCL_APPLY(A->angX, BTOCL_ROW_FIELD(4) * A->apuX);
    BTOCL_APPLY(A->angY, BTOCL_ROW_FIELD(5) * A->apuY);
    BTOCL_APPLY(A->angZ, BTOCL_ROW_FIELD(6) * A->apuZ);
    B->linX = select(B->linX, B->linX - (nX * B->lpuX) * impulse, active);
    B->linY = select(B->linY, B->linY - (nY * B->lpuY) * impulse, active);
    B->linZ = select(B->linZ, B->linZ - (nZ * B->lpuZ) * impulse, active);
    BTOCL_APPLY(B->angX, BTOCL_ROW_FIELD(8) * B->apuX);
    BTOCL_APPLY(B->angY, BTOCL_ROW_FIELD(9) * B->apuY);
    BTOCL_APPLY(B->angZ, BTOCL_ROW_FIELD(10) * B->apuZ);
#undef BTOCL_APPLY
}

// One block of W rows (btoclWideRowFloat's layout), as btoclSolveRowImpulse solves a row, in the
// lanes where `active`; `applied` is the block's impulses. lower and upper: the clamp.
BTOCL_SOLVE_INLINE void btoclSolveLaneRows(__global const float* row, __global float* applied, btoclLaneBodies* A,
                                           btoclLaneBodies* B, btoclLanesF lower, btoclLanesF upper, int push,
                                           btoclLanesI active) {
    const btoclLanesF nX = BTOCL_ROW_FIELD(0), nY = BTOCL_ROW_FIELD(1), nZ = BTOCL_ROW_FIELD(2);
    const btoclLanesF old = btoclLoadLanes(applied);
    const btoclLanesF start =
        (push ? BTOCL_ROW_FIELD(BTOCL_LANE_ROW_SHARED) : BTOCL_ROW_FIELD(3)) - old * BTOCL_ROW_FIELD(7);  // rhs, cfm
    const btoclLanesF vX = (nX * A->linX - nX * B->linX) + (BTOCL_ROW_FIELD(4) * A->angX + BTOCL_ROW_FIELD(8) * B->angX);
    const btoclLanesF vY = (nY * A->linY - nY * B->linY) + (BTOCL_ROW_FIELD(5) * A->angY + BTOCL_ROW_FIELD(9) * B->angY);
    const btoclLanesF vZ =
        (nZ * A->linZ - nZ * B->linZ) + (BTOCL_ROW_FIELD(6) * A->angZ + BTOCL_ROW_FIELD(10) * B->angZ);
    const btoclLanesF unclamped = start - (vX + vY + vZ) * BTOCL_ROW_FIELD(11);  // jacDiagABInv
    const btoclLanesF sum = old + unclamped;
    const btoclLanesI below = sum < lower, above = sum > upper;
    const btoclLanesF delta = select(select(unclamped, upper - old, above), lower - old, below);
    const btoclLanesF next = select(select(sum, upper, above), lower, below);
    btoclStoreLanes(select(old, next, active), applied);
    btoclApplyLaneImpulse(row, A, B, delta, active);
}

// The warm start of one block: each lane's starting impulse applied.
BTOCL_SOLVE_INLINE void btoclWarmStartLaneRows(__global const float* row, __global const float* applied,
                                               btoclLaneBodies* A, btoclLaneBodies* B, btoclLanesI active) {
    btoclApplyLaneImpulse(row, A, B, btoclLoadLanes(applied), active);
}
#undef BTOCL_ROW_FIELD

// The rows stream from memory (each block is read once a pass) and the solve waited on them:
// a block asks for the one this many blocks ahead, a cache line at a time (16 floats).
#define BTOCL_ROWS_AHEAD 12
#define BTOCL_PREFETCH_ROWS(row, blockFloats)                           \
    if (BTOCL_PREFETCHES)                                               \
        for (int line = 0; line < (blockFloats); line += 16)            \
            BTOCL_PREFETCH((row) + BTOCL_ROWS_AHEAD * (blockFloats) + line)

// One slot in one pass: its lanes' constraints as btoclSolveConstraint solves each in a pass that
// pairs (btoclPassPairs), the warm start or a push pass: contact rows alone, in their order.
// hasNext: the bundle has a slot after this one. pushSlots: the pass's part in noting the slots
// with a push share (btoclPushSlotsPart).
BTOCL_SOLVE_INLINE void btoclSolveLaneSlot(const btoclSolveBuffers* b, const btoclLaneBuffers* lb, int slot, int pass,
                                           int pushSlots, int hasNext) {
    const int push = pass == BTOCL_PASS_PUSH;
    if (pushSlots == BTOCL_PUSH_SLOTS_SKIP && !lb->slotPushes[slot]) return;
    const btoclLaneSlot s = lb->slots[slot];
    __global const int* lanes = lb->lanes + slot * (BTOCL_LANE_INTS * BTOCL_LANES);
    const btoclLanesI bodyA = BTOCL_CAT(vload, BTOCL_LANES)(0, lanes + BTOCL_LANE_BODY_A * BTOCL_LANES);
    const btoclLanesI bodyB = BTOCL_CAT(vload, BTOCL_LANES)(0, lanes + BTOCL_LANE_BODY_B * BTOCL_LANES);
    const btoclLanesI numPoints = BTOCL_CAT(vload, BTOCL_LANES)(0, lanes + BTOCL_LANE_POINTS * BTOCL_LANES);
    if (BTOCL_PREFETCHES && hasNext) {
        // The bodies of the slot after this one lie scattered (in its lanes' groups), and the
        // loads of a slot's start waited for them: asked for now, solved behind this slot's rows.
        __global const int* next = lanes + BTOCL_LANE_INTS * BTOCL_LANES;
        const btoclLanesI nextA = BTOCL_CAT(vload, BTOCL_LANES)(0, next + BTOCL_LANE_BODY_A * BTOCL_LANES);
        const btoclLanesI nextB = BTOCL_CAT(vload, BTOCL_LANES)(0, next + BTOCL_LANE_BODY_B * BTOCL_LANES);
#define BTOCL_PREFETCH_LANE(i)                                                    \
    BTOCL_PREFETCH(b->deltas + nextA.s##i);                                       \
    BTOCL_PREFETCH(b->deltas + nextB.s##i);                                       \
    BTOCL_PREFETCH(lb->bodyPerUnit + nextA.s##i * BTOCL_BODY_PER_UNIT_FLOATS);    \
    BTOCL_PREFETCH(lb->bodyPerUnit + nextB.s##i * BTOCL_BODY_PER_UNIT_FLOATS);
        BTOCL_EACH_LANE(BTOCL_PREFETCH_LANE)
#undef BTOCL_PREFETCH_LANE
    }
    btoclLaneBodies A = btoclLoadLaneBodies(b, lb, bodyA, push, pass == BTOCL_PASS_WARMSTART);
    btoclLaneBodies B = btoclLoadLaneBodies(b, lb, bodyB, push, pass == BTOCL_PASS_WARMSTART);
    const int blockFloats = BTOCL_LANE_ROW_FLOATS * BTOCL_LANES;
    btoclLanesI pushes = 0;
    if (pass == BTOCL_PASS_FRICTION) {
        const int perPoint = lb->frictionPerPoint;
        for (int k = 0; k < s.frictionBlocks; ++k) {
            const int block = s.frictionBlock + k;
            __global const float* row = lb->rows + block * blockFloats;
            BTOCL_PREFETCH_ROWS(row, blockFloats);
            const btoclLanesF total = btoclLoadLanes(b->applied + (s.normalBlock + k / perPoint) * BTOCL_LANES);
            // The friction coefficient times the point's normal impulse.
            const btoclLanesF limit = btoclLoadLanes(row + BTOCL_LANE_ROW_SHARED * BTOCL_LANES) * total;
            const btoclLanesI active = (numPoints * perPoint > k) & (total > 0.0f);
            btoclSolveLaneRows(row, b->applied + block * BTOCL_LANES, &A, &B, -limit, limit, 0, active);
        }
    } else {
        for (int k = 0; k < s.normalBlocks; ++k) {
            const int block = s.normalBlock + k;
            __global const float* row = lb->rows + block * blockFloats;
            BTOCL_PREFETCH_ROWS(row, blockFloats);
            btoclLanesI active = numPoints > k;
            if (pass == BTOCL_PASS_WARMSTART) {
                btoclWarmStartLaneRows(row, b->applied + block * BTOCL_LANES, &A, &B, active);
                if (pushSlots == BTOCL_PUSH_SLOTS_NOTE)
                    pushes |= active & (btoclLoadLanes(row + BTOCL_LANE_ROW_SHARED * BTOCL_LANES) != 0.0f);
            } else if (push) {
                active &= btoclLoadLanes(row + BTOCL_LANE_ROW_SHARED * BTOCL_LANES) != 0.0f;  // no push share: skipped
                pushes |= active;
                btoclSolveLaneRows(row, b->pushApplied + block * BTOCL_LANES, &A, &B, (btoclLanesF)0.0f,
                                   (btoclLanesF)BTOCL_FLT_MAX, 1, active);
            } else {
                btoclSolveLaneRows(row, b->applied + block * BTOCL_LANES, &A, &B, (btoclLanesF)0.0f,
                                   (btoclLanesF)BTOCL_FLT_MAX, 0, active);
            }
        }
    }
    btoclStoreLaneBodies(b, bodyA, push, &A);
    btoclStoreLaneBodies(b, bodyB, push, &B);
    if (pushSlots == BTOCL_PUSH_SLOTS_NOTE) lb->slotPushes[slot] = any(pushes);
}

// A bundle (a btoclGroup whose offset and count are its slots) in one pass, slot after slot.
BTOCL_SOLVE_INLINE float btoclSolveLaneBundle(const btoclSolveBuffers* b, const btoclLaneBuffers* lb,
                                              btoclGroup bundle, int pass, int pushSlots) {
    const int end = bundle.offset + bundle.count;
    for (int slot = bundle.offset; slot < end; ++slot)
        btoclSolveLaneSlot(b, lb, slot, pass, pushSlots, slot + 1 < end);
    return 0.0f;
}

#endif
#endif
