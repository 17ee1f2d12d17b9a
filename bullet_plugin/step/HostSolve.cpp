#include "HostSolve.h"

#include "StepPlan.h"
#include "row_solve.h"

#include <algorithm>
#include <type_traits>

namespace btocl {

namespace {

// One pass over every set, group and batch in layout order, or over the constraints in gather
// order as one group of one run (the serial path's whole step); with the randomized order, each
// group's batches and each batch's constraints in the orders that one lane walks on the device
// (solve.cl). Returns the largest squared residual. The iteration and m_numIterations matter to
// the velocity passes (btoclSolveConstraint). The pass is a constant, as in the kernels, so that
// the compiler folds its branches away. With `pairsAllowed`, pairs of constraints are solved side
// by side where the pass allows (btoclPassPairs), counted in `pairsSolved`.
template <int PASS>
float solvePassOf(const btoclSolveBuffers& b, int numConstraints, const BatchLayout* layout, int flags, int iteration,
                  int numIterations, unsigned passSeed, bool pairsAllowed, long& pairsSolved) {
    const int shuffled = btoclShuffledRows(PASS, flags), constraintsShuffled = btoclShuffledConstraints(PASS, flags);
    float maxResidual2 = 0;  // stays 0 where a pass pairs: it tracks no residual
    const bool pairs = pairsAllowed && btoclPassPairs(PASS, flags, iteration, numIterations);
    const int* const order = layout ? layout->solveOrder.data() : nullptr;
    auto at = [&](int i) { return b.constraints + (order ? order[i] : i); };
    auto solveOne = [&](const btoclConstraint* c) {
        btoclSolveConstraint(&b, c, PASS, flags, iteration, numIterations, 0u);
    };
    // Where the pass pairs: constraints [begin, end) of the solve order in order, taken two side by
    // side where they may be (btoclSolveContactPair).
    auto pairRun = [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            if (i + 1 < end && btoclPairable(at(i), at(i + 1))) {
                btoclSolveContactPair(&b, at(i), at(i + 1), PASS, flags);
                ++pairsSolved;
                ++i;
            } else {
                solveOne(at(i));
            }
        }
    };
    // Two groups of one set share no dynamic body: the k-th constraints of both side by side give
    // the bits of one group after the other (however their constraints pair within a group).
    auto pairGroups = [&](const btoclGroup& g1, const btoclGroup& g2) {
        const int n = std::min(g1.count, g2.count);
        for (int k = 0; k < n; ++k) {
            const btoclConstraint *c1 = at(g1.offset + k), *c2 = at(g2.offset + k);
            if (btoclPairable(c1, c2)) {
                btoclSolveContactPair(&b, c1, c2, PASS, flags);
                ++pairsSolved;
            } else {
                solveOne(c1);
                solveOne(c2);
            }
        }
        pairRun(g1.offset + n, g1.offset + g1.count);
        pairRun(g2.offset + n, g2.offset + g2.count);
    };
    if (pairs && layout) {
        // In a fixed order a group's batches one after another are its constraints in order.
        const std::vector<btoclGroup>& groups = layout->groups;
        for (int s = 0; s <= BTOCL_OVERFLOW_SET; ++s)
            for (int g = layout->setGroupStart[s]; g < layout->setGroupStart[s + 1]; g += 2) {
                if (g + 1 < layout->setGroupStart[s + 1])
                    pairGroups(groups[size_t(g)], groups[size_t(g) + 1]);
                else
                    pairRun(groups[size_t(g)].offset, groups[size_t(g)].offset + groups[size_t(g)].count);
            }
        return maxResidual2;
    }
    auto walk = [&](const btoclGroup& g, const int* batchEnd) {
        if (pairs) {
            pairRun(g.offset, g.offset + g.count);
            return;
        }
        const unsigned groupSeed = shuffled ? btoclSeedOf(passSeed, g.offset) : 0u;
        for (int kk = 0; kk < g.numBatches; ++kk) {
            const int k = btoclOrderAt(g.numBatches, constraintsShuffled, groupSeed, kk);
            const int begin = k == 0 ? g.offset : batchEnd[g.offset + k - 1];
            const int end = batchEnd[g.offset + k];
            const unsigned batchSeed = shuffled ? btoclSeedOf(groupSeed, k) : 0u;
            for (int j = 0; j < end - begin; ++j) {
                const int i = begin + btoclOrderAt(end - begin, constraintsShuffled, batchSeed, j);
                const float residual2 = btoclSolveConstraint(&b, at(i), PASS, flags, iteration, numIterations,
                                                             shuffled ? btoclSeedOf(batchSeed, i) : 0u);
                maxResidual2 = std::max(maxResidual2, residual2);
            }
        }
    };
    if (!layout) {
        const btoclGroup whole{0, numConstraints, 1, 0};
        if (numConstraints > 0) walk(whole, &numConstraints);
        return maxResidual2;
    }
    for (const btoclGroup& g : layout->groups) walk(g, layout->batchEnd.data());
    return maxResidual2;
}

}  // namespace

