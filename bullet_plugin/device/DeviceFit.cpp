#include "DeviceFit.h"

#include "btOpenCLSolverError.h"
#include "split_grid.h"

#include <algorithm>
#include <climits>

namespace btocl {

DeviceLimits deviceLimitsOf(const OclRuntime& rt) {
    DeviceLimits limits;
    limits.maxAlloc = rt.maxAllocSize();
    limits.globalMem = rt.device().getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
    limits.deviceName = rt.deviceName();
    return limits;
}

StepCounts countsOf(const StepProblem& p) {
    StepCounts c;
    c.bodies = p.bodies.size();
    c.constraints = p.constraints.size();
    c.points = p.points.size();
    c.frictionRows = size_t(p.numRowsOf(BTOCL_ROWS_FRICTION));
    c.rows = size_t(p.numRows());
    c.hostRows = p.rows.size();
    c.rowsOnDevice = p.rowsOnDevice;
    return c;
}

std::vector<StepBuffer> stepBuffers(const StepCounts& c) {
    const size_t n = c.constraints;
    std::vector<StepBuffer> b = {
        // DeviceSolver
        {"bodies", c.bodies, sizeof(btoclBody)},
        {"body deltas", c.bodies, sizeof(btoclBodyDelta)},
        {"constraints", n, sizeof(btoclConstraint)},
        {"constraints in solve order", n, sizeof(btoclConstraint)},
        {"row offsets", n, sizeof(int)},
        {"friction row offsets", n, sizeof(int)},
        {"rows", c.rows, sizeof(btoclSolveRow)},
        {"row map", c.rows, sizeof(int)},
        {"normal row of each row", c.rows, sizeof(int)},
        {"applied impulses", c.rows, sizeof(float)},
        {"push impulses", c.rows, sizeof(float)},
        {"impulses read back", c.rows, sizeof(float)},
        {"rows set up on the host", c.hostRows, sizeof(btoclRow)},
        // DeviceLayout and its sort (DevicePrimitives)
        {"overflow flags", c.bodies, sizeof(cl_uchar)},
        {"split keys", n, sizeof(cl_uint)},
        {"sorted constraints", n, sizeof(int)},
        {"solve order", n, sizeof(int)},
        {"batch ends", n, sizeof(int)},
        {"groups", std::min<size_t>(n, BTOCL_SPLIT_NUM_KEYS), sizeof(btoclGroup)},
        {"sort scratch keys", n, sizeof(cl_uint)},
        {"sort scratch values", n, sizeof(cl_uint)},
    };
    if (c.rowsOnDevice) {
        b.push_back({"contact points", c.points, sizeof(btoclContactPoint)});
        b.push_back({"friction directions", 2 * c.points, sizeof(btoclFloat4)});
    }
    return b;
}

void checkStepFitsDevice(const StepCounts& c, const DeviceLimits& limits) {
    const std::string prefix = "btOpenCLConstraintSolver: the step does not fit " + limits.deviceName + ": ";
    const std::vector<StepBuffer> buffers = stepBuffers(c);
    size_t total = 0;
    for (const StepBuffer& b : buffers) {
        if (b.count > size_t(INT_MAX))
            throw btOpenCLSolverError(prefix + "the " + b.name + " buffer needs " + std::to_string(b.count) +
                                      " elements, more than the kernels' int indices reach (2^31 - 1)");
        if (b.bytes() > limits.maxAlloc)
            throw btOpenCLSolverError(prefix + "the " + b.name + " buffer needs " + std::to_string(b.bytes()) +
                                      " bytes (" + std::to_string(b.count) + " of " + std::to_string(b.elementSize) +
                                      "), more than the largest allocation, CL_DEVICE_MAX_MEM_ALLOC_SIZE = " +
                                      std::to_string(limits.maxAlloc) + " bytes");
        total += b.bytes();
    }
    if (total > limits.globalMem) {
        const StepBuffer& largest = *std::max_element(
            buffers.begin(), buffers.end(), [](const StepBuffer& a, const StepBuffer& b) { return a.bytes() < b.bytes(); });
        throw btOpenCLSolverError(prefix + "its buffers need " + std::to_string(total) + " bytes together (the " +
                                  largest.name + " buffer " + std::to_string(largest.bytes()) +
                                  "), more than the global memory, CL_DEVICE_GLOBAL_MEM_SIZE = " +
                                  std::to_string(limits.globalMem) + " bytes");
    }
}

}  // namespace btocl
