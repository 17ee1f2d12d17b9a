// Lays the constraints and their rows out in solve order (set, group, batch), so that every
// solve pass streams through memory instead of jumping across it. Rows fall into two regions,
// one per kind of pass: first every constraint's joint and normal rows, in solve order, then every
// constraint's friction and rolling rows, in solve order (the normal pass and the friction pass
// each read one region front to back; interleaved, the friction rows the normal pass skips would
// still cross the memory bus).
// Host reference: the layout checks of tests/test_device_solve.cpp (rows read back through the map).
#include "btocl_shared.h"
#include "row_setup.h"

// Rows of the constraint at solve position i: normalCounts[i] in the first region, frictionCounts[i]
// in the second (btoclInFrictionRegion).
__kernel void countRowsInSolveOrder(__global const int* solveOrder, __global const btoclConstraint* constraints,
                                    __global int* normalCounts, __global int* frictionCounts, int n) {
    const int i = get_global_id(0);
    if (i >= n) return;
    if (BTOCL_PREFETCHES && i + 8 < n) BTOCL_PREFETCH(constraints + solveOrder[i + 8]);
    const btoclConstraint c = constraints[solveOrder[i]];
    int counts[2] = {0, 0};
    for (int kind = 0; kind < BTOCL_NUM_ROW_KINDS; ++kind) counts[btoclInFrictionRegion(kind)] += c.numRows[kind];
    normalCounts[i] = counts[0];
    frictionCounts[i] = counts[1];
}

// Constraint solveOrder[i] goes to position i, its rows of the first region from normalBase[i]
// on, those of the second from frictionRegion + frictionBase[i]; rowMap records the new index of
// each of its rows (indexed by the row's index in gather order).
__kernel void placeConstraints(__global const int* solveOrder, __global const btoclConstraint* constraints,
                               __global const int* normalBase, __global const int* frictionBase, int frictionRegion,
                               __global btoclConstraint* placed, __global int* rowMap, int n) {
    const int i = get_global_id(0);
    if (i >= n) return;
    if (BTOCL_PREFETCHES) {
        // Constraints lie in gather order, read here in solve order, and their rows' map entries
        // lie by gather order too: the record 16 ahead asked for, and the entries of the one 8
        // ahead, whose record was asked for 8 constraints ago.
        if (i + 16 < n) BTOCL_PREFETCH(constraints + solveOrder[i + 16]);
        if (i + 8 < n) {
            __global const btoclConstraint* ahead = constraints + solveOrder[i + 8];
            BTOCL_PREFETCH(rowMap + ahead->firstRow[BTOCL_ROWS_NORMAL]);
            BTOCL_PREFETCH(rowMap + ahead->firstRow[BTOCL_ROWS_FRICTION]);
        }
    }
    btoclConstraint c = constraints[solveOrder[i]];
    int next[2] = {normalBase[i], frictionRegion + frictionBase[i]};
    for (int kind = 0; kind < BTOCL_NUM_ROW_KINDS; ++kind) {
        const int region = btoclInFrictionRegion(kind);
        for (int k = 0; k < c.numRows[kind]; ++k) rowMap[c.firstRow[kind] + k] = next[region] + k;
        c.firstRow[kind] = next[region];
        next[region] += c.numRows[kind];
    }
    placed[i] = c;
}

// Rows set up on the host, gather rows [base, base + n), to their places as the iterations read
// them; their starting impulses to the compact arrays that the solve updates.
__kernel void placeRows(__global const btoclRow* in, int base, __global const int* rowMap,
                        __global btoclSolveRow* out, __global int* normalOfRow, __global float* applied,
                        __global float* pushApplied, int n, btoclRowRegions regions,
                        __global const btoclBody* bodies) {
    const int r = get_global_id(0);
    if (r >= n) return;
    const btoclRow row = in[r];
    const int g = base + r;
    const int to = rowMap[g];
    const btoclBody A = bodies[row.bodyA], B = bodies[row.bodyB];
    out[to] = btoclSolveRowOf(row, btoclKindOfRow(&regions, g), &A, &B);
    if (row.frictionIndex >= 0) normalOfRow[to] = rowMap[row.frictionIndex];
    applied[to] = BTOCL_ROW_APPLIED(row);
    pushApplied[to] = BTOCL_ROW_APPLIED_PUSH(row);
}

// The download: the applied impulses of rows [0, n), from solve order back to gather order, for
// the write-back.
__kernel void impulsesToGatherOrder(__global const float* applied, __global const int* rowMap, __global float* out,
                                    int n) {
    const int r = get_global_id(0);
    if (BTOCL_PREFETCHES && r + 16 < n) BTOCL_PREFETCH(applied + rowMap[r + 16]);  // scattered in solve order
    if (r < n) out[r] = applied[rowMap[r]];
}