float HostSolve::solvePass(StepProblem& p, const BatchLayout* layout, int pass, int flags, int iteration,
                           int numIterations, unsigned passSeed) {
    const btoclSolveBuffers b{p.constraints.data(), m_rows.data(), m_normalOfRow.data(), m_applied.data(),
                              m_pushApplied.data(), p.bodies.data(), p.deltas.data()};
    const int n = int(p.constraints.size());
    auto run = [&](auto passConstant) {
        return solvePassOf<decltype(passConstant)::value>(b, n, layout, flags, iteration, numIterations, passSeed,
                                                          m_pairs, m_pairsSolved);
    };
    switch (pass) {
        case BTOCL_PASS_NORMAL: return run(std::integral_constant<int, BTOCL_PASS_NORMAL>());
        case BTOCL_PASS_FRICTION: return run(std::integral_constant<int, BTOCL_PASS_FRICTION>());
        case BTOCL_PASS_PUSH: return run(std::integral_constant<int, BTOCL_PASS_PUSH>());
        default: return run(std::integral_constant<int, BTOCL_PASS_WARMSTART>());
    }
}

void HostSolve::beginRows(size_t numRows, const btoclBody* bodies) {
    m_bodies = bodies;
    m_rows.resize(numRows);
    m_normalOfRow.resize(numRows);
    m_applied.resize(numRows);
    m_pushApplied.resize(numRows);
}

int HostSolve::solve(StepProblem& p, const btoclPassSchedule& passes, const SolveSettings& settings,
                     const BatchLayout* layout) {
    beginRows(p.rows.size(), p.bodies.data());
    for (const btoclConstraint& c : p.constraints)
        for (int kind = 0; kind < BTOCL_NUM_ROW_KINDS; ++kind)
            for (int r = c.firstRow[kind]; r < c.firstRow[kind] + c.numRows[kind]; ++r)
                setRow(r, p.rows[size_t(r)], kind);
    return solveRowsSet(p, passes, settings, layout);
}

int HostSolve::solveRowsSet(StepProblem& p, const btoclPassSchedule& passes, const SolveSettings& settings,
                            const BatchLayout* layout) {
    m_pairsSolved = 0;
    const bool track = (settings.flags & BTOCL_FLAG_TRACK_RESIDUAL) != 0;
    const int numPasses = p.constraints.empty() ? 0 : btoclPassCount(passes);
    int iterations = 0;
    float residual2 = 0;
    for (int i = 0; i < numPasses; ++i) {
        const btoclPassStep step = btoclPassAt(passes, i);
        residual2 = std::max(residual2, solvePass(p, layout, step.pass, settings.flags, step.iteration,
                                                  passes.numIterations, btoclPassSeed(passes, i)));
        if (!step.endsIteration) continue;
        if (step.pass != BTOCL_PASS_PUSH) ++iterations;
        if (track && residual2 <= settings.residualThreshold) {
            if (step.pass != BTOCL_PASS_PUSH) break;
            i = btoclFirstVelocityPass(passes) - 1;  // the push iterations have converged
        }
        residual2 = 0;
    }
    p.appliedImpulses.assign(m_applied.begin(), m_applied.end());
    return iterations;
}

int solveOnHost(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings) {
    HostSolve solve;
    return solve.solve(p, passScheduleOf(settings, p), settings, &layout);
}

}  // namespace btocl
