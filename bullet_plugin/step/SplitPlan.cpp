#include "SplitPlan.h"

#include "btOpenCLSolverError.h"

#include <algorithm>
#include <cmath>

namespace btocl {
namespace {

// A contact point lies within its body's AABB grown by the contact margin; 10% more covers the
// AABB being a step old and float rounding far from the origin.
constexpr float kRelativeMargin = 1.1f;
// A dynamic body more than this many times the median dynamic extent goes to the overflow group.
constexpr float kOverflowFactor = 4.0f;

float contactSpan(float extent, const SplitParams& params) { return extent * kRelativeMargin + params.contactMargin; }

}  // namespace

void checkSplitParams(const SplitParams& params) {
    if (!(params.cellSize >= 0) || !std::isfinite(params.cellSize))
        throw btOpenCLSolverError("btOpenCLConstraintSolver: cellSize must be 0 (automatic) or a positive finite length");
    if (params.batchIterations < 1)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: batchIterations must be at least 1");
}

SplitBodiesPlan planSplitBodies(const std::vector<SplitBody>& bodies, const SplitParams& params) {
    checkSplitParams(params);
    SplitBodiesPlan plan;
    plan.overflowBody.assign(bodies.size(), 0);
    if (params.cellSize > 0) {
        plan.baseCellSize = params.cellSize;
        for (size_t i = 0; i < bodies.size(); ++i)
            plan.overflowBody[i] = bodies[i].dynamic && contactSpan(bodies[i].extent, params) > params.cellSize;
        return plan;
    }
    std::vector<float> extents;
    for (const SplitBody& b : bodies)
        if (b.dynamic) extents.push_back(b.extent);
    if (extents.empty()) return plan;
    auto mid = extents.begin() + std::ptrdiff_t(extents.size() / 2);
    std::nth_element(extents.begin(), mid, extents.end());
    const float limit = kOverflowFactor * *mid;
    float cell = 0;
    for (size_t i = 0; i < bodies.size(); ++i) {
        if (!bodies[i].dynamic) continue;
        if (limit > 0 && bodies[i].extent > limit)
            plan.overflowBody[i] = 1;
        else
            cell = std::max(cell, contactSpan(bodies[i].extent, params));
    }
    plan.baseCellSize = cell;
    return plan;
}

}  // namespace btocl
