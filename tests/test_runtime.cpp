// The OpenCL runtime layer: device choice, program builds, errors.
#include "OclRuntime.h"
#include "DeviceBuffer.h"
#include "btOpenCLConstraintSolver.h"
#include "btocl_shared.h"

#include <catch2/catch.hpp>

#include <numeric>

using namespace btocl;

TEST_CASE("a trivial kernel runs and its result is right", "[runtime]") {
    OclRuntime rt("");
    const char* src = "__kernel void square(__global const int* in, __global int* out) {"
                      "  int i = get_global_id(0); out[i] = in[i] * in[i] + 1; }";
    cl::Program program = rt.buildProgramSource(src, "square");
    cl::Kernel k = rt.makeKernel(program, "square");
    std::vector<int> in(1000);
    std::iota(in.begin(), in.end(), -500);
    DeviceBuffer<int> a, b;
    a.write(rt, in);
    b.reserve(rt, in.size());
    k.setArg(0, a.buffer());
    k.setArg(1, b.buffer());
    checkCl(rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(in.size())), "square");
    const std::vector<int> out = b.read(rt, in.size());
    for (size_t i = 0; i < in.size(); ++i) REQUIRE(out[i] == in[i] * in[i] + 1);
}

TEST_CASE("a kernel with a syntax error throws with the compiler's message", "[runtime]") {
    OclRuntime rt("");
    const char* src = "__kernel void broken(__global int* out) { out[0] = undeclared_name_xyz + ; }";
    try {
        rt.buildProgramSource(src, "broken");
        FAIL("the build should have failed");
    } catch (const btOpenCLSolverError& e) {
        const std::string what = e.what();
        INFO(what);
        CHECK(what.find("broken") != std::string::npos);
        CHECK(what.find("undeclared_name_xyz") != std::string::npos);  // the compiler's own words
    }
}

// The host asks a CPU's compiler for software prefetch (btocl_shared.h) and no other: the programs
// must build either way on a CPU, the GPU's way too, though the tests run on a CPU. A GPU's
// compiler may refuse the prefetch (NVIDIA's does: a global pointer where it wants a generic one).
TEST_CASE("the programs that prefetch on a CPU build with and without it", "[runtime]") {
    OclRuntime rt("");
    for (const char* file : {"solve.cl", "setup.cl", "arrange.cl"})
        for (const char* options : {"", "-DBTOCL_CPU_PREFETCH"}) {
            if (*options && !rt.isCpu()) continue;
            INFO(file << " " << options);
            CHECK_NOTHROW(rt.buildProgramFile(file, options));
        }
}

TEST_CASE("an unknown device string lists the devices there are", "[runtime]") {
    const std::vector<DeviceEntry> devices = listDevices();
    REQUIRE_FALSE(devices.empty());
    try {
        OclRuntime rt("no-such-device-anywhere");
        FAIL("selecting an unknown device should throw");
    } catch (const btOpenCLSolverError& e) {
        const std::string what = e.what();
        INFO(what);
        CHECK(what.find("no-such-device-anywhere") != std::string::npos);
        CHECK(what.find(devices.front().deviceName) != std::string::npos);
    }
}

TEST_CASE("devices are chosen by type, index and name", "[runtime]") {
    const std::vector<DeviceEntry> devices = listDevices();
    REQUIRE_FALSE(devices.empty());
    CHECK(OclRuntime("0").deviceName().find(devices[0].deviceName) != std::string::npos);
    CHECK(OclRuntime("cpu").isCpu());
    CHECK(OclRuntime(devices[0].deviceName.substr(0, 6)).deviceName().find(devices[0].deviceName) != std::string::npos);
    btOpenCLSolverConfig config;
    config.device = "cpu";
    btOpenCLConstraintSolver solver(config);
    CHECK(solver.getDeviceName().find(devices[0].deviceName) != std::string::npos);
}

TEST_CASE("host and kernels agree on the layout of the shared structs", "[runtime]") {
    OclRuntime rt("");
    const std::string src = "#include \"btocl_shared.h\"\n"
                            "__kernel void sizes(__global int* out) { out[0] = sizeof(btoclRow);"
                            " out[1] = sizeof(btoclBody); out[2] = sizeof(btoclConstraint);"
                            " out[3] = sizeof(btoclBodyDelta); out[4] = sizeof(btoclGroup); }";
    cl::Program program = rt.buildProgramSource(src, "sizes");
    cl::Kernel k = rt.makeKernel(program, "sizes");
    DeviceBuffer<int> out;
    out.reserve(rt, 5);
    k.setArg(0, out.buffer());
    checkCl(rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1)), "sizes");
    const std::vector<int> s = out.read(rt, 5);
    CHECK(s[0] == int(sizeof(btoclRow)));
    CHECK(s[1] == int(sizeof(btoclBody)));
    CHECK(s[2] == int(sizeof(btoclConstraint)));
    CHECK(s[3] == int(sizeof(btoclBodyDelta)));
    CHECK(s[4] == int(sizeof(btoclGroup)));
}

// Hidden ([.]): each runs in a process of its own by ctest (pocl_threads_pinned / _unpinned), with
// POCL_AFFINITY unset, so that its first solver is the process's first device query.
TEST_CASE("pinPoclThreads pins PoCL's workers through POCL_AFFINITY, unless the first solver says not",
          "[.][pocl-affinity]") {
    REQUIRE(std::getenv("POCL_AFFINITY") == nullptr);
    const char* pin = std::getenv("BTOCL_TEST_PIN");
    REQUIRE(pin != nullptr);
    btOpenCLSolverConfig first, second;
    first.pinPoclThreads = std::string(pin) == "1";
    second.pinPoclThreads = !first.pinPoclThreads;  // too late: the first solver decided
    btOpenCLConstraintSolver a(first);
    btOpenCLConstraintSolver b(second);
    const char* affinity = std::getenv("POCL_AFFINITY");
    if (first.pinPoclThreads)
        CHECK((affinity != nullptr && std::string(affinity) == "1"));
    else
        CHECK(affinity == nullptr);
}
