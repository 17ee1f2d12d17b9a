// Global split (docs/architecture.md, "The global split"): a cell key per constraint; the stable
// sort by key and the scan over key bins are DevicePrimitives' (kernels/primitives.cl); then the
// groups (one per non-empty key, set-major) and each set's first group. Deterministic: no atomics.
#include "btocl_shared.h"
#include "split_grid.h"


// One work-group: work-item p takes the bounds of the positions of constraints
// [p * chunk, (p + 1) * chunk), then work-item 0 the whole box from the parts, in order, and the
// grid of this step.
__kernel void splitBoundsAndGrid(__global const btoclConstraint* constraints, int n, int chunk, float baseCell,
                                 __global btoclSplitGrid* grid, __local float4* partMin, __local float4* partMax) {
    const int p = get_local_id(0);
    const int begin = min(n, p * chunk), end = min(n, begin + chunk);
    float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
    for (int i = begin; i < end; ++i) {
        const float4 x = constraints[i].position;
        lo = fmin(lo, x);  // NaN is ignored, as on the host
        hi = fmax(hi, x);
    }
    partMin[p] = lo;
    partMax[p] = hi;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (p != 0) return;
    lo = (float4)(INFINITY);
    hi = (float4)(-INFINITY);
    for (int q = 0; q < (int)get_local_size(0); ++q) {
        lo = fmin(lo, partMin[q]);
        hi = fmax(hi, partMax[q]);
    }
    *grid = btoclMakeSplitGrid(lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, baseCell);
}

// Key and identity index per constraint. A constraint with a too-big dynamic body gets the
// overflow key; body indices out of range never read past overflowBody.
__kernel void splitKeys(__global const btoclConstraint* constraints, int n, __global const uchar* overflowBody,
                        int numBodies, __global const btoclSplitGrid* gridIn, __global uint* keys,
                        __global int* indices) {
    const int i = get_global_id(0);
    if (i >= n) return;
    const btoclSplitGrid g = *gridIn;
    const int a = constraints[i].bodyA, b = constraints[i].bodyB;
    const bool overA = constraints[i].dynamicA && a >= 0 && a < numBodies && overflowBody[a];
    const bool overB = constraints[i].dynamicB && b >= 0 && b < numBodies && overflowBody[b];
    int key = g.overflowKey;
    if (!overA && !overB) {
        const float4 pos = constraints[i].position;
        const int cx = btoclSplitCellCoord(BTOCL_AXIS(pos, g.axisU), g.originU, g.invCell, g.nx);
        const int cy = btoclSplitCellCoord(BTOCL_AXIS(pos, g.axisV), g.originV, g.invCell, g.ny);
        key = btoclSplitKeyOfCell(g, cx, cy);
    }
    keys[i] = (uint)key;
    indices[i] = i;
}

// Key ranges of the sorted keys, and a flag on each non-empty bin. binStart, binEnd and flags
// start all 0 (filled by the host).
__kernel void splitMarkBins(__global const uint* keys, int n, __global int* binStart, __global int* binEnd,
                            __global int* flags) {
    const int i = get_global_id(0);
    if (i >= n) return;
    const uint k = keys[i];
    if (i == 0 || keys[i - 1] != k) {
        binStart[k] = i;
        flags[k] = 1;
    }
    if (i == n - 1 || keys[i + 1] != k) binEnd[k] = i + 1;
}

// One work-item per bin. groupOfBin: the exclusive scan of the flags, i.e. the group index of
// each non-empty bin. serialRuns: the serial path builds no local batches; each group is then one
// run, walked in order by one work-item (numBatches 1, its batch ending at the group's end).
// Work-item 0 also writes the summary: [0..5] setGroupStart, [6] overflow constraints, [7] the
// cell edge's bits. The overflow key is the largest key there is, so it closes the count of groups.
__kernel void splitWriteGroups(__global const int* binStart, __global const int* binEnd, __global const int* groupOfBin,
                               __global const btoclSplitGrid* gridIn, __global btoclGroup* groups, int serialRuns,
                               __global int* batchEnd, __global int* summary) {
    const int b = get_global_id(0);
    if (b == 0) {
        const btoclSplitGrid g = *gridIn;
        const int overflowCount = binEnd[g.overflowKey] - binStart[g.overflowKey];
        for (int s = 0; s <= BTOCL_NUM_SETS; ++s) summary[s] = groupOfBin[s * g.cellsPerSet];
        summary[BTOCL_NUM_SETS + 1] = groupOfBin[g.overflowKey] + (overflowCount > 0 ? 1 : 0);
        summary[BTOCL_NUM_SETS + 2] = overflowCount;
        summary[BTOCL_NUM_SETS + 3] = as_int(g.cellSize);
    }
    if (binEnd[b] <= binStart[b]) return;
    btoclGroup g;
    g.offset = binStart[b];
    g.count = binEnd[b] - binStart[b];
    g.numBatches = serialRuns ? 1 : 0;
    g.cell = btoclSplitCellOfKey(*gridIn, b);
    groups[groupOfBin[b]] = g;
    if (serialRuns) batchEnd[g.offset] = g.offset + g.count;
}
