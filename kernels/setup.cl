// Constraint rows from contact points, one work-item per point: the normal row, one or two
// friction rows and the rolling/spinning rows (kernels/row_setup.h), written straight to their
// places in solve order. Host twin: bullet_plugin/bullet/HostRowSetup.cpp, from the same row_setup.h.
#include "btocl_shared.h"
#include "row_setup.h"

// Row `index` of the solve-order layout as the iterations read it, its starting impulses in the
// compact arrays, and for friction and rolling rows the index of their normal row. In lanes
// (lanes > 1) a friction row's normal is found by its place, and transposeRowsToLanes turns the
// rows and their impulses into blocks and clears the push impulses.
inline void storeRow(__global btoclSolveRow* rows, __global int* normalOfRow, __global float* applied,
                     __global float* pushApplied, int index, btoclRow row, int kind, int normalRow, int lanes) {
    rows[index] = btoclSolveRowOf(row, kind);
    if (kind != BTOCL_ROWS_NORMAL && lanes <= 1) normalOfRow[index] = normalRow;
    applied[index] = BTOCL_ROW_APPLIED(row);
    if (lanes <= 1) pushApplied[index] = 0.0f;
}

// rowMap: where each row (by its index in gather order) lives in the solve-order layout.
// lateralDirs: two per point, its friction directions (written back to Bullet).
__kernel void setupContactRows(__global const btoclContactPoint* points, __global const btoclBody* bodies,
                               __global const int* rowMap, __global btoclSolveRow* rows,
                               __global int* normalOfRow, __global float* applied,
                               __global float* pushApplied, __global float4* lateralDirs, btoclSetupParams prm,
                               int lanes) {
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
    storeRow(rows, normalOfRow, applied, pushApplied, normalRow, normal, BTOCL_ROWS_NORMAL, normalRow, lanes);

    if (pt.firstRollingRow >= 0) {
        float4 axis0, axis1;
        btoclPlaneSpace(pt.normalOnB, &axis0, &axis1);
        const int first = pt.firstRollingRow;
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first],
                 btoclTorsionalRow(pt.normalOnB, BTOCL_POINT_SPINNING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow, lanes);
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first + 1],
                 btoclTorsionalRow(btoclNormalize3(axis0), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow, lanes);
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first + 2],
                 btoclTorsionalRow(btoclNormalize3(axis1), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow, lanes);
    }

    const btoclFrictionFrame ff = btoclFrictionFrameOf(&pt, &f, prm.solverMode);
    lateralDirs[2 * i] = ff.dir1;  // cached ones unchanged
    lateralDirs[2 * i + 1] = ff.dir2;
    storeRow(rows, normalOfRow, applied, pushApplied, rowMap[pt.firstFrictionRow],
             btoclFrictionRow(ff.dir1, &pt, &A, &B, &f, &prm, ff.motion1, ff.cfmSlip, normalRow), BTOCL_ROWS_FRICTION,
             normalRow, lanes);
    if (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS)
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[pt.firstFrictionRow + 1],
                 btoclFrictionRow(ff.dir2, &pt, &A, &B, &f, &prm, ff.motion2, ff.cfmSlip, normalRow), BTOCL_ROWS_FRICTION,
                 normalRow, lanes);
}

// A step in lanes: the rows of each slot, set up as records at LaneLayout's setupMap places (each
// lane's rows of a kind together, as a constraint's in solve order), turned into the slot's
// blocks of W rows whose floats lie W apart (btoclWideRowFloat), one work-item a slot, with their
// starting impulses; a place of no row gets zeros (its lane is masked; no float there is left
// uninitialised). The setup writing each float to its place instead touched 20 lines a row.
inline void btoclTransposeRegion(__global const btoclSolveRow* records, __global const float* recordImpulses,
                                 __global float* wide, __global float* applied, __global float* pushApplied,
                                 int firstBlock, int blocks, int rowsPerPoint, __global const int* points,
                                 int lanes) {
    for (int lane = 0; lane < lanes; ++lane) {
        const int rows = points[lane] * rowsPerPoint;
        for (int k = 0; k < blocks; ++k) {
            const int from = firstBlock * lanes + lane * blocks + k;
            const int to = (firstBlock + k) * lanes + lane;
            btoclSolveRow r = records[from];
            float impulse = recordImpulses[from];
            if (k >= rows) {
                r.normal = r.relpos1CrossNormal = r.relpos2CrossNormal = (float4)(0.0f);
                r.angularComponentA = r.angularComponentB = (float4)(0.0f);
                impulse = 0.0f;
            }
            __global float* out = wide + (firstBlock + k) * (BTOCL_SOLVE_ROW_FLOATS * lanes) + lane;
            const float4 parts[5] = {r.normal, r.relpos1CrossNormal, r.relpos2CrossNormal, r.angularComponentA,
                                     r.angularComponentB};
            for (int v = 0; v < 5; ++v) {
                out[(4 * v) * lanes] = parts[v].x;
                out[(4 * v + 1) * lanes] = parts[v].y;
                out[(4 * v + 2) * lanes] = parts[v].z;
                out[(4 * v + 3) * lanes] = parts[v].w;
            }
            applied[to] = impulse;
            pushApplied[to] = 0.0f;
        }
    }
}

__kernel void transposeRowsToLanes(__global const btoclSolveRow* records, __global const float* recordImpulses,
                                   __global const btoclLaneSlot* slots, __global const int* laneInts,
                                   __global float* wide, __global float* applied, __global float* pushApplied,
                                   int numSlots, int lanes, int frictionPerPoint) {
    const int slot = get_global_id(0);
    if (slot >= numSlots) return;
    const btoclLaneSlot s = slots[slot];
    __global const int* points = laneInts + (slot * BTOCL_LANE_INTS + BTOCL_LANE_POINTS) * lanes;
    btoclTransposeRegion(records, recordImpulses, wide, applied, pushApplied, s.normalBlock, s.normalBlocks, 1,
                         points, lanes);
    btoclTransposeRegion(records, recordImpulses, wide, applied, pushApplied, s.frictionBlock, s.frictionBlocks,
                         frictionPerPoint, points, lanes);
}
