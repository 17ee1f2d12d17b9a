#include "HostSplit.h"

#include "HostArray.h"
#include "HostParallel.h"
#include "btOpenCLSolverError.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace btocl {
namespace {

// The constraints' bounds are taken in this many fixed chunks (makeSplitGridHost).
constexpr size_t kSplitChunks = 16;

void checkBodyIndex(int body, size_t numBodies, size_t constraint) {
    if (body < 0 || size_t(body) >= numBodies)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: constraint " + std::to_string(constraint) +
                                  " names body " + std::to_string(body) + " but there are " +
                                  std::to_string(numBodies) + " bodies");
}

}  // namespace

int splitKeyOfConstraint(const btoclConstraint& c, const btoclSplitGrid& g, const std::vector<unsigned char>& overflowBody) {
    const int nb = int(overflowBody.size());
    const bool overA = c.dynamicA && c.bodyA >= 0 && c.bodyA < nb && overflowBody[size_t(c.bodyA)];
    const bool overB = c.dynamicB && c.bodyB >= 0 && c.bodyB < nb && overflowBody[size_t(c.bodyB)];
    if (overA || overB) return g.overflowKey;
    const int cx = btoclSplitCellCoord(BTOCL_AXIS(c.position, g.axisU), g.originU, g.invCell, g.nx);
    const int cy = btoclSplitCellCoord(BTOCL_AXIS(c.position, g.axisV), g.originV, g.invCell, g.ny);
    return btoclSplitKeyOfCell(g, cx, cy);
}

btoclSplitGrid makeSplitGridHost(const btoclConstraint* constraints, size_t n, float baseCellSize) {
    // The bounds of fixed chunks, on the host's threads, then of the chunks in their order: the
    // same result whichever thread takes a chunk (the loop reads memory the gather's threads
    // just wrote, and one thread waited on it).
    struct Bounds {
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        void include(const float* low, const float* high) {
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::fmin(lo[a], low[a]);
                hi[a] = std::fmax(hi[a], high[a]);
            }
        }
    };
    std::array<Bounds, kSplitChunks> chunks{};
    parallelFor(kSplitChunks, [&](size_t k) {
        for (size_t i = n * k / kSplitChunks; i < n * (k + 1) / kSplitChunks; ++i) {
            const btoclFloat4& p = constraints[i].position;
            const float point[3] = {p.x, p.y, p.z};
            chunks[k].include(point, point);
        }
    }, n / kSplitChunks);
    Bounds all;
    for (const Bounds& b : chunks) all.include(b.lo, b.hi);
    return btoclMakeSplitGrid(all.lo[0], all.lo[1], all.lo[2], all.hi[0], all.hi[1], all.hi[2], baseCellSize);
}

void splitHostInto(const btoclConstraint* constraints, size_t count, const std::vector<SplitBody>& bodies,
                   const SplitParams& params, bool serialRuns, BatchLayout& layout) {
    const SplitBodiesPlan plan = planSplitBodies(bodies, params);
    // Every constraint's bodies checked (a btOpenCLSolverError) before the layout changes.
    parallelFor(count, [&](size_t i) {
        checkBodyIndex(constraints[i].bodyA, bodies.size(), i);
        checkBodyIndex(constraints[i].bodyB, bodies.size(), i);
    });
    btoclSplitGrid grid{};
    if (count > 0) grid = makeSplitGridHost(constraints, count, plan.baseCellSize);
    const int n = int(count);
    resizeForOverwrite(layout.solveOrder, size_t(n));
    resizeForOverwrite(layout.batchEnd, size_t(n));
    std::fill(layout.batchEnd.begin(), layout.batchEnd.end(), 0);
    layout.groups.clear();
    layout.setGroupStart.fill(0);
    layout.cellSize = 0;
    layout.numOverflowConstraints = 0;
    layout.serialRuns = serialRuns;
    if (n == 0) return;

    layout.cellSize = grid.cellSize;
    // Stable counting sort by key: each group's constraints stay in index order.
    std::vector<int> keys(static_cast<size_t>(n));
    parallelFor(size_t(n), [&](size_t i) { keys[i] = splitKeyOfConstraint(constraints[i], grid, plan.overflowBody); });
    std::vector<int> start(size_t(grid.overflowKey) + 2, 0);
    for (int key : keys) ++start[size_t(key) + 1];
    for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int i = 0; i < n; ++i) layout.solveOrder[size_t(fill[size_t(keys[size_t(i)])]++)] = i;

    int set = 0;
    for (int key = 0; key <= grid.overflowKey; ++key) {
        const int keySet = key == grid.overflowKey ? BTOCL_OVERFLOW_SET : key / grid.cellsPerSet;
        while (set < keySet) layout.setGroupStart[size_t(++set)] = int(layout.groups.size());
        const int first = start[size_t(key)], size = start[size_t(key) + 1] - first;
        if (size == 0) continue;
        layout.groups.push_back(btoclGroup{first, size, serialRuns ? 1 : 0, btoclSplitCellOfKey(grid, key)});
        if (serialRuns) layout.batchEnd[size_t(first)] = first + size;
    }
    layout.setGroupStart[BTOCL_NUM_SETS + 1] = int(layout.groups.size());
    layout.numOverflowConstraints = start[size_t(grid.overflowKey) + 1] - start[size_t(grid.overflowKey)];
}

BatchLayout splitHost(const std::vector<btoclConstraint>& constraints, const std::vector<SplitBody>& bodies,
                      const SplitParams& params) {
    BatchLayout layout;
    splitHostInto(constraints.data(), constraints.size(), bodies, params, false, layout);
    return layout;
}

std::vector<int> cutCells(std::vector<std::pair<int, long long>> cells, int parts) {
    std::sort(cells.begin(), cells.end());
    long long total = 0;
    for (const auto& cell : cells) total += cell.second;
    std::vector<int> cuts;
    long long before = 0;
    for (const auto& cell : cells) {
        // The cell goes to the part its middle falls in.
        const long long middle = 2 * before + cell.second;
        while (int(cuts.size()) + 1 < parts && middle * parts >= 2 * total * (long long)(cuts.size() + 1))
            cuts.push_back(cell.first);
        before += cell.second;
    }
    while (int(cuts.size()) + 1 < parts) cuts.push_back(std::numeric_limits<int>::max());
    return cuts;
}

std::vector<int> cellCuts(const BatchLayout& split, int parts) {
    std::vector<std::pair<int, long long>> cells;  // (cell, constraints) of every cell group
    for (int g = 0; g < split.setGroupStart[BTOCL_OVERFLOW_SET]; ++g)
        cells.emplace_back(split.groups[size_t(g)].cell, split.groups[size_t(g)].count);
    return cutCells(std::move(cells), parts);
}

int partOfCell(const std::vector<int>& cuts, int cell) {
    return int(std::upper_bound(cuts.begin(), cuts.end(), cell) - cuts.begin());
}

}  // namespace btocl
