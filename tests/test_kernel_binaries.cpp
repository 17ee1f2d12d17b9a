// Programs built from the binaries made with the library (ocl/KernelBinaries.h): the same kernels
// as compiled ones, used only where they fit, passed over where the device refuses them.
#include "KernelBinaries.h"
#include "OclRuntime.h"
#include "Scenes.h"
#include "ScopedEnv.h"
#include "StepPipeline.h"
#include "TestWorld.h"
#include "WorldSnapshot.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace testworld;
using btocl::test::ScopedEnv;
namespace fs = std::filesystem;

namespace {

// A folder of this test's own, emptied when made and removed after.
struct TempDir {
    fs::path path = fs::temp_directory_path() / ("btocl-test-binaries-" + std::to_string(getpid()));
    TempDir() {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

btOpenCLSolverConfig deviceStepsConfig(bool kernelBinaries) {
    btOpenCLSolverConfig c = validatingConfig();
    c.hostStepMaxRows = 0;  // every step on the device: its kernels are what is compared
    c.wholeStepMaxRows = 0;
    c.kernelBinaries = kernelBinaries;
    return c;
}

// Two solvers, one with kernelBinaries on (reading what the environment names), one compiling,
// step the same pile (split steps, split impulse): what they write to Bullet must agree to the bit.
void requireSameSteps() {
    World fromBinary(SolverKind::OpenCL, deviceStepsConfig(true));
    World compiled(SolverKind::OpenCL, deviceStepsConfig(false));
    for (World* w : {&fromBinary, &compiled}) {
        groundAndPile(*w, 200);
        w->info().m_splitImpulse = 1;
    }
    for (int s = 0; s < 30; ++s) {
        fromBinary.step();
        compiled.step();
        INFO("step " << s);
        REQUIRE(solveOutputsOf(fromBinary.bodies(), fromBinary.manifolds()) ==
                solveOutputsOf(compiled.bodies(), compiled.manifolds()));
    }
    CHECK(fromBinary.openCL()->getLastStats().numContactPoints > 100);
}

}  // namespace

TEST_CASE("a program built from its binary is the compiled one: the same results to the bit", "[kernel-binaries]") {
    TempDir dir;
    std::string key;
    {
        btocl::StepPipeline compiled(deviceStepsConfig(false));
        compiled.warmUp();
        REQUIRE_FALSE(compiled.runtime().programBuilds().empty());
        CHECK_FALSE(compiled.runtime().programBuilds().front().fromBinary);
        compiled.runtime().writeProgramBinaries(dir.path.string());
        key = compiled.runtime().programBuilds().front().binaryKey;
    }
    REQUIRE(fs::exists(dir.path / (key + ".bin")));
    {
        btOpenCLSolverConfig config = deviceStepsConfig(true);
        config.kernelBinaryDir = dir.path.string();  // the config's folder, whatever the environment says
        ScopedEnv off("BT_OPENCL_KERNEL_BINARIES", "off");
        btocl::StepPipeline fromConfig(config);
        CHECK(fromConfig.runtime().programBuilds().front().fromBinary);
    }
    ScopedEnv env("BT_OPENCL_KERNEL_BINARIES", dir.path.string().c_str());
    {
        btocl::StepPipeline loaded(deviceStepsConfig(true));
        REQUIRE(loaded.runtime().programBuilds().front().fromBinary);
        CHECK(loaded.runtime().programBuilds().front().binaryKey == key);
        btocl::StepPipeline off(deviceStepsConfig(false));  // the config's switch
        CHECK_FALSE(off.runtime().programBuilds().front().fromBinary);
    }
    requireSameSteps();
}

TEST_CASE("a binary the device refuses, or none, or 'off': the program is compiled", "[kernel-binaries]") {
    TempDir dir;
    std::string key;
    {
        btocl::StepPipeline compiled(deviceStepsConfig(false));
        key = compiled.runtime().programBuilds().front().binaryKey;
    }
    SECTION("a damaged file") {
        std::ofstream(dir.path / (key + ".bin"), std::ios::binary) << "not a program binary";
        ScopedEnv env("BT_OPENCL_KERNEL_BINARIES", dir.path.string().c_str());
        btocl::StepPipeline p(deviceStepsConfig(true));
        CHECK_FALSE(p.runtime().programBuilds().front().fromBinary);
        requireSameSteps();
    }
    SECTION("a folder without it") {
        ScopedEnv env("BT_OPENCL_KERNEL_BINARIES", dir.path.string().c_str());
        btocl::StepPipeline p(deviceStepsConfig(true));
        CHECK_FALSE(p.runtime().programBuilds().front().fromBinary);
    }
    SECTION("off") {
        ScopedEnv env("BT_OPENCL_KERNEL_BINARIES", "off");
        CHECK(btocl::kernelBinaryDirs().empty());
        btocl::StepPipeline p(deviceStepsConfig(true));
        CHECK_FALSE(p.runtime().programBuilds().front().fromBinary);
    }
}

TEST_CASE("a binary's name changes with its source, its options and its device", "[kernel-binaries]") {
    btocl::OclRuntime rt("");
    const std::string key = btocl::kernelBinaryKey("kernel void k() {}", "-DA", rt.device());
    CHECK(key.size() == 16);
    CHECK(key == btocl::kernelBinaryKey("kernel void k() {}", "-DA", rt.device()));
    CHECK(key != btocl::kernelBinaryKey("kernel void k() { }", "-DA", rt.device()));
    CHECK(key != btocl::kernelBinaryKey("kernel void k() {}", "-DB", rt.device()));
    CHECK(key != btocl::kernelBinaryKey("kernel void k() {}-DA", "", rt.device()));
    const std::vector<btocl::DeviceEntry> devices = btocl::listDevices();
    for (const btocl::DeviceEntry& d : devices)
        if (d.deviceName != rt.device().getInfo<CL_DEVICE_NAME>())  // another device
            CHECK(key != btocl::kernelBinaryKey("kernel void k() {}", "-DA", d.device));
}
