// Lays the constraints and their rows out in solve order (set, group, batch), so that every
// solve pass streams through memory instead of jumping across it. A constraint's rows stay
// together, kind after kind: [joint rows][normal rows][friction rows][rolling rows].
// Host reference: the layout checks of tests/test_device_solve.cpp (rows read back through the map).
#include "btocl_shared.h"

inline int rowCount(const btoclConstraint* c) {
    int n = 0;
    for (int kind = 0; kind < BTOCL_NUM_ROW_KINDS; ++kind) n += c->numRows[kind];
    return n;
}

__kernel void countRowsInSolveOrder(__global const int* solveOrder, __global const btoclConstraint* constraints,
                                    __global int* counts, int n) {
    const int i = get_global_id(0);
    if (i >= n) return;
    const btoclConstraint c = constraints[solveOrder[i]];
    counts[i] = rowCount(&c);
}

// Constraint solveOrder[i] goes to position i with its rows from rowBase[i] on; rowMap records
// the new index of each of its rows (indexed by the row's index in gather order).
__kernel void placeConstraints(__global const int* solveOrder, __global const btoclConstraint* constraints,
                               __global const int* rowBase, __global btoclConstraint* placed,
                               __global int* rowMap, int n) {
    const int i = get_global_id(0);
    if (i >= n) return;
    btoclConstraint c = constraints[solveOrder[i]];
    int next = rowBase[i];
    for (int kind = 0; kind < BTOCL_NUM_ROW_KINDS; ++kind) {
        for (int k = 0; k < c.numRows[kind]; ++k) rowMap[c.firstRow[kind] + k] = next + k;
        c.firstRow[kind] = next;
        next += c.numRows[kind];
    }
    placed[i] = c;
}

// Rows set up on the host, gather rows [base, base + n), to their places; their starting
// impulses to the compact arrays that the solve updates.
__kernel void placeRows(__global const btoclRow* in, int base, __global const int* rowMap, __global btoclRow* out,
                        __global float* applied, __global float* pushApplied, int n) {
    const int r = get_global_id(0);
    if (r >= n) return;
    btoclRow row = in[r];
    if (row.frictionIndex >= 0) row.frictionIndex = rowMap[row.frictionIndex];
    const int to = rowMap[base + r];
    out[to] = row;
    applied[to] = BTOCL_ROW_APPLIED(row);
    pushApplied[to] = BTOCL_ROW_APPLIED_PUSH(row);
}

// The applied impulse of rows [0, n) in gather order, for the write-back to the manifold points.
__kernel void gatherAppliedImpulses(__global const float* applied, __global const int* rowMap, __global float* out,
                                    int n) {
    const int r = get_global_id(0);
    if (r < n) out[r] = applied[rowMap[r]];
}
