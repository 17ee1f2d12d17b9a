// Constraint rows from contact points, one work-item per point: the normal row, one or two
// friction rows and the rolling/spinning rows (kernels/row_setup.h), written straight to their
// places in solve order. Host twin: bullet_plugin/bullet/HostRowSetup.cpp, from the same row_setup.h.
#include "btocl_shared.h"
#include "row_setup.h"
#include "row_solve.h"

// Row `index` of the solve-order layout as the iterations read it, its starting impulses in the
// compact arrays, and for friction and rolling rows the index of their normal row.
inline void storeRow(__global btoclSolveRow* rows, __global int* normalOfRow, __global float* applied,
                     __global float* pushApplied, int index, btoclRow row, int kind, int normalRow,
                     const btoclBody* A, const btoclBody* B) {
    rows[index] = btoclSolveRowOf(row, kind, A, B);
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
    storeRow(rows, normalOfRow, applied, pushApplied, normalRow, normal, BTOCL_ROWS_NORMAL, normalRow, &A, &B);

    if (pt.firstRollingRow >= 0) {
        float4 axis0, axis1;
        btoclPlaneSpace(pt.normalOnB, &axis0, &axis1);
        const int first = pt.firstRollingRow;
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first],
                 btoclTorsionalRow(pt.normalOnB, BTOCL_POINT_SPINNING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow, &A, &B);
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first + 1],
                 btoclTorsionalRow(btoclNormalize3(axis0), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow, &A, &B);
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[first + 2],
                 btoclTorsionalRow(btoclNormalize3(axis1), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow),
                 BTOCL_ROWS_ROLLING, normalRow, &A, &B);
    }

    const btoclFrictionFrame ff = btoclFrictionFrameOf(&pt, &f, prm.solverMode);
    lateralDirs[2 * i] = ff.dir1;  // cached ones unchanged
    lateralDirs[2 * i + 1] = ff.dir2;
    const int friction = btoclFirstFrictionRow(&prm, i);
    storeRow(rows, normalOfRow, applied, pushApplied, rowMap[friction],
             btoclFrictionRow(ff.dir1, &pt, &A, &B, &f, &prm, ff.motion1, ff.cfmSlip, normalRow), BTOCL_ROWS_FRICTION,
             normalRow, &A, &B);
    if (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS)
        storeRow(rows, normalOfRow, applied, pushApplied, rowMap[friction + 1],
                 btoclFrictionRow(ff.dir2, &pt, &A, &B, &f, &prm, ff.motion2, ff.cfmSlip, normalRow), BTOCL_ROWS_FRICTION,
                 normalRow, &A, &B);
}

#if defined(BTOCL_LANES) && BTOCL_LANES > 1
#include "lane_setup.h"

// A step in lanes (kernels/lane_solve.h), one work-item a slot (lane_setup.h): each lane's points'
// rows set up as setupContactRows sets them up (the same row code, so the same bits), written to
// the slot's blocks lane by lane, so that a block's cache lines are written whole by one
// work-item (the rows written from point order touched 20 lines a row).
__kernel void setupLaneSlots(__global const btoclContactPoint* points, __global const btoclBody* bodies,
                             __global const btoclLaneSlot* slots, __global const int* laneInts, __global float* wide,
                             __global float* applied, __global float* pushApplied, __global float4* lateralDirs,
                             btoclSetupParams prm, int numSlots) {
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
    btoclSetupLaneSlot(points, bodies, slots[slot], ints, wide, applied, pushApplied, lateralDirs, &prm, BTOCL_LANES);
}
#endif
