// What one step solves: solver bodies, constraints and their contact points (or rows set up on
// the host), in the flat records that the kernels read (kernels/btocl_shared.h). Plain data: no
// Bullet type, so that the device side, which takes it, cannot see Bullet; where each record came
// from in Bullet is the gather's BulletStep (BulletStep.h). Filled by StepGatherer
// (BulletGather.h), solved by DeviceSolver, written back by writeBackStep.
#pragma once

#include "HostArray.h"
#include "SplitPlan.h"
#include "btocl_shared.h"

#include <algorithm>
#include <vector>

namespace btocl {

// Rows are all written after the array is sized (the host row setup, the joints' rows).
using RowArray = std::vector<btoclRow, DefaultInitAllocator<btoclRow>>;

struct StepProblem {
    // Per solver body. Index 0 is the fixed body that every static object maps to (as SI's).
    HostArray<btoclBody> bodies;  // HostArray: read in place by a device on the host's memory
    HostArray<btoclBodyDelta> deltas;  // zero here; the solve fills them (in place, as `bodies`)
    std::vector<SplitBody> splitBodies;
    // Bodies whose angular velocity change the passes keep as SI's (BTOCL_BODY_SCALED 0), counted
    // by the gather as it fills their records: a step with one has rows that the lanes' 13 floats
    // do not hold.
    int unscaledBodies = 0;

    // One constraint per manifold that has points in reach, then one per joint with rows; the
    // rows of each kind contiguous, in their regions of gather order (btoclRowRegions).
    std::vector<btoclConstraint> constraints;
    btoclRowRegions regions = btoclRowRegionsOf(0, 0, 0, 0);
    // The most velocity iterations a joint with rows asks for (SI's override, else
    // m_numIterations; 0 without joints).
    int jointIterations = 0;

    // One record per contact point; normal row i is point i. kernels/setup.cl sets the rows up
    // from them on the device ...
    HostArray<btoclContactPoint> points;
    btoclSetupParams setupParams{};
    // Some point may give its normal row a push share (btoclPointMayNeedPush): the push
    // iterations then run (passScheduleOf, StepPlan.h).
    bool mayNeedPush = false;
    // ... unless rowsOnDevice is false: then the host set them up (HostRowSetup.h). `rows` holds
    // the rows set up on the host, in gather order from row hostRowBase() on: every row then, or
    // the joint rows alone when the device sets the contact rows up.
    bool rowsOnDevice = true;
    RowArray rows;
    int hostRowBase() const { return rowsOnDevice ? rowStart(BTOCL_ROWS_JOINT) : 0; }

    // After the solve: applied impulses of every row (gather order), and the two friction
    // directions of each point (the host's or the device's choice). HostArray: written in place
    // by a device on the host's memory.
    HostArray<float> appliedImpulses;
    HostArray<btoclFloat4> lateralDirs;

    // The host arrays' storage from `source` from now on (null: the heap), their elements kept.
    void takeHostMemoryFrom(HostMemorySource* source) {
        moveToSource(bodies, source);
        moveToSource(deltas, source);
        moveToSource(points, source);
        moveToSource(appliedImpulses, source);
        moveToSource(lateralDirs, source);
    }

    int numBodies() const { return int(bodies.size()) - 1; }  // the fixed body left out
    int rowStart(int kind) const { return regions.start[kind]; }
    int numRowsOf(int kind) const { return btoclRegionRows(&regions, kind); }
    int numRows() const { return regions.start[BTOCL_NUM_ROW_KINDS]; }
    int numContactPoints() const { return numRowsOf(BTOCL_ROWS_NORMAL); }  // normal row i is point i
    int numJointRows() const { return numRowsOf(BTOCL_ROWS_JOINT); }
    // Each point's friction rows: two with SOLVER_USE_2_FRICTION_DIRECTIONS, else one.
    int frictionRowsPerPoint() const {
        return (setupParams.solverMode & BTOCL_SOLVER_USE_2_FRICTION_DIRECTIONS) ? 2 : 1;
    }
    // A contact point's first friction row: each point's friction rows in point order, after the
    // normal rows, as the gather lays them out and the setups find them (setupParams.numPoints).
    int firstFrictionRowOf(int point) const { return btoclFirstFrictionRow(&setupParams, point); }
    // Velocity iterations: m_numIterations, or more when a joint's override asks (SI's maxIterations).
    int maxIterations(int numIterations) const { return std::max(numIterations, jointIterations); }
};

}  // namespace btocl
