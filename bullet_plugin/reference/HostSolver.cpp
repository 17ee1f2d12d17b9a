#include "HostSolver.h"

#include "row_solve.h"

#include <algorithm>

namespace btocl {
namespace {

// One pass over every set, group and batch in layout order; returns the largest squared residual.
// The iteration and m_numIterations matter to the velocity pass only (btoclSolveConstraint).
float solvePass(StepProblem& p, const BatchLayout& layout, std::vector<float>& applied,
                std::vector<float>& pushApplied, int pass, int applyFactors, int iteration = 0, int numIterations = 1) {
    float maxResidual2 = 0;
    for (const btoclGroup& g : layout.groups) {
        int start = g.offset;
        for (int k = 0; k < g.numBatches; ++k) {
            const int end = layout.batchEnd[size_t(g.offset + k)];
            for (int i = start; i < end; ++i) {
                const btoclConstraint& c = p.constraints[size_t(layout.solveOrder[size_t(i)])];
                maxResidual2 = std::max(maxResidual2, btoclSolveConstraint(&c, p.rows.data(), applied.data(),
                                                                           pushApplied.data(), p.bodies.data(),
                                                                           p.deltas.data(), pass, applyFactors,
                                                                           iteration, numIterations));
            }
            start = end;
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
        iterations = std::max(iterations, BTOCL_ROW_ITERATIONS(p.rows[size_t(c.firstRow[BTOCL_ROWS_JOINT])]));
    }
    return iterations;
}

}  // namespace

int solveOnHost(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings) {
    std::vector<float> applied(p.rows.size()), pushApplied(p.rows.size());
    for (size_t r = 0; r < p.rows.size(); ++r) {
        applied[r] = BTOCL_ROW_APPLIED(p.rows[r]);
        pushApplied[r] = BTOCL_ROW_APPLIED_PUSH(p.rows[r]);
    }
    const int applyFactors = settings.flags & BTOCL_FLAG_APPLY_FACTORS;
    const bool track = (settings.flags & BTOCL_FLAG_TRACK_RESIDUAL) != 0;
    int iterations = 0, numJointRows = 0;
    const int maxIterations = iterationsWithJoints(p, settings.numIterations, numJointRows);
    if (p.numNormalRows > 0 || numJointRows > 0) {
        if (settings.warmStart) solvePass(p, layout, applied, pushApplied, BTOCL_PASS_WARMSTART, applyFactors);
        if (settings.splitImpulse)
            for (int it = 0; it < settings.numIterations; ++it)
                if (solvePass(p, layout, applied, pushApplied, BTOCL_PASS_PENETRATION, applyFactors) <=
                        settings.residualThreshold && track)
                    break;
        for (int it = 0; it < maxIterations; ++it) {
            const float residual = solvePass(p, layout, applied, pushApplied, BTOCL_PASS_VELOCITY, applyFactors, it,
                                             settings.numIterations);
            ++iterations;
            if (track && residual <= settings.residualThreshold) break;
        }
    }
    p.appliedImpulses = applied;
    return iterations;
}

}  // namespace btocl
