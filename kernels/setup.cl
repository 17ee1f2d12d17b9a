// Constraint rows from contact points, one work-item per point: the normal row, one or two
// friction rows and the rolling/spinning rows (kernels/row_setup.h), written straight to their
// places in solve order. Host twin: bullet_plugin/bullet/HostRowSetup.cpp, from the same row_setup.h.
#include "btocl_shared.h"
#include "row_setup.h"
#include "row_solve.h"

// Row `index` of the solve-order layout as the iterations read it, its starting impulses in the
// compact arrays, and for friction and rolling rows the index of their normal row.
inline void storeRow(__global btoclSolveRow* rows, __global int* normalOfRow, __global float* applied,
                     __global float* pushApplied, int index, btoclRow row, int kind, int normalRow) {
    rows[index] = btoclSolveRowOf(row, kind);
    if (kind != BTOCL_ROWS_NORMAL) normalOfRow[index] = normalRow;
    applied[index] = BTOCL_ROW_APPLIED(row);
    pushApplied[index] = 0.0f;
}

// rowMap: where each row (by its index in gather order) lives in the solve-order layout.
// lateralDirs: two per point, its friction directions (written back to Bullet).
__kernel void setupContactRows(__global const btoclContactPoint* points, __global const btoclBody* bodies,
                               __global const int* rowMap, __global btoclSolveRow* rows,
                               __global int* normalOfRow, __global float* applied,
                               __global float* pushApplied, __global float4* lateralDirs, btoclSetupParams prm) {
    const int i = get_global_id(0);
    if (i >= prm.numPoints) return;
    if (BTOCL_PREFETCHES && i + 8 < prm.numPoints) {
        // The bodies of the point 8 ahead, which lie scattered.
        __global const btoclBody* a = bodies + points[i + 8].bodyA;
        __global const btoclBody* b = bodies + points[i + 8].bodyB;
        for (int line = 0; line < (int)sizeof(btoclBody); line += 64) {
            BTOCL_PREFETCH((__global const char*)a + line);
            BTOCL_PREFETCH((__global const char*)b + line);
        }
    }
    const btoclContactPoint pt = points[i];
    const btoclBody A = bodies[pt.bodyA];
    const btoclBody B = bodies[pt.bodyB];
    const btoclContactFrame f = btoclContactFrameOf(&pt, &A, &B);

    const int normalRow = rowMap[i];
    const btoclRow normal = btoclNormalRow(&pt, &A, &B, &f, &prm);
    storeRow(rows, normalOfRow, applied, pushApplied, normalRow, normal, BTOCL_ROWS_NORMAL, normalRow);

    if (pt.firstRollingRow >= 0) {
        float4 axis0, axis1;
        btoclPlaneSpace(pt.normalOnB, &axis0, &axis1);
        const int first = pt.firstRollingRow;
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first],
                 btoclTorsionalRow(pt.normalOnB, BTOCL_POINT_SPINNING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow);
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first + 1],
                 btoclTorsionalRow(btoclNormalize3(axis0), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow);
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first + 2],
                 btoclTorsionalRow(btoclNormalize3(axis1), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow);
    }

    const btoclFrictionFrame ff = btoclFrictionFrameOf(&pt, &f, prm.solverMode);
    lateralDirs[2 * i] = ff.dir1;  // cached ones unchanged
    lateralDirs[2 * i + 1] = ff.dir2;
    storeRow(rows, normalOfRow, applied, pushApplied, rowMap[pt.firstFrictionRow],
             btoclFrictionRow(ff.dir1, &pt, &A, &B, &f, &prm, ff.motion1, ff.cfmSlip, normalRow), BTOCL_ROWS_FRICTION,
             normalRow);
    if (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS)
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[pt.firstFrictionRow + 1],
                 btoclFrictionRow(ff.dir2, &pt, &A, &B, &f, &prm, ff.motion2, ff.cfmSlip, normalRow), BTOCL_ROWS_FRICTION,
                 normalRow);
}

#if defined(BTOCL_LANES) && BTOCL_LANES > 1
// Row `row` of a step in lanes to lane `lane` of block `block` (btoclWideRowFloat's layout), its
// starting impulse with it: a row of zeros and no impulse where the lane has no row there (masked
// in the solve; no float left uninitialised).
inline void storeLaneRow(__global float* wide, __global float* applied, __global float* pushApplied, int block,
                         int lane, btoclSolveRow r, float impulse) {
    __global float* out = wide + btoclWideRowFloat(block * BTOCL_LANES + lane, 0, BTOCL_LANES);
    const float4 parts[5] = {r.normal, r.relpos1CrossNormal, r.relpos2CrossNormal, r.angularComponentA,
                             r.angularComponentB};
    for (int v = 0; v < 5; ++v) {
        out[(4 * v) * BTOCL_LANES] = parts[v].x;
        out[(4 * v + 1) * BTOCL_LANES] = parts[v].y;
        out[(4 * v + 2) * BTOCL_LANES] = parts[v].z;
        out[(4 * v + 3) * BTOCL_LANES] = parts[v].w;
    }
    applied[block * BTOCL_LANES + lane] = impulse;
    pushApplied[block * BTOCL_LANES + lane] = 0.0f;
}

