// The tests' view into the device's part of a step (DeviceSolver): a host-built layout uploaded
// for it to solve, and its rows read back in the full record. Not in the shipped library.
#pragma once

#include "BatchLayout.h"
#include "DeviceSolver.h"

#include <vector>

namespace btocl {

class DeviceSolveProbe {
public:
    explicit DeviceSolveProbe(const OclRuntime& rt) : m_rt(rt) {}

    // Copies a host-built layout to this probe's buffers, for a DeviceSolver to solve in.
    DeviceLayoutView uploadLayout(const BatchLayout& layout);

    // The rows as they are on the device after `solver`'s step, in gather order, in the full
    // record (tests compare them with SI's): B's linear Jacobian the negative of A's, zero on a
    // side without a rigid body.
    static std::vector<btoclRow> downloadRows(const DeviceSolver& solver, const StepProblem& p);

    // The constraints in solve order and the rows' places, as `solver`'s arrangement left them.
    static HostArrangement downloadArrangement(const DeviceSolver& solver, const StepProblem& p);

private:
    const OclRuntime& m_rt;
    DeviceBuffer<btoclGroup> m_groups;
    DeviceBuffer<int> m_solveOrder, m_batchEnd, m_setGroupStart;
};

}  // namespace btocl
