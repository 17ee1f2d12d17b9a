// A slot of a step in lanes set up (docs/architecture.md, "Lanes"): each lane's points' rows from
// the row code of row_setup.h, written to the slot's blocks lane by lane (btoclWideRowFloat's
// layout); and each body's per-unit scales, the warm start's and the other passes'
// (BTOCL_BODY_PER_UNIT_FLOATS). Written once for the device (kernels/setup.cl, setupLaneSlots: one
// work-item a slot) and the host (bullet_plugin/step/HostLaneSolve.cpp), so both give the
// one-lane setup's bits.
#ifndef BTOCL_LANE_SETUP_H
#define BTOCL_LANE_SETUP_H

#include "row_setup.h"
#include "row_solve.h"

// Row `r` to lane `lane` of block `block` of `lanes`-wide blocks, its starting impulse with it: a
// row of zeros and no impulse where the lane has no row there (masked in the solve; no float
// left uninitialised).
BTOCL_INLINE void btoclStoreLaneRow(BTOCL_GLOBAL float* wide, BTOCL_GLOBAL float* applied,
                                    BTOCL_GLOBAL float* pushApplied, int lanes, int block, int lane,
                                    btoclSolveRow r, float impulse) {
    BTOCL_GLOBAL float* out = wide + btoclWideRowFloat(block * lanes + lane, 0, lanes);
    const btoclFloat4 parts[3] = {r.normal, r.relpos1CrossNormal, r.relpos2CrossNormal};
    for (int v = 0; v < 3; ++v) {
        out[(4 * v) * lanes] = parts[v].x;
        out[(4 * v + 1) * lanes] = parts[v].y;
        out[(4 * v + 2) * lanes] = parts[v].z;
        out[(4 * v + 3) * lanes] = parts[v].w;
    }
    // The push rhs, or where a row has none (a friction row's is 0) its friction coefficient: a
    // push rhs of -0 becomes +0, which the push pass skips as it skips -0.
    out[BTOCL_LANE_ROW_SHARED * lanes] = r.angularComponentA.w != 0.0f ? r.angularComponentA.w : r.angularComponentB.w;
    applied[block * lanes + lane] = impulse;
    pushApplied[block * lanes + lane] = 0.0f;
}

#ifndef __OPENCL_VERSION__
// Body `body`'s per-unit scales, the warm start's and the other passes', into its
// BTOCL_BODY_PER_UNIT_FLOATS floats of `bodyPerUnit` (every body's): set by the host for every
// device, a few floats a body.
BTOCL_INLINE void btoclSetupBodyPerUnit(const btoclBody* bodies, const btoclBodyDelta* deltas, int body,
                                        float* bodyPerUnit, int flags) {
    for (int which = 0; which < 2; ++which) {  // the warm start applies the factors always
        const int applyFactors = which == 0 || (flags & BTOCL_FLAG_APPLY_FACTORS) != 0;
        const btoclSolveBody u = btoclLoadSolveBody(bodies + body, deltas + body, 0, applyFactors);
        float* out = bodyPerUnit + body * BTOCL_BODY_PER_UNIT_FLOATS + which * (BTOCL_BODY_PER_UNIT_FLOATS / 2);
        const float values[BTOCL_BODY_PER_UNIT_FLOATS / 2] = {u.linearPerUnit.x,  u.linearPerUnit.y,
                                                              u.linearPerUnit.z,  u.dynamic,
                                                              u.angularPerUnit.x, u.angularPerUnit.y,
                                                              u.angularPerUnit.z, 0.0f};
        for (int f = 0; f < BTOCL_BODY_PER_UNIT_FLOATS / 2; ++f) out[f] = values[f];
    }
}
#endif

