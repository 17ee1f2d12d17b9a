// The check that a step fits the device, made before its first enqueue (DeviceFit.h): each
// buffer against the largest allocation, all of them against the global memory, counts against
// the kernels' int indices; the message names the buffer, its bytes and the limit.
#include "DeviceFit.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <climits>
#include <string>

using namespace btocl;

namespace {

// About a 1,000-box pile with two friction directions: 4 points a manifold.
StepCounts pileCounts() {
    StepCounts c;
    c.bodies = 1001;
    c.constraints = 3000;
    c.points = 12000;
    c.frictionRows = 24000;
    c.rows = 36000;
    return c;
}

DeviceLimits roomy() {
    DeviceLimits l;
    l.maxAlloc = size_t(1) << 40;
    l.globalMem = size_t(1) << 42;
    l.deviceName = "a test device";
    return l;
}

// Bytes of one element of the named buffer.
size_t elementSize(const char* name, const StepCounts& c = pileCounts()) {
    for (const StepBuffer& b : stepBuffers(c))
        if (std::string(b.name) == name) return b.elementSize;
    FAIL("no buffer named " << name);
    return 0;
}

size_t totalBytes(const StepCounts& c) {
    size_t total = 0;
    for (const StepBuffer& b : stepBuffers(c)) total += b.bytes();
    return total;
}

}  // namespace

TEST_CASE("a step within the device's limits passes the fit check", "[device-fit]") {
    REQUIRE_NOTHROW(checkStepFitsDevice(pileCounts(), roomy()));
    // The rows are the largest buffer of a contact step.
    DeviceLimits l = roomy();
    l.maxAlloc = pileCounts().rows * elementSize("rows");
    REQUIRE_NOTHROW(checkStepFitsDevice(pileCounts(), l));
}

TEST_CASE("a buffer past the largest allocation is named with its bytes and the limit", "[device-fit][errors]") {
    DeviceLimits l = roomy();
    const size_t rowBytes = pileCounts().rows * elementSize("rows");
    l.maxAlloc = rowBytes - 1;
    CHECK_THROWS_WITH(checkStepFitsDevice(pileCounts(), l),
                      Catch::Contains("a test device") &&
                          Catch::Contains("the rows buffer needs " + std::to_string(rowBytes) + " bytes") &&
                          Catch::Contains("CL_DEVICE_MAX_MEM_ALLOC_SIZE = " + std::to_string(rowBytes - 1)));
    // Rows set up on the host travel in a buffer of their own, in their full record.
    StepCounts host = pileCounts();
    host.rowsOnDevice = false;
    host.hostRows = host.rows;
    l.maxAlloc = host.rows * elementSize("rows set up on the host", host);
    REQUIRE_NOTHROW(checkStepFitsDevice(host, l));
    host.hostRows += 1;
    CHECK_THROWS_WITH(checkStepFitsDevice(host, l), Catch::Contains("rows"));
    // Contact points, with rows set up on the device.
    StepCounts points = pileCounts();
    l.maxAlloc = points.points * sizeof(btoclContactPoint) - 1;
    points.rows = 1;
    CHECK_THROWS_WITH(checkStepFitsDevice(points, l), Catch::Contains("the contact points buffer"));
}

TEST_CASE("buffers past the global memory together are refused, naming the total and the largest",
          "[device-fit][errors]") {
    DeviceLimits l = roomy();
    l.globalMem = totalBytes(pileCounts());
    REQUIRE_NOTHROW(checkStepFitsDevice(pileCounts(), l));
    l.globalMem -= 1;
    CHECK_THROWS_WITH(checkStepFitsDevice(pileCounts(), l),
                      Catch::Contains("need " + std::to_string(totalBytes(pileCounts())) + " bytes together") &&
                          Catch::Contains("rows buffer") && Catch::Contains("CL_DEVICE_GLOBAL_MEM_SIZE"));
}

TEST_CASE("counts past the kernels' int indices are refused", "[device-fit][errors]") {
    StepCounts c = pileCounts();
    c.rows = size_t(INT_MAX) + 1;
    CHECK_THROWS_WITH(checkStepFitsDevice(c, roomy()), Catch::Contains("2^31 - 1"));
    c = pileCounts();
    c.points = size_t(INT_MAX) / 2 + 1;  // two friction directions each: past INT_MAX
    CHECK_THROWS_WITH(checkStepFitsDevice(c, roomy()), Catch::Contains("friction directions"));
}
