#include "HostSolver.h"

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

// One pass over every set, group and batch in layout order; returns the largest squared residual.
// The iteration and m_numIterations matter to the velocity passes (btoclSolveConstraint).
float solvePass(StepProblem& p, const SolveRows& rows, const BatchLayout& layout, std::vector<float>& applied,
                std::vector<float>& pushApplied, int pass, int flags, int iteration, int numIterations) {
    float maxResidual2 = 0;
    for (const btoclGroup& g : layout.groups)
        for (int k = 0; k < g.numBatches; ++k) {
            const int begin = k == 0 ? g.offset : layout.batchEnd[size_t(g.offset + k - 1)];
            const int end = layout.batchEnd[size_t(g.offset + k)];
            for (int i = begin; i < end; ++i) {
                const btoclConstraint& c = p.constraints[size_t(layout.solveOrder[size_t(i)])];
                maxResidual2 = std::max(maxResidual2,
                                        btoclSolveConstraint(&c, rows.rows.data(), rows.normalOfRow.data(),
                                                             applied.data(), pushApplied.data(), p.bodies.data(),
                                                             p.deltas.data(), pass, flags, iteration, numIterations));
            }
        }
    return maxResidual2;
}

// SI's iteration count: m_numIterations, or more when some joint overrides it with more.
int iterationsWithJoints(const StepProblem& p, int numIterations, int& numJointRows) {
    int iterations = numIterations;
    numJointRows = 0;
    for (const btoclConstraint& c : p.constraints) {
        if (c.numRows[BTOCL_ROWS_JOINT] == 0) continue;
        numJointRows += c.numRows[BTOCL_ROWS_JOINT];
        iterations = std::max(iterations, int(BTOCL_CONSTRAINT_ITERATIONS(c)));
    }
    return iterations;
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
    auto pass = [&](int which, int iteration) {
        return solvePass(p, rows, layout, applied, pushApplied, which, settings.flags, iteration,
                         settings.numIterations);
    };
    int iterations = 0, numJointRows = 0;
    const int maxIterations = iterationsWithJoints(p, settings.numIterations, numJointRows);
    if (p.numContactPoints() > 0 || numJointRows > 0) {
        if (settings.warmStart) pass(BTOCL_PASS_WARMSTART, 0);
        if (settings.usePush)
            for (int it = 0; it < settings.numIterations; ++it)
                if (pass(BTOCL_PASS_PUSH, it) <= settings.residualThreshold && track) break;
        for (int it = 0; it < maxIterations; ++it) {
            const float normal = pass(BTOCL_PASS_NORMAL, it);  // before the friction: SI's order of kinds
            const float residual = std::max(normal, pass(BTOCL_PASS_FRICTION, it));
            ++iterations;
            if (track && residual <= settings.residualThreshold) break;
        }
    }
    p.appliedImpulses.assign(applied.begin(), applied.end());
    return iterations;
}

}  // namespace btocl
