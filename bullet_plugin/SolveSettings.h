// The parts of btContactSolverInfo (and of the solver's config) that the iterations read.
#pragma once

#include "btocl_shared.h"

#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>

namespace btocl {

struct SolveSettings {
    int numIterations = 10;      // m_numIterations (the velocity iterations: passScheduleOf, StepPlan.h)
    int flags = 0;               // BTOCL_FLAG_*
    float residualThreshold = 0;
    bool usePush = false;        // m_splitImpulse
    bool warmStart = false;      // apply the rows' starting impulses before the iterations

    // rotatePoints: each iteration starts a manifold's points at another one (btOpenCLSolverConfig).
    static SolveSettings from(const btContactSolverInfo& info, bool rotatePoints) {
        SolveSettings s;
        s.numIterations = info.m_numIterations;
        s.residualThreshold = info.m_leastSquaresResidualThreshold;
        s.usePush = info.m_splitImpulse != 0;
        s.warmStart = (info.m_solverMode & SOLVER_USE_WARMSTARTING) != 0;
        // SI's SIMD row update scales by the factors once (in the row); its scalar one twice.
        if (!(info.m_solverMode & SOLVER_SIMD)) s.flags |= BTOCL_FLAG_APPLY_FACTORS;
        if (s.residualThreshold > 0) s.flags |= BTOCL_FLAG_TRACK_RESIDUAL;
        if (rotatePoints) s.flags |= BTOCL_FLAG_ROTATE_POINTS;
        return s;
    }
};

}  // namespace btocl
