// A step's passes on the calling thread, with the row code the kernels run (kernels/row_solve.h):
// the host launch mode, for steps too small to repay a device launch (StepMode::Host), and the
// serial host reference that the tests hold the device's solve to. The same passes as the device
// walks (passScheduleOf), over the constraints in a layout's order or in gather order.
#pragma once

#include "BatchLayout.h"
#include "SolveSettings.h"
#include "StepProblem.h"
#include "row_setup.h"

#include <vector>

namespace btocl {

class HostSolve {
public:
    // Solves the rows set up on the host (p.rows, every row, gather order) in `layout`'s order, or
    // constraint after constraint in gather order without one: the warm start, the push and the
    // velocity iterations of `passes`. Leaves p.deltas and p.appliedImpulses (every row, gather
    // order) as DeviceSolver::download does. Returns the velocity iterations run. The scratch
    // arrays are kept from call to call.
    int solve(StepProblem& p, const btoclPassSchedule& passes, const SolveSettings& settings,
              const BatchLayout* layout = nullptr);

    // A host step's rows put here as they are set up (setupRowsOnHost with a HostSolve), rather
    // than set up into p.rows and converted: room for `numRows` rows of the step's `bodies`, then
    // setRow at each gather index, then solveRowsSet, which solves them as solve() would.
    void beginRows(size_t numRows, const btoclBody* bodies);
    void setRow(int index, const btoclRow& row, int kind) {
        const size_t i = size_t(index);
        m_rows[i] = btoclSolveRowOf(row, kind, m_bodies + row.bodyA, m_bodies + row.bodyB);
        m_normalOfRow[i] = row.frictionIndex;
        m_applied[i] = BTOCL_ROW_APPLIED(row);
        m_pushApplied[i] = BTOCL_ROW_APPLIED_PUSH(row);
    }
    // setRow's records, for a setup that writes them itself (LaneRowSetup.h): each row's record,
    // its normal row (-1 for a normal row) and its starting impulses, by gather index.
    struct RowRecords {
        btoclSolveRow* rows;
        int* normalOfRow;
        float* applied;
        float* pushApplied;
    };
    RowRecords rowRecords() { return {m_rows.data(), m_normalOfRow.data(), m_applied.data(), m_pushApplied.data()}; }
    int solveRowsSet(StepProblem& p, const btoclPassSchedule& passes, const SolveSettings& settings,
                     const BatchLayout* layout = nullptr);

    // Two adjacent constraints that share no dynamic body are solved side by side where a pass
    // allows (btoclSolveContactPair), with the bits of one after the other; off, never (the tests
    // compare the two). pairsSolved: how many pairs the last solve took so.
    void pairConstraints(bool on) { m_pairs = on; }
    long pairsSolved() const { return m_pairsSolved; }

private:
    float solvePass(StepProblem& p, const BatchLayout* layout, int pass, int flags, int iteration, int numIterations,
                    unsigned passSeed);

    // The rows as the passes read them (btoclSolveRow), with each friction and rolling row's normal
    // row, and the impulses they update, all in gather order.
    std::vector<btoclSolveRow> m_rows;
    const btoclBody* m_bodies = nullptr;  // the step's, which setRow reads (beginRows)
    std::vector<int> m_normalOfRow;
    std::vector<float> m_applied, m_pushApplied;
    bool m_pairs = true;
    long m_pairsSolved = 0;
};

// The serial host reference of the device's solve: p's passes (passScheduleOf) in `layout`'s order.
int solveOnHost(StepProblem& p, const BatchLayout& layout, const SolveSettings& settings);

}  // namespace btocl
