// Constraint rows from contact points, one work-item per point: the normal row, one or two
// friction rows and the rolling/spinning rows (kernels/row_setup.h), written straight to their
// places in solve order. Host twin: bullet_plugin/HostRowSetup.cpp, from the same row_setup.h.
#include "btocl_shared.h"
#include "row_setup.h"

// Row `index` of the solve-order layout, and its starting impulses in the compact arrays.
inline void storeRow(__global btoclRow* rows, __global float* applied, __global float* pushApplied, int index,
                     btoclRow row) {
    rows[index] = row;
    applied[index] = BTOCL_ROW_APPLIED(row);
    pushApplied[index] = 0.0f;
}

// rowMap: where each row (by its index in gather order) lives in the solve-order layout.
// lateralDirs: two per point, its friction directions (written back to Bullet).
__kernel void setupContactRows(__global const btoclContactPoint* points, __global const btoclBody* bodies,
                               __global const int* rowMap, __global btoclRow* rows, __global float* applied,
                               __global float* pushApplied, __global float4* lateralDirs, __global int* control,
                               btoclSetupParams prm) {
    const int i = get_global_id(0);
    if (i >= prm.numPoints) return;
    const btoclContactPoint pt = points[i];
    const btoclBody A = bodies[pt.bodyA];
    const btoclBody B = bodies[pt.bodyB];
    const btoclContactFrame f = btoclContactFrameOf(&pt, &A, &B);

    const int normalRow = rowMap[i];
    const btoclRow normal = btoclNormalRow(&pt, &A, &B, &f, &prm);
    storeRow(rows, applied, pushApplied, normalRow, normal);
    // Most steps have no point this deep: the host then launches no split-impulse pass.
    if (BTOCL_ROW_RHS_PENETRATION(normal) != 0.0f) atomic_or(control + BTOCL_CONTROL_HAS_PENETRATION, 1);

    if (pt.firstRollingRow >= 0) {
        float4 axis0, axis1;
        btoclPlaneSpace(pt.normalOnB, &axis0, &axis1);
        const int first = pt.firstRollingRow;
        storeRow(rows, applied, pushApplied, rowMap[first],
                 btoclTorsionalRow(pt.normalOnB, BTOCL_POINT_SPINNING_FRICTION(pt), &pt, &A, &B, &f, normalRow));
        storeRow(rows, applied, pushApplied, rowMap[first + 1],
                 btoclTorsionalRow(btoclNormalize3(axis0), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow));
        storeRow(rows, applied, pushApplied, rowMap[first + 2],
                 btoclTorsionalRow(btoclNormalize3(axis1), BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, normalRow));
    }

    const btoclFrictionFrame ff = btoclFrictionFrameOf(&pt, &f, prm.solverMode);
    lateralDirs[2 * i] = ff.dir1;  // cached ones unchanged
    lateralDirs[2 * i + 1] = ff.dir2;
    storeRow(rows, applied, pushApplied, rowMap[pt.firstFrictionRow],
             btoclFrictionRow(ff.dir1, &pt, &A, &B, &f, &prm, ff.motion1, ff.cfmSlip, normalRow));
    if (prm.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS)
        storeRow(rows, applied, pushApplied, rowMap[pt.firstFrictionRow + 1],
                 btoclFrictionRow(ff.dir2, &pt, &A, &B, &f, &prm, ff.motion2, ff.cfmSlip, normalRow));
}
