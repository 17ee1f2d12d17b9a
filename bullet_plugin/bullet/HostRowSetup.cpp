#include "HostRowSetup.h"

#include "BulletConversions.h"
#include "HostParallel.h"
#include "HostSolve.h"
#include "LaneRowSetup.h"
#include "LaneVectors.h"
#include "btOpenCLSolverError.h"
#include "row_setup.h"

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <algorithm>

namespace btocl {
namespace {

// SI's applyAnisotropicFriction: the direction scaled per axis in the object's frame.
btoclFloat4 anisotropic(const btCollisionObject* object, btoclFloat4 direction, int mode) {
    if (!object->hasAnisotropicFriction(mode)) return direction;
    const btMatrix3x3& basis = object->getWorldTransform().getBasis();
    btVector3 local = toVector3(direction) * basis;  // into the object's frame
    local *= object->getAnisotropicFriction();
    return toFloat4(basis * local);
}

btoclFloat4 anisotropicForBoth(const btPersistentManifold* m, btoclFloat4 direction, int mode) {
    return anisotropic(m->getBody1(), anisotropic(m->getBody0(), direction, mode), mode);
}

}  // namespace

void setupRowsOnHost(StepProblem& p, const BulletStep& bullet, HostSolve* into, bool inParallel) {
    const btoclSetupParams& prm = p.setupParams;
    const bool two = p.frictionRowsPerPoint() == 2;
    const int rollingBase = p.rowStart(BTOCL_ROWS_ROLLING);
    // The joints' rows: into a host solve, those the gather set up (then `rows` holds them
    // alone); without one, the gather calls this before it adds them.
    const size_t numJointRows = into && p.rowsOnDevice ? p.rows.size() : 0;
    const int jointStart = p.rowStart(BTOCL_ROWS_JOINT);
    if (!into && !p.rows.empty())
        throw btOpenCLSolverError("btOpenCLConstraintSolver: contact rows set up on the host after other rows");
    if (into)
        into->beginRows(size_t(p.numRows()), p.bodies.data());  // as many or more: a rolling row may be left out
    else
        p.rows.resize(size_t(rollingBase));
    auto put = [&](int index, const btoclRow& row, int kind) {
        if (into)
            into->setRow(index, row, kind);
        else
            p.rows[size_t(index)] = row;
    };
    p.lateralDirs.resize(2 * p.points.size());
    std::vector<btoclRow> rolling;
    // A point's rows (m: its manifold, read for anisotropic friction alone).
    auto setUpPoint = [&](int i, const btPersistentManifold* m, bool anisotropicPair) {
        btoclContactPoint& pt = p.points[size_t(i)];
        const btoclBody& A = p.bodies[size_t(pt.bodyA)];
        const btoclBody& B = p.bodies[size_t(pt.bodyB)];
        const btoclContactFrame f = btoclContactFrameOf(&pt, &A, &B);
        put(i, btoclNormalRow(&pt, &A, &B, &f, &prm), BTOCL_ROWS_NORMAL);

        if (pt.firstRollingRow >= 0) {
            pt.firstRollingRow = rollingBase + int(rolling.size());
            rolling.push_back(btoclTorsionalRow(pt.normalOnB, BTOCL_POINT_SPINNING_FRICTION(pt), &pt, &A, &B, &f, i));
            btoclFloat4 axis0, axis1;
            btoclPlaneSpace(pt.normalOnB, &axis0, &axis1);
            for (btoclFloat4 axis : {axis0, axis1}) {
                axis = btoclNormalize3(axis);
                if (anisotropicPair) axis = anisotropicForBoth(m, axis, btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION);
                if (btoclLength3(axis) > 0.001f)
                    rolling.push_back(btoclTorsionalRow(axis, BTOCL_POINT_ROLLING_FRICTION(pt), &pt, &A, &B, &f, i));
            }
        }

        btoclFrictionFrame ff = btoclFrictionFrameOf(&pt, &f, prm.solverMode);
        if (ff.chosen) {
            const int mode = btCollisionObject::CF_ANISOTROPIC_FRICTION;
            if (anisotropicPair) ff.dir1 = anisotropicForBoth(m, ff.dir1, mode);
            // SI takes the second direction across the first one as anisotropy left it.
            if (two && ff.fromVelocity) ff.dir2 = btoclNormalize3(btoclCross3(ff.dir1, pt.normalOnB));
            if (two && anisotropicPair) ff.dir2 = anisotropicForBoth(m, ff.dir2, mode);
        }
        p.lateralDirs[2 * size_t(i)] = ff.dir1;
        p.lateralDirs[2 * size_t(i) + 1] = ff.dir2;
        const int friction = btoclFirstFrictionRow(&prm, i);
        put(friction, btoclFrictionRow(ff.dir1, &pt, &A, &B, &f, &prm, ff.motion1, ff.cfmSlip, i), BTOCL_ROWS_FRICTION);
        if (two)
            put(friction + 1, btoclFrictionRow(ff.dir2, &pt, &A, &B, &f, &prm, ff.motion2, ff.cfmSlip, i),
                BTOCL_ROWS_FRICTION);
    };
    auto setUpConstraint = [&](size_t ci) {
        btoclConstraint& c = p.constraints[ci];
        const btPersistentManifold* m = bullet.manifoldOfConstraint[ci];
        if (!m) return;  // a joint's
        // Most manifolds have none: their points skip the objects' reads, and a step whose
        // gather found none reads no manifold's objects at all.
        const bool anisotropicPair = bullet.mayHaveAnisotropic &&
                                     (hasAnisotropicFriction(m->getBody0()) || hasAnisotropicFriction(m->getBody1()));
        c.firstRow[BTOCL_ROWS_ROLLING] = rollingBase + int(rolling.size());
        const int firstPoint = c.firstRow[BTOCL_ROWS_NORMAL];
        for (int i = firstPoint; i < firstPoint + c.numRows[BTOCL_ROWS_NORMAL]; ++i) setUpPoint(i, m, anisotropicPair);
        c.numRows[BTOCL_ROWS_ROLLING] = rollingBase + int(rolling.size()) - c.firstRow[BTOCL_ROWS_ROLLING];
    };
    const bool noRolling = p.numRowsOf(BTOCL_ROWS_ROLLING) == 0;
    if (into && noRolling && !bullet.mayHaveAnisotropic && lanesAvailable()) {
        // Eight points at a time in the vector unit's lanes, where all eight are points the lanes
        // take; the others one by one.
        for (size_t ci = 0; ci < p.constraints.size(); ++ci) {
            if (!bullet.manifoldOfConstraint[ci]) continue;
            p.constraints[ci].firstRow[BTOCL_ROWS_ROLLING] = rollingBase;
            p.constraints[ci].numRows[BTOCL_ROWS_ROLLING] = 0;
        }
        const size_t numPoints = p.points.size(), numRuns = (numPoints + 7) / 8;
        auto setUpRun = [&](size_t run) {
            const size_t first = 8 * run, count = std::min<size_t>(8, numPoints - first);
            if (setUpPointRowsInLanes(p, first, count, *into)) return;
            for (size_t i = first; i < first + count; ++i) setUpPoint(int(i), nullptr, false);
        };
        // Eight points weigh about as much as three manifolds.
        if (inParallel)
            parallelFor(numRuns, setUpRun, 3 * kContactConstraintWeight);
        else
            for (size_t run = 0; run < numRuns; ++run) setUpRun(run);
    } else if (inParallel && noRolling) {  // each constraint writes its own rows alone, but rolling
        parallelFor(p.constraints.size(), setUpConstraint, kContactConstraintWeight);  // rows are numbered as they come
    } else {
        for (size_t ci = 0; ci < p.constraints.size(); ++ci) setUpConstraint(ci);
    }
    p.regions = btoclRowRegionsOf(p.numRowsOf(BTOCL_ROWS_NORMAL), p.numRowsOf(BTOCL_ROWS_FRICTION),
                                  int(rolling.size()), p.numJointRows());
    // Rolling rows left out move the joints' rows down.
    const int jointShift = p.rowStart(BTOCL_ROWS_JOINT) - jointStart;
    for (btoclConstraint& c : p.constraints)
        if (c.numRows[BTOCL_ROWS_JOINT] > 0) c.firstRow[BTOCL_ROWS_JOINT] += jointShift;
    if (into) {
        // p.rows keeps the joints' rows alone, as the device's steps leave it (p.rowsOnDevice).
        into->beginRows(size_t(p.numRows()), p.bodies.data());
        for (size_t k = 0; k < rolling.size(); ++k) into->setRow(rollingBase + int(k), rolling[k], BTOCL_ROWS_ROLLING);
        for (size_t k = 0; k < numJointRows; ++k)
            into->setRow(p.rowStart(BTOCL_ROWS_JOINT) + int(k), p.rows[k], BTOCL_ROWS_JOINT);
        return;
    }
    p.rows.insert(p.rows.begin() + rollingBase, rolling.begin(), rolling.end());
    p.rowsOnDevice = false;
}

}  // namespace btocl