// A step in lanes (kernels/lane_solve.h), one work-item a slot: each lane's points' rows set up as
// setupContactRows sets them up (the same row code, so the same bits), written to the slot's
// blocks lane by lane, so that a block's cache lines are written whole by one work-item (the
// rows written from point order touched 20 lines a row); and the slot's per-unit scales of each
// side, the warm start's and the other passes' (BTOCL_LANE_PER_UNIT_FLOATS).
__kernel void setupLaneSlots(__global const btoclContactPoint* points, __global const btoclBody* bodies,
                             __global const btoclBodyDelta* deltas, __global const btoclLaneSlot* slots,
                             __global const int* laneInts, __global float* wide, __global float* applied,
                             __global float* pushApplied, __global float* slotPerUnit, __global float4* lateralDirs,
                             btoclSetupParams prm, int numSlots, int flags) {
    const int slot = get_global_id(0);
    if (slot >= numSlots) return;
    __global const int* ints = laneInts + slot * (BTOCL_LANE_INTS * BTOCL_LANES);
    if (BTOCL_PREFETCHES) {
        // The points of the slot two on, and the bodies of the next (their indices are the lanes'):
        // both lie scattered.
        __global const int* later = ints + 2 * BTOCL_LANE_INTS * BTOCL_LANES;
        for (int i = 0; slot + 2 < numSlots && i < BTOCL_LANES; ++i) {
            __global const char* p =
                (__global const char*)(points + later[BTOCL_LANE_FIRST_POINT * BTOCL_LANES + i]);
            const int bytes = later[BTOCL_LANE_POINTS * BTOCL_LANES + i] * (int)sizeof(btoclContactPoint);
            for (int line = 0; line < bytes; line += 64) BTOCL_PREFETCH(p + line);
        }
        for (int i = 0; slot + 1 < numSlots && i < BTOCL_LANES; ++i)
            for (int side = BTOCL_LANE_BODY_A; side <= BTOCL_LANE_BODY_B; ++side) {
                __global const char* b =
                    (__global const char*)(bodies + ints[BTOCL_LANE_INTS * BTOCL_LANES + side * BTOCL_LANES + i]);
                for (int line = 0; line < (int)sizeof(btoclBody); line += 64) BTOCL_PREFETCH(b + line);
            }
    }
    const btoclLaneSlot s = slots[slot];
    const int twoDirections = (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) != 0;
    const btoclSolveRow none = {(float4)(0.0f), (float4)(0.0f), (float4)(0.0f), (float4)(0.0f), (float4)(0.0f)};
    for (int lane = 0; lane < BTOCL_LANES; ++lane) {
        for (int side = 0; side < 2; ++side) {
            const int body = ints[(side == 0 ? BTOCL_LANE_BODY_A : BTOCL_LANE_BODY_B) * BTOCL_LANES + lane];
            for (int which = 0; which < 2; ++which) {  // the warm start applies the factors always
                const int applyFactors = which == 0 || (flags & BTOCL_FLAG_APPLY_FACTORS) != 0;
                const btoclSolveBody u = btoclLoadSolveBody(bodies + body, deltas + body, 0, applyFactors);
                __global float* out =
                    slotPerUnit + ((2 * slot + side) * 2 + which) * (BTOCL_LANE_PER_UNIT_FLOATS * BTOCL_LANES) + lane;
                const float values[BTOCL_LANE_PER_UNIT_FLOATS] = {u.linearPerUnit.x,  u.linearPerUnit.y,
                                                                  u.linearPerUnit.z,  u.dynamic,
                                                                  u.angularPerUnit.x, u.angularPerUnit.y,
                                                                  u.angularPerUnit.z};
                for (int f = 0; f < BTOCL_LANE_PER_UNIT_FLOATS; ++f) out[f * BTOCL_LANES] = values[f];
            }
        }
        const int numPoints = ints[BTOCL_LANE_POINTS * BTOCL_LANES + lane];
        const int firstPoint = ints[BTOCL_LANE_FIRST_POINT * BTOCL_LANES + lane];
        for (int k = 0; k < s.normalBlocks; ++k) {
            const int frictionBlock = s.frictionBlock + k * (1 + twoDirections);
            if (k >= numPoints) {
                storeLaneRow(wide, applied, pushApplied, s.normalBlock + k, lane, none, 0.0f);
                storeLaneRow(wide, applied, pushApplied, frictionBlock, lane, none, 0.0f);
                if (twoDirections) storeLaneRow(wide, applied, pushApplied, frictionBlock + 1, lane, none, 0.0f);
                continue;
            }
            const int i = firstPoint + k;
            const btoclContactPoint pt = points[i];
            const btoclBody A = bodies[pt.bodyA];
            const btoclBody B = bodies[pt.bodyB];
            const btoclContactFrame f = btoclContactFrameOf(&pt, &A, &B);
            const btoclRow normal = btoclNormalRow(&pt, &A, &B, &f, &prm);
            storeLaneRow(wide, applied, pushApplied, s.normalBlock + k, lane, btoclSolveRowOf(normal, BTOCL_ROWS_NORMAL),
                         BTOCL_ROW_APPLIED(normal));
            const btoclFrictionFrame ff = btoclFrictionFrameOf(&pt, &f, prm.solverMode);
            lateralDirs[2 * i] = ff.dir1;  // cached ones unchanged
            lateralDirs[2 * i + 1] = ff.dir2;
            const btoclRow first = btoclFrictionRow(ff.dir1, &pt, &A, &B, &f, &prm, ff.motion1, ff.cfmSlip, 0);
            storeLaneRow(wide, applied, pushApplied, frictionBlock, lane, btoclSolveRowOf(first, BTOCL_ROWS_FRICTION),
                         BTOCL_ROW_APPLIED(first));
            if (twoDirections) {
                const btoclRow second = btoclFrictionRow(ff.dir2, &pt, &A, &B, &f, &prm, ff.motion2, ff.cfmSlip, 0);
                storeLaneRow(wide, applied, pushApplied, frictionBlock + 1, lane,
                             btoclSolveRowOf(second, BTOCL_ROWS_FRICTION), BTOCL_ROW_APPLIED(second));
            }
        }
    }
}
#endif
