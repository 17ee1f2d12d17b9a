// Start-up cost: builds every kernels/*.cl program embedded in the library, then constructs a
// DevicePrimitives (which warms up its kernels) and runs one tiny sort and scan, timing each;
// then, apart, makes a btOpenCLConstraintSolver and times the first two steps of a small world.
//   startup                 one run in the current PoCL cache; prints JSON
//   startup --cold-warm     runs itself twice with POCL_CACHE_DIR set to a fresh empty
//                           directory (cold), then the same directory again (warm)
//   --boost                 also times the Boost.Compute backend (not used by default):
//                           first construction, again on the same context, on a new context
#include "DeviceBuffer.h"
#include "DevicePrimitives.h"
#include "KernelSources.h"
#include "OclRuntime.h"
#include "btOpenCLConstraintSolver.h"

#include <CLI/CLI.hpp>
#include <btBulletDynamicsCommon.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

using namespace btocl;

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool endsWith(const std::string& s, const char* tail) {
    const size_t n = std::strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

// One measurement in this process; prints a JSON object.
int runOnce(bool withBoost) {
    const auto tAll = std::chrono::steady_clock::now();
    auto t0 = std::chrono::steady_clock::now();
    OclRuntime rt("");
    const double msRuntime = msSince(t0);

    std::string programs;
    double msPrograms = 0;
    for (const EmbeddedKernelFile& f : embeddedKernelFiles()) {
        const std::string name = f.name;
        if (!endsWith(name, ".cl")) continue;
        t0 = std::chrono::steady_clock::now();
        rt.buildProgramFile(name);
        const double ms = msSince(t0);
        msPrograms += ms;
        char line[256];
        std::snprintf(line, sizeof line, "%s\n      {\"file\": \"%s\", \"build_ms\": %.1f}", programs.empty() ? "" : ",",
                      name.c_str(), ms);
        programs += line;
    }

    t0 = std::chrono::steady_clock::now();
    DevicePrimitives prims(rt);
    const double msPrimitives = msSince(t0);

    t0 = std::chrono::steady_clock::now();
    std::vector<cl_uint> keys = {5, 3, 5, 1, 0, 3, 2, 7};
    DeviceBuffer<cl_uint> k, v;
    k.write(rt, keys);
    v.write(rt, keys);
    prims.sortByKeySmallRange(k.buffer(), v.buffer(), keys.size(), 8);
    prims.exclusiveScan(v.buffer(), v.buffer(), keys.size());
    rt.finish("tiny sort and scan");
    const double msTiny = msSince(t0);

    const double msTotal = msSince(tAll);

    // What a user waits for: the solver made, then the first steps of a small world (PoCL
    // generates each kernel's code at its first launch), apart from the totals above.
    t0 = std::chrono::steady_clock::now();
    btOpenCLConstraintSolver solver;
    const double msSolver = msSince(t0);
    btDefaultCollisionConfiguration collisionConfig;
    btCollisionDispatcher dispatcher(&collisionConfig);
    btDbvtBroadphase broadphase;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &collisionConfig);
    btBoxShape ground(btVector3(20, 1, 20)), box(btVector3(0.5f, 0.5f, 0.5f));
    btRigidBody groundBody(0, nullptr, &ground);
    groundBody.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, -1, 0)));
    world.addRigidBody(&groundBody);
    btVector3 inertia;
    box.calculateLocalInertia(1, inertia);
    std::vector<std::unique_ptr<btRigidBody>> boxes;
    for (int i = 0; i < 10; ++i) {
        boxes.emplace_back(new btRigidBody(1, nullptr, &box, inertia));
        boxes.back()->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.5f + i, 0)));
        world.addRigidBody(boxes.back().get());
    }
    double msSteps[2];
    for (double& ms : msSteps) {
        t0 = std::chrono::steady_clock::now();
        world.stepSimulation(1.f / 60, 0);
        ms = msSince(t0);
    }
    for (auto& b : boxes) world.removeRigidBody(b.get());
    world.removeRigidBody(&groundBody);

    // For comparison, not part of the total: what the Boost.Compute backend costs. Boost.Compute
    // keeps its compiled programs per OpenCL context, in memory only.
    double msBoost[3] = {0, 0, 0};
    if (withBoost) {
        t0 = std::chrono::steady_clock::now();
        DevicePrimitives boostFirst(rt, DevicePrimitives::Backend::BoostCompute);
        msBoost[0] = msSince(t0);
        t0 = std::chrono::steady_clock::now();
        DevicePrimitives boostSameContext(rt, DevicePrimitives::Backend::BoostCompute);
        msBoost[1] = msSince(t0);
        OclRuntime rt2("");
        t0 = std::chrono::steady_clock::now();
        DevicePrimitives boostNewContext(rt2, DevicePrimitives::Backend::BoostCompute);
        msBoost[2] = msSince(t0);
    }

    std::printf("{\"device\": \"%s\", \"pocl_cache_dir\": \"%s\",\n"
                "    \"runtime_ms\": %.1f, \"programs_build_ms\": %.1f, \"programs\": [%s],\n"
                "    \"device_primitives\": \"%s\", \"device_primitives_construct_ms\": %.1f,"
                " \"tiny_sort_scan_ms\": %.2f, \"total_ms\": %.1f,\n"
                "    \"solver_construct_ms\": %.1f, \"first_step_ms\": %.1f, \"second_step_ms\": %.1f",
                rt.deviceName().c_str(), std::getenv("POCL_CACHE_DIR") ? std::getenv("POCL_CACHE_DIR") : "(default)",
                msRuntime, msPrograms, programs.c_str(), prims.backendName(), msPrimitives, msTiny, msTotal, msSolver,
                msSteps[0], msSteps[1]);
    if (withBoost)
        std::printf(",\n    \"boost_compute_construct_ms\": {\"first\": %.1f, \"again_same_context\": %.1f,"
                    " \"new_context\": %.1f}",
                    msBoost[0], msBoost[1], msBoost[2]);
    std::printf("}");
    std::fflush(stdout);
    return 0;
}

