// The parts of btContactSolverInfo (and of the solver's config) that the iterations read, as plain
// values (made by solveSettingsOf, BulletConversions.h).
#pragma once

#include "btocl_shared.h"

namespace btocl {

struct SolveSettings {
    int numIterations = 10;      // m_numIterations (the velocity iterations: passScheduleOf, StepPlan.h)
    int flags = 0;               // BTOCL_FLAG_*
    float residualThreshold = 0;
    bool usePush = false;        // m_splitImpulse
    bool warmStart = false;      // apply the rows' starting impulses before the iterations
    unsigned orderSeed = 0;      // with BTOCL_FLAG_RANDOM_ORDER: the step's seed of its shuffled orders
};

}  // namespace btocl
