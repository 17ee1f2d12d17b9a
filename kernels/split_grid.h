// The grid of the global split, shared word for word by the host reference (C++) and the device
// (OpenCL C), so that both put every constraint into the same cell, bit for bit: the same float
// operations in the same order, no division on the per-constraint path, no a*b+c to contract.
#ifndef BTOCL_SPLIT_GRID_H
#define BTOCL_SPLIT_GRID_H

#include "btocl_shared.h"

#ifndef __OPENCL_VERSION__
#include <math.h>  // the float overloads of floor, fmin, fmax in the global namespace
#endif

// Cells per grid axis at most. The cell is enlarged instead, so the key range stays below 2^16:
// 4 sets * 127 * 127 + 1 overflow key < 65536, two 8-bit radix passes on the device.
#define BTOCL_SPLIT_MAX_CELLS 254
#define BTOCL_SPLIT_KEY_BITS 16
#define BTOCL_SPLIT_NUM_KEYS (1 << BTOCL_SPLIT_KEY_BITS)

// The grid of one step: cells of edge cellSize on the two widest axes of the constraints' bounding
// box, numbered from its minimum corner.
typedef struct {
    float originU, originV;  // the bounding box's minimum on the two grid axes
    float invCell;           // 1 / cellSize
    float cellSize;
    int axisU, axisV;        // 0 = x, 1 = y, 2 = z
    int nx, ny;              // cells along axisU, axisV (1..BTOCL_SPLIT_MAX_CELLS)
    int halfNx;              // cells per row inside one set: (nx + 1) / 2
    int cellsPerSet;         // halfNx * ((ny + 1) / 2)
    int overflowKey;         // 4 * cellsPerSet: the key of the overflow group, after all sets
    int pad;
} btoclSplitGrid;

#define BTOCL_AXIS(p, a) ((a) == 0 ? (p).x : (a) == 1 ? (p).y : (p).z)

// Cells along one axis of width w: at least 1, at most BTOCL_SPLIT_MAX_CELLS.
BTOCL_INLINE int btoclSplitCellsAlong(float w, float invCell) {
    float f = floor(w * invCell);
    f = fmin(fmax(f, 0.0f), (float)(BTOCL_SPLIT_MAX_CELLS - 1));  // NaN becomes 0
    return (int)f + 1;
}

// bmin/bmax: the bounding box of the constraints' positions; baseCell: the cell edge the bodies ask
// for (0 or less = none). Non-finite widths (a broken input) count as 0 so nothing overflows.
BTOCL_INLINE btoclSplitGrid btoclMakeSplitGrid(float minX, float minY, float minZ, float maxX, float maxY,
                                                     float maxZ, float baseCell) {
    float lo[3];
    float w[3];
    lo[0] = minX;
    lo[1] = minY;
    lo[2] = minZ;
    w[0] = maxX - minX;
    w[1] = maxY - minY;
    w[2] = maxZ - minZ;
    for (int i = 0; i < 3; ++i)
        if (!(w[i] >= 0.0f && w[i] <= 3.0e38f)) w[i] = 0.0f;
    int u = 0;
    for (int i = 1; i < 3; ++i)
        if (w[i] > w[u]) u = i;
    int v = u == 0 ? 1 : 0;
    for (int i = 0; i < 3; ++i)
        if (i != u && w[i] > w[v]) v = i;

    float cell = (baseCell > 0.0f && baseCell <= 3.0e38f) ? baseCell : 1.0f;
    // Enlarge the cell rather than exceed BTOCL_SPLIT_MAX_CELLS per axis (w[v] <= w[u]).
    cell = fmax(cell, w[u] * (1.0f / (float)BTOCL_SPLIT_MAX_CELLS));

    btoclSplitGrid g;
    g.originU = lo[u];
    g.originV = lo[v];
    g.cellSize = cell;
    g.invCell = 1.0f / cell;
    g.axisU = u;
    g.axisV = v;
    g.nx = btoclSplitCellsAlong(w[u], g.invCell);
    g.ny = btoclSplitCellsAlong(w[v], g.invCell);
    g.halfNx = (g.nx + 1) / 2;
    g.cellsPerSet = g.halfNx * ((g.ny + 1) / 2);
    g.overflowKey = 4 * g.cellsPerSet;
    g.pad = 0;
    return g;
}

// Cell coordinate of p along one axis, relative to the box and clamped (NaN goes to cell 0).
BTOCL_INLINE int btoclSplitCellCoord(float p, float origin, float invCell, int n) {
    float c = floor((p - origin) * invCell);
    c = fmin(fmax(c, 0.0f), (float)(n - 1));
    return (int)c;
}

// Sort key of a cell: set-major (set = 2x2 checkerboard colour), then row, then column inside the set.
BTOCL_INLINE int btoclSplitKeyOfCell(btoclSplitGrid g, int cx, int cy) {
    int set = (cx & 1) + 2 * (cy & 1);
    return set * g.cellsPerSet + (cy >> 1) * g.halfNx + (cx >> 1);
}

// The linear cell index (cy * nx + cx) of a key, or -1 for the overflow key.
BTOCL_INLINE int btoclSplitCellOfKey(btoclSplitGrid g, int key) {
    if (key >= g.overflowKey) return -1;
    int set = key / g.cellsPerSet;
    int rest = key - set * g.cellsPerSet;
    int cx = 2 * (rest % g.halfNx) + (set & 1);
    int cy = 2 * (rest / g.halfNx) + (set >> 1);
    return cy * g.nx + cx;
}

#endif
