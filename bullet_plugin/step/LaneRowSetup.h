// Contact rows set up eight points at a time in the CPU's vector lanes (AVX2), a point a lane:
// row_setup.h's contact rows (btoclContactFrameOf, btoclNormalRow, btoclFrictionFrameOf,
// btoclFrictionRow) with the same operations in the same order in each lane, so the same bits as
// the scalar setup. The lanes take the common points (pointInLanes); a caller sets the others up
// one at a time with row_setup.h. Called only where lanesAvailable() (LaneVectors.h).
#pragma once

#include "LaneLayout.h"
#include "StepProblem.h"
#include "btocl_shared.h"

namespace btocl {

class HostSolve;

// Whether the lanes set a point's rows up: a contact with the solver's own cfm and erp, no
// friction anchor, its friction directions chosen this step (not cached).
inline bool pointInLanes(const btoclContactPoint& pt, int solverMode) {
    const int own = BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM | BTOCL_CONTACT_FLAG_HAS_CONTACT_ERP |
                    BTOCL_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING | BTOCL_CONTACT_FLAG_FRICTION_ANCHOR;
    const bool cached = (solverMode & BTOCL_SOLVER_ENABLE_FRICTION_DIRECTION_CACHING) &&
                        (pt.flags & BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED);
    return (pt.flags & own) == 0 && !cached;
}

// A lane layout's slot (s, its lanes' ints `ints`): its rows into the blocks of `wide`, `applied`
// and `pushApplied` and its points' friction directions into lateralDirs, as lane_setup.h's
// btoclSetupLaneRows writes them for each lane, where every point of the slot is one the lanes
// take. Returns false, having written nothing, where one is not. stream: the blocks go past the
// caches (see drainStreamedStores, HostParallel.h).
bool setUpSlotRowsInLanes(const btoclContactPoint* points, const btoclBody* bodies, const btoclLaneSlot& s,
                          const int* ints, float* wide, float* applied, float* pushApplied, btoclFloat4* lateralDirs,
                          const btoclSetupParams& prm, bool stream);

// Points [first, first + count) of p (count at most 8, gather order): their normal and friction
// rows into `into` (HostSolve::setRow's records) and their friction directions into
// p.lateralDirs, as setupRowsOnHost sets a point up without rolling rows or anisotropic friction,
// where every one is a point the lanes take. Returns false, having written nothing, where one is not.
bool setUpPointRowsInLanes(StepProblem& p, size_t first, size_t count, HostSolve& into);

}  // namespace btocl
