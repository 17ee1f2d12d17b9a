// Whether a step fits the device, checked before its first enqueue: every device buffer the step
// needs (DeviceSolver, DeviceLayout, DevicePrimitives) computed from the step's counts and the
// records' sizes (kernels/btocl_shared.h), against the largest single allocation and the global
// memory of the device. Keep stepBuffers() in step with those classes when a layout changes.
#pragma once

#include "OclRuntime.h"
#include "StepProblem.h"

#include <cstddef>
#include <string>
#include <vector>

namespace btocl {

struct DeviceLimits {
    size_t maxAlloc = 0;   // CL_DEVICE_MAX_MEM_ALLOC_SIZE: the largest single buffer
    size_t globalMem = 0;  // CL_DEVICE_GLOBAL_MEM_SIZE: all buffers together
    std::string deviceName;
};
DeviceLimits deviceLimitsOf(const OclRuntime& rt);

// The counts a step's buffers grow with.
struct StepCounts {
    size_t bodies = 0;       // solver bodies, the fixed body included
    size_t constraints = 0;  // manifolds with points in reach
    size_t points = 0;       // contact points (= normal rows)
    size_t frictionRows = 0;
    size_t rows = 0;         // every row: normal, friction, rolling and joint rows
    size_t hostRows = 0;     // rows set up on the host (the joints', or all where the host sets rows up)
    bool rowsOnDevice = true;
};
StepCounts countsOf(const StepProblem& p);

// One device buffer: `count` elements of `elementSize` bytes.
struct StepBuffer {
    const char* name;
    size_t count;
    size_t elementSize;
    size_t bytes() const { return count * elementSize; }
};
// The buffers whose size follows the counts; the fixed ones (key bins, bounds, control) are
// under 1 MB together and left out.
std::vector<StepBuffer> stepBuffers(const StepCounts& c);

// Throws btOpenCLSolverError naming the buffer, its bytes and the limit when a buffer exceeds
// the largest allocation, or all of them the global memory, or a count the int indices of the
// kernels cannot hold. A device limit, not bad input: fallbackToBullet solves such a step.
void checkStepFitsDevice(const StepCounts& c, const DeviceLimits& limits);

}  // namespace btocl
