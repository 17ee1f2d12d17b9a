#include "HostSolver.h"

#include "StepPlan.h"
#include "row_setup.h"
#include "row_solve.h"

#include <algorithm>

namespace btocl {
namespace {

// The rows as the iterations read them (btoclSolveRow), in gather order, with each friction and
// rolling row's normal row.
struct SolveRows {
    std::vector<btoclSolveRow> rows;
    std::vector<int> normalOfRow;
};

SolveRows solveRowsOf(const StepProblem& p) {
    SolveRows s;
    s.rows.resize(p.rows.size());
    s.normalOfRow.assign(p.rows.size(), -1);
    for (const btoclConstraint& c : p.constraints)
        for (int kind = 0; kind < BTOCL_NUM_ROW_KINDS; ++kind)
            for (int r = c.firstRow[kind]; r < c.firstRow[kind] + c.numRows[kind]; ++r) {
                s.rows[size_t(r)] = btoclSolveRowOf(p.rows[size_t(r)], kind);
                s.normalOfRow[size_t(r)] = p.rows[size_t(r)].frictionIndex;
            }
    return s;
}

// One pass over every set, group and batch in layout order (with the randomized order, each
// group's batches and each batch's constraints in the orders that one lane walks on the device:
// solve.cl); returns the largest squared residual. The iteration and m_numIterations matter to
// the velocity passes (btoclSolveConstraint).
float solvePass(StepProblem& p, const SolveRows& rows, const BatchLayout& layout, std::vector<float>& applied,
                std::vector<float>& pushApplied, int pass, int flags, int iteration, int numIterations,
                unsigned passSeed) {
    const btoclSolveBuffers b{p.constraints.data(), rows.rows.data(), rows.normalOfRow.data(), applied.data(),
                              pushApplied.data(), p.bodies.data(), p.deltas.data()};
    const int shuffled = btoclShuffledRows(pass, flags), constraintsShuffled = btoclShuffledConstraints(pass, flags);
    float maxResidual2 = 0;
    for (const btoclGroup& g : layout.groups) {
        const unsigned groupSeed = shuffled ? btoclSeedOf(passSeed, g.offset) : 0u;
        for (int kk = 0; kk < g.numBatches; ++kk) {
            const int k = btoclOrderAt(g.numBatches, constraintsShuffled, groupSeed, kk);
            const int begin = k == 0 ? g.offset : layout.batchEnd[size_t(g.offset + k - 1)];
            const int end = layout.batchEnd[size_t(g.offset + k)];
            const unsigned batchSeed = shuffled ? btoclSeedOf(groupSeed, k) : 0u;
            for (int j = 0; j < end - begin; ++j) {
                const int i = begin + btoclOrderAt(end - begin, constraintsShuffled, batchSeed, j);
                const btoclConstraint* c = b.constraints + layout.solveOrder[size_t(i)];
                maxResidual2 = std::max(maxResidual2, btoclSolveConstraint(&b, c, pass, flags, iteration, numIterations,
                                                                           shuffled ? btoclSeedOf(batchSeed, i) : 0u));
            }
        }
    }
    return maxResidual2;
}

}  // namespace

int solveOnHost(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings) {
    const SolveRows rows = solveRowsOf(p);
    std::vector<float> applied(p.rows.size()), pushApplied(p.rows.size());
    for (size_t r = 0; r < p.rows.size(); ++r) {
        applied[r] = BTOCL_ROW_APPLIED(p.rows[r]);
        pushApplied[r] = BTOCL_ROW_APPLIED_PUSH(p.rows[r]);
    }
    const bool track = (settings.flags & BTOCL_FLAG_TRACK_RESIDUAL) != 0;
    const btoclPassSchedule schedule = passScheduleOf(settings, p);
    const int numPasses = p.constraints.empty() ? 0 : btoclPassCount(schedule);
    int iterations = 0;
    float residual2 = 0;
    for (int i = 0; i < numPasses; ++i) {
        const btoclPassStep step = btoclPassAt(schedule, i);
        residual2 = std::max(residual2, solvePass(p, rows, layout, applied, pushApplied, step.pass, settings.flags,
                                                  step.iteration, schedule.numIterations, btoclPassSeed(schedule, i)));
        if (!step.endsIteration) continue;
        if (step.pass != BTOCL_PASS_PUSH) ++iterations;
        if (track && residual2 <= settings.residualThreshold) {
            if (step.pass != BTOCL_PASS_PUSH) break;
            i = btoclFirstVelocityPass(schedule) - 1;  // the push iterations have converged
        }
        residual2 = 0;
    }
    p.appliedImpulses.assign(applied.begin(), applied.end());
    return iterations;
}

}  // namespace btocl
