// What the global split needs from the bodies, planned on the host before the device splits:
// the cell edge the dynamic bodies ask for, and which of them are too big for a cell.
#pragma once

#include <vector>

namespace btocl {

struct SplitParams {
    float cellSize = 0;       // 0 = from the dynamic bodies' extents
    int batchIterations = 4;  // locking rounds per streamed chunk
    int workGroupSize = 64;
    // World distance by which a contact point may lie outside its body's AABB (Bullet's contact
    // breaking threshold is 0.02; points of a manifold may also sit on the other body's surface).
    float contactMargin = 0.05f;
};

// Throws btOpenCLSolverError for a cell edge that is negative or not finite, or fewer than one
// locking round: the one check of these settings, made by the solver at construction and by each
// layout builder (DeviceLayout, the host references) before it uses them.
void checkSplitParams(const SplitParams& params);

// Per body, what the split needs: the largest edge of its AABB (0 for static/kinematic bodies).
struct SplitBody {
    float extent = 0;
    bool dynamic = false;
};

// Rule: with params.cellSize > 0 that is the cell; a dynamic body is too big when its contact span,
// extent * 1.1 + contactMargin, exceeds it. Otherwise a dynamic body is too big when its extent
// exceeds 4x the median dynamic extent, and the cell is the largest contact span of the others.
// Constraints of a too-big body go to the overflow group.
struct SplitBodiesPlan {
    float baseCellSize = 0;                  // before the grid's cap on cells per axis
    std::vector<unsigned char> overflowBody; // per body: 1 = its constraints go to the overflow group
};
SplitBodiesPlan planSplitBodies(const std::vector<SplitBody>& bodies, const SplitParams& params);

}  // namespace btocl
