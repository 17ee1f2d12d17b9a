// The iterations on the device: uploads a step's bodies and rows, launches one kernel per set
// and pass for every iteration with no host round trip between them, and reads back the
// velocity changes and applied impulses. Buffers are kept and grown from step to step.
#pragma once

#include "ConstraintBatches.h"
#include "DeviceBuffer.h"
#include "SolveSettings.h"
#include "StepProblem.h"

#include <array>

namespace btocl {

// Where the solve finds the split/batch layout: the device batcher's buffers or uploaded ones.
struct DeviceLayoutView {
    const cl::Buffer* groups = nullptr;
    const cl::Buffer* solveOrder = nullptr;
    const cl::Buffer* batchEnd = nullptr;
    std::array<int, BTOCL_NUM_SETS + 2> setGroupStart{};
};

class DeviceSolver {
public:
    // workGroupSize: lanes per group on a GPU; a CPU device uses one lane per group.
    DeviceSolver(const OclRuntime& runtime, int workGroupSize);

    // Copies bodies, deltas, constraints and rows (or contact points) to the device.
    void upload(const StepProblem& p);
    // With rows set up on the device: sets them up from the contact points (kernels/setup.cl).
    void setupRows(const StepProblem& p);
    // Copies a host-built layout to this solver's own buffers.
    DeviceLayoutView uploadLayout(const BatchLayout& layout);
    // Enqueues every split-impulse and velocity iteration.
    void iterate(const StepProblem& p, const DeviceLayoutView& layout, const SolveSettings& settings);
    // Reads back p.deltas, p.appliedImpulses (normal and friction rows) and, with rows set up on
    // the device, p.lateralDirs. Returns the number of velocity iterations the device ran.
    int download(StepProblem& p, const SolveSettings& settings);
    // Reads the rows as they are on the device into p.rows (tests compare them with the host's).
    void downloadRows(StepProblem& p) const;

    const DeviceBuffer<btoclConstraint>& constraints() const { return m_constraints; }

private:
    void launchPass(const DeviceLayoutView& layout, int pass, int flags);

    const OclRuntime& m_rt;
    int m_workGroupSize;
    cl::Program m_program, m_setupProgram;
    std::array<cl::Kernel, 6> m_passKernels;
    cl::Kernel m_endIteration, m_gatherImpulses, m_setupRows;
    DeviceBuffer<btoclBody> m_bodies;
    DeviceBuffer<btoclBodyDelta> m_deltas;
    DeviceBuffer<btoclConstraint> m_constraints;
    DeviceBuffer<btoclRow> m_rows;
    DeviceBuffer<btoclContactPoint> m_points;
    DeviceBuffer<btoclFloat4> m_lateralDirs;
    DeviceBuffer<btoclGroup> m_groups;
    DeviceBuffer<int> m_solveOrder, m_batchEnd, m_control;
    DeviceBuffer<float> m_impulses;
};

}  // namespace btocl
