// The solve path the tests exercise, as the solver reads it from BT_OPENCL_SOLVE_PATH ("serial"
// unless it says "wide", in any case): CI runs the suite once per path, so device-level tests follow it too.
#pragma once

#include "DevicePrimitives.h"
#include "OclRuntime.h"
#include "StepPlan.h"

#include <cstdlib>
#include <string>

namespace btocl::test {

inline bool testsRunWide() {
    const char* path = std::getenv("BT_OPENCL_SOLVE_PATH");
    return path && lowerCase(path) == "wide";
}
// The wide path on a CPU device takes Boost.Compute's sort and scan (which a GPU may get); the
// serial path our chunked kernels.
inline DevicePrimitives::Backend testBackend() {
    return testsRunWide() ? DevicePrimitives::Backend::BoostCompute : DevicePrimitives::Backend::Chunked;
}
// Whether the tests' device (the default one) is a CPU device.
inline bool testDeviceIsCpu() {
    static const bool cpu = OclRuntime("").isCpu();
    return cpu;
}
// The claimed launch is planned on a CPU device only (its work-groups read each other's writes
// through coherent caches: StepPolicy.h); elsewhere the tests skip it as the solver does.
inline bool claimedRunsHere() { return !testsRunWide() && testDeviceIsCpu(); }
inline GroupLanes testLanes() { return testsRunWide() ? GroupLanes::wide(64) : GroupLanes::serial(); }

// A plan of the given mode on the path under test, with the step's passes (the claimed and host
// modes are the serial path's: one lane a group).
inline StepPlan testPlan(StepMode mode, const btoclPassSchedule& passes) {
    switch (mode) {
        case StepMode::WholeStep: return StepPlan::wholeStep(testLanes(), passes);
        case StepMode::PerSet: return StepPlan::perSet(testLanes(), passes);
        case StepMode::Claimed: return StepPlan::claimed(passes);
        case StepMode::HostSplit: return StepPlan::onHostSplit(passes);
        case StepMode::Host: break;
    }
    return StepPlan::onHost(passes);
}

}  // namespace btocl::test
