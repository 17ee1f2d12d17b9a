// The warm-up (btOpenCLSolverConfig::warmUpAtConstruction, btOpenCLConstraintSolver::warmUp):
// every kernel the solver can launch compiled before a step needs it, and no step changed by it.
#include "JointScenes.h"
#include "KernelSources.h"
#include "Scenes.h"
#include "TestDevice.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <vector>

using namespace testworld;
namespace fs = std::filesystem;

namespace {

// A pile with a chain beside it: contacts, joints (rows set up on the host) and split impulse.
void pileAndChain(World& w) {
    groundAndPile(w, 300);
    btscenes::addChain(w, btVector3(12, 8, 0), 8, 1);
}

}  // namespace

TEST_CASE("a warm-up changes no result: at construction, later, or never", "[warm-up]") {
    const int wholeStepMaxRows = GENERATE(1000000, 0);  // whole steps, then every step split
    const bool push = GENERATE(false, true);
    CAPTURE(wholeStepMaxRows, push);
    auto makeConfig = [&](bool warmUpAtConstruction) {
        btOpenCLSolverConfig c = validatingConfig();
        c.hostStepMaxRows = 0;  // every step on the device, whose kernels the warm-up compiles
        c.wholeStepMaxRows = wholeStepMaxRows;
        c.warmUpAtConstruction = warmUpAtConstruction;
        return c;
    };
    World atConstruction(SolverKind::OpenCL, makeConfig(true));
    World never(SolverKind::OpenCL, makeConfig(false));
    World later(SolverKind::OpenCL, makeConfig(false));
    for (World* w : {&atConstruction, &never, &later}) {
        pileAndChain(*w);
        w->info().m_splitImpulse = push ? 1 : 0;
    }
    for (int s = 0; s < 40; ++s) {
        if (s == 20) {
            later.openCL()->warmUp();
            later.openCL()->warmUp();  // a second call does nothing
        }
        for (World* w : {&atConstruction, &never, &later}) w->step();
        const btOpenCLSolverStats& a = atConstruction.openCL()->getLastStats();
        for (World* w : {&never, &later}) {
            const btOpenCLSolverStats& b = w->openCL()->getLastStats();
            INFO("step " << s);
            REQUIRE(a.numConstraintRows == b.numConstraintRows);
            REQUIRE(a.numGroups == b.numGroups);
            REQUIRE(a.numIterationsRun == b.numIterationsRun);
            REQUIRE(a.solvedWholeStep == b.solvedWholeStep);
            REQUIRE(bodyBytes(atConstruction) == bodyBytes(*w));
        }
    }
    const btOpenCLSolverStats& last = atConstruction.openCL()->getLastStats();
    CHECK(last.numJointRows > 0);
    CHECK(last.solvedWholeStep == (wholeStepMaxRows != 0));
}

namespace {

// The kernels' code PoCL has generated into its cache, as "<kernel>/<variant>" (the variant
// names the local size and grid it was made for: 64-1-1-goffs0-smallgrid), ours alone (the sort
// library's kernels on the wide path are Boost.Compute's, which it launches in shapes of its own).
std::multiset<std::string> ourCompiledKernels(const fs::path& cache) {
    std::string sources;
    for (const btocl::EmbeddedKernelFile& f : btocl::embeddedKernelFiles()) sources += f.text;
    std::multiset<std::string> out;
    if (!fs::exists(cache)) return out;
    for (const auto& prefix : fs::directory_iterator(cache)) {
        if (!prefix.is_directory()) continue;
        for (const auto& program : fs::directory_iterator(prefix.path())) {
            if (!program.is_directory()) continue;
            for (const auto& kernel : fs::directory_iterator(program.path())) {
                const std::string name = kernel.path().filename().string();
                if (!kernel.is_directory() || sources.find(" " + name + "(") == std::string::npos) continue;
                for (const auto& variant : fs::directory_iterator(kernel.path()))
                    if (variant.is_directory()) out.insert(name + "/" + variant.path().filename().string());
            }
        }
    }
    return out;
}

// The kernel of a "<kernel>/<variant>" entry.
std::string kernelOf(const std::string& compiled) { return compiled.substr(0, compiled.find('/')); }

std::set<std::string> kernelNames(const std::multiset<std::string>& compiled) {
    std::set<std::string> names;
    for (const std::string& k : compiled) names.insert(kernelOf(k));
    return names;
}

void stepScene(const btOpenCLSolverConfig& config, int steps, const std::function<void(World&)>& build,
               const std::function<void(const btOpenCLSolverStats&)>& check = {}) {
    World w(SolverKind::OpenCL, config);
    build(w);
    for (int s = 0; s < steps; ++s) w.step();
    if (check) check(w.openCL()->getLastStats());
}

}  // namespace