// The rows of lane `lane` of slot s (its lanes' ints `ints`) into `wide`, `applied` and
// `pushApplied`, and its points' friction directions into lateralDirs (two a point, as
// setupContactRows writes them).
BTOCL_INLINE void btoclSetupLaneRows(BTOCL_GLOBAL const btoclContactPoint* points, BTOCL_GLOBAL const btoclBody* bodies,
                                     btoclLaneSlot s, BTOCL_GLOBAL const int* ints, int lane, BTOCL_GLOBAL float* wide,
                                     BTOCL_GLOBAL float* applied, BTOCL_GLOBAL float* pushApplied,
                                     BTOCL_GLOBAL btoclFloat4* lateralDirs, const btoclSetupParams* prm, int lanes) {
    const int twoDirections = (prm->solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) != 0;
    const btoclSolveRow none = {btoclZero4(), btoclZero4(), btoclZero4(), btoclZero4(), btoclZero4()};
    const int numPoints = ints[BTOCL_LANE_POINTS * lanes + lane];
    const int firstPoint = ints[BTOCL_LANE_FIRST_POINT * lanes + lane];
    for (int k = 0; k < s.normalBlocks; ++k) {
        const int frictionBlock = s.frictionBlock + k * (1 + twoDirections);
        if (k >= numPoints) {
            btoclStoreLaneRow(wide, applied, pushApplied, lanes, s.normalBlock + k, lane, none, 0.0f);
            btoclStoreLaneRow(wide, applied, pushApplied, lanes, frictionBlock, lane, none, 0.0f);
            if (twoDirections)
                btoclStoreLaneRow(wide, applied, pushApplied, lanes, frictionBlock + 1, lane, none, 0.0f);
            continue;
        }
        const int i = firstPoint + k;
        const btoclContactPoint pt = points[i];
        const btoclBody A = bodies[pt.bodyA];
        const btoclBody B = bodies[pt.bodyB];
        const btoclContactFrame f = btoclContactFrameOf(&pt, &A, &B);
        const btoclRow normal = btoclNormalRow(&pt, &A, &B, &f, prm);
        btoclStoreLaneRow(wide, applied, pushApplied, lanes, s.normalBlock + k, lane,
                          btoclSolveRowOf(normal, BTOCL_ROWS_NORMAL, &A, &B), BTOCL_ROW_APPLIED(normal));
        const btoclFrictionFrame ff = btoclFrictionFrameOf(&pt, &f, prm->solverMode);
        lateralDirs[2 * i] = ff.dir1;  // cached ones unchanged
        lateralDirs[2 * i + 1] = ff.dir2;
        const btoclRow first = btoclFrictionRow(ff.dir1, &pt, &A, &B, &f, prm, ff.motion1, ff.cfmSlip, 0);
        btoclStoreLaneRow(wide, applied, pushApplied, lanes, frictionBlock, lane,
                          btoclSolveRowOf(first, BTOCL_ROWS_FRICTION, &A, &B), BTOCL_ROW_APPLIED(first));
        if (twoDirections) {
            const btoclRow second = btoclFrictionRow(ff.dir2, &pt, &A, &B, &f, prm, ff.motion2, ff.cfmSlip, 0);
            btoclStoreLaneRow(wide, applied, pushApplied, lanes, frictionBlock + 1, lane,
                              btoclSolveRowOf(second, BTOCL_ROWS_FRICTION, &A, &B), BTOCL_ROW_APPLIED(second));
        }
    }
}

// Slot s (its lanes' ints `ints`) of a layout `lanes` wide: every lane's rows.
BTOCL_INLINE void btoclSetupLaneSlot(BTOCL_GLOBAL const btoclContactPoint* points, BTOCL_GLOBAL const btoclBody* bodies,
                                     btoclLaneSlot s, BTOCL_GLOBAL const int* ints, BTOCL_GLOBAL float* wide,
                                     BTOCL_GLOBAL float* applied, BTOCL_GLOBAL float* pushApplied,
                                     BTOCL_GLOBAL btoclFloat4* lateralDirs, const btoclSetupParams* prm, int lanes) {
    for (int lane = 0; lane < lanes; ++lane)
        btoclSetupLaneRows(points, bodies, s, ints, lane, wide, applied, pushApplied, lateralDirs, prm, lanes);
}

#endif