// Runs this program again (single mode) with POCL_CACHE_DIR=dir; returns its exit status.
int runChild(const char* self, const std::string& dir, bool withBoost) {
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        setenv("POCL_CACHE_DIR", dir.c_str(), 1);
        execl(self, self, withBoost ? "--boost" : static_cast<char*>(nullptr), static_cast<char*>(nullptr));
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

}  // namespace

int main(int argc, char** argv) {
    bool coldWarm = false, withBoost = false;
    CLI::App app("Start-up cost: builds every embedded OpenCL program, constructs DevicePrimitives and runs\n"
                 "a tiny sort and scan, then makes a btOpenCLConstraintSolver and times the first two steps of\n"
                 "a small world. Prints JSON.",
                 "startup");
    app.add_flag("--cold-warm", coldWarm,
                 "two runs in child processes: cold (a fresh POCL_CACHE_DIR), then warm (the same one)");
    app.add_flag("--boost", withBoost, "also time constructing the Boost.Compute backend (first, same and new context)");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "startup: %s\nRun startup --help for the options.\n", e.what());
        return 2;
    }
    try {
        if (coldWarm) {
            std::array<char, 64> tmpl{};
            std::snprintf(tmpl.data(), tmpl.size(), "/tmp/btocl-pocl-cache-XXXXXX");
            if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
            const std::string dir = tmpl.data();
            std::printf("{\"cold\": ");
            std::fflush(stdout);
            int rc = runChild("/proc/self/exe", dir, withBoost);
            std::printf(",\n \"warm\": ");
            std::fflush(stdout);
            rc |= runChild("/proc/self/exe", dir, withBoost);
            std::printf("}\n");
            const std::string rm = "rm -rf '" + dir + "'";
            if (std::system(rm.c_str()) != 0) std::fprintf(stderr, "startup: could not remove %s\n", dir.c_str());
            return rc;
        }
        const int rc = runOnce(withBoost);
        std::printf("\n");
        return rc;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "startup: %s\n", e.what());
        return 1;
    }
}
