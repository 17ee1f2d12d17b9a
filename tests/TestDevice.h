// The solve path the tests exercise, as the solver reads it from BT_OPENCL_SOLVE_PATH ("serial"
// unless it says "wide"): CI runs the suite once per path, so device-level tests follow it too.
#pragma once

#include "DevicePrimitives.h"

#include <cstdlib>
#include <string>

namespace btocl::test {

inline bool testsRunWide() {
    const char* path = std::getenv("BT_OPENCL_SOLVE_PATH");
    return path && std::string(path) == "wide";
}
// The wide path on a CPU device takes Boost.Compute's sort and scan (which a GPU may get); the
// serial path our chunked kernels.
inline DevicePrimitives::Backend testBackend() {
    return testsRunWide() ? DevicePrimitives::Backend::BoostCompute : DevicePrimitives::Backend::Chunked;
}
inline int testLanesPerGroup() { return testsRunWide() ? 64 : 1; }

}  // namespace btocl::test