// Hidden ([.]): run in a process of its own by ctest with POCL_CACHE_DIR set to a directory of the
// build that it empties first, before PoCL starts in the process: kernel_warm_up_cache compiles
// (BT_OPENCL_KERNEL_BINARIES=off); kernel_binaries_cache has the build's binaries
// (BTOCL_TEST_KERNELS=binaries), from which the program comes with its kernels' code.
TEST_CASE("after the warm-up, no step makes PoCL generate a kernel", "[.][warm-up-cache]") {
    const char* dirText = std::getenv("POCL_CACHE_DIR");
    REQUIRE(dirText != nullptr);
    const fs::path cache(dirText);
    // Never empty a cache this test did not make its own.
    REQUIRE(cache.filename().string().rfind("btocl-test-pocl-cache", 0) == 0);
    fs::remove_all(cache);
    fs::create_directories(cache);
    const char* kernels = std::getenv("BTOCL_TEST_KERNELS");
    const bool fromBinaries = kernels && std::string(kernels) == "binaries";

    btOpenCLSolverConfig deferred;
    deferred.warmUpAtConstruction = false;
    btOpenCLConstraintSolver solver(deferred);
    const std::multiset<std::string> made = ourCompiledKernels(cache);
    if (fromBinaries)
        CHECK(made.size() > 5);  // the binary brought the kernels' code
    else
        CHECK(made.empty());  // made without compiling any kernel
    solver.warmUp();
    const std::multiset<std::string> warm = ourCompiledKernels(cache);
    INFO("after the warm-up: " << Catch::Detail::stringify(warm));
    REQUIRE(warm.size() > 5);
    if (fromBinaries) {
        // Nothing compiled by the warm-up either: each kernel came with a program's binary, which
        // carries a generic variant of every kernel besides those launched ("0-0-0": no local
        // size); a kernel there at construction has no variant more after the warm-up. A program
        // made at the warm-up (the wide path's batch program) brings its own.
        std::vector<std::string> compiled;
        for (const std::string& k : warm) {
            const std::string name = kernelOf(k);
            const bool atConstruction = made.count(name + "/0-0-0") != 0;
            if ((atConstruction && made.count(k) == 0) || warm.count(name + "/0-0-0") == 0) compiled.push_back(k);
        }
        INFO("compiled by the warm-up: " << Catch::Detail::stringify(compiled));
        CHECK(compiled.empty());
    } else {
        CHECK(kernelNames(warm).size() == warm.size());  // one variant a kernel
    }

    // Steps of every kind the path runs: whole and split, joints, push, launches past 65,535
    // work-items (a dense block: some 70K contact points). Each solver warms up as it is made
    // (the default), from what the process has already loaded.
    btOpenCLSolverConfig config = validatingConfig();
    config.hostStepMaxRows = 0;  // small steps too on the device: its kernels are what this counts
    config.wholeStepMaxRows = 1000000;
    stepScene(config, 30, [](World& w) { groundAndPile(w, 200); },
              [](const btOpenCLSolverStats& s) { CHECK(s.solvedWholeStep); });
    config.wholeStepMaxRows = 0;
    stepScene(config, 30, [](World& w) { pileAndChain(w); w.info().m_splitImpulse = 1; },
              [](const btOpenCLSolverStats& s) {
                  CHECK_FALSE(s.solvedWholeStep);
                  CHECK(s.numJointRows > 0);
              });
    config.wholeStepMaxRows = -1;
    config.validate = false;
    stepScene(config, 2, [](World& w) { btscenes::groundAndBondedBlock(w, 3200); },
              [](const btOpenCLSolverStats& s) { CHECK(s.numContactPoints > 65536); });
    CHECK(ourCompiledKernels(cache) == warm);
}
