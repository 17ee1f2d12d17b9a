// Start-up cost: builds every kernels/*.cl program embedded in the library, then constructs a
// DevicePrimitives (which warms up its kernels) and runs one tiny sort and scan, timing each;
// then, apart, makes a btOpenCLConstraintSolver and times the first two steps of a small world.
//   startup                 one run in the current PoCL cache; prints JSON
//   startup --cold-warm     runs itself twice with POCL_CACHE_DIR set to a fresh empty
//                           directory (cold), then the same directory again (warm), and
//                           prints both runs' JSON in one object
//   --boost                 also times the Boost.Compute backend (not used by default):
//                           first construction, again on the same context, on a new context
#include "CliChecks.h"
#include "DeviceBuffer.h"
#include "DevicePrimitives.h"
#include "KernelSources.h"
#include "OclRuntime.h"
#include "btOpenCLConstraintSolver.h"

#include <CLI/CLI.hpp>
#include <btBulletDynamicsCommon.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

using namespace btocl;
using Json = nlohmann::ordered_json;

namespace {

// Times in the JSON keep only the digits that mean something (ms to 0.1, or 0.01 for the tiny
// sort and scan).
double rounded(double ms, int decimals) {
    const double scale = std::pow(10.0, decimals);
    return std::round(ms * scale) / scale;
}

std::string dumpJson(const Json& j) { return j.dump(2, ' ', false, Json::error_handler_t::replace); }

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool endsWith(const std::string& s, const char* tail) {
    const size_t n = std::strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

// One measurement in this process, as a JSON object.
Json runOnce(bool withBoost) {
    const auto tAll = std::chrono::steady_clock::now();
    auto t0 = std::chrono::steady_clock::now();
    OclRuntime rt("");
    const double msRuntime = msSince(t0);

    Json programs = Json::array();
    double msPrograms = 0;
    for (const EmbeddedKernelFile& f : embeddedKernelFiles()) {
        const std::string name = f.name;
        if (!endsWith(name, ".cl")) continue;
        t0 = std::chrono::steady_clock::now();
        rt.buildProgramFile(name);
        const double ms = msSince(t0);
        msPrograms += ms;
        programs.push_back({{"file", name}, {"build_ms", rounded(ms, 1)}});
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

    const char* cacheDir = std::getenv("POCL_CACHE_DIR");
    Json out;
    out["device"] = rt.deviceName();
    out["pocl_cache_dir"] = cacheDir ? cacheDir : "(default)";
    out["runtime_ms"] = rounded(msRuntime, 1);
    out["programs_build_ms"] = rounded(msPrograms, 1);
    out["programs"] = std::move(programs);
    out["device_primitives"] = prims.backendName();
    out["device_primitives_construct_ms"] = rounded(msPrimitives, 1);
    out["tiny_sort_scan_ms"] = rounded(msTiny, 2);
    out["total_ms"] = rounded(msTotal, 1);
    out["solver_construct_ms"] = rounded(msSolver, 1);
    out["first_step_ms"] = rounded(msSteps[0], 1);
    out["second_step_ms"] = rounded(msSteps[1], 1);
    if (withBoost)
        out["boost_compute_construct_ms"] = {{"first", rounded(msBoost[0], 1)},
                                             {"again_same_context", rounded(msBoost[1], 1)},
                                             {"new_context", rounded(msBoost[2], 1)}};
    return out;
}

// Runs this program again (single mode) with POCL_CACHE_DIR=dir, its stdout read through a pipe
// (its stderr is ours); `result` gets the JSON it printed, or null when that does not parse.
// Returns its exit status, 1 when it exited 0 but printed no JSON.
int runChild(const char* self, const std::string& dir, bool withBoost, Json& result) {
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        throw std::runtime_error("fork failed");
    }
    if (pid == 0) {
        dup2(fds[1], STDOUT_FILENO);
        close(fds[0]);
        close(fds[1]);
        setenv("POCL_CACHE_DIR", dir.c_str(), 1);
        execl(self, self, withBoost ? "--boost" : static_cast<char*>(nullptr), static_cast<char*>(nullptr));
        _exit(127);
    }
    close(fds[1]);
    std::string text;
    char chunk[4096];
    for (;;) {
        const ssize_t got = read(fds[0], chunk, sizeof chunk);
        if (got > 0)
            text.append(chunk, size_t(got));
        else if (got == 0 || errno != EINTR)
            break;
    }
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
    result = Json::parse(text, nullptr, false);
    if (result.is_discarded()) {
        std::fprintf(stderr, "startup: the run with POCL_CACHE_DIR=%s printed no JSON (exit status %d)\n",
                     dir.c_str(), rc);
        result = nullptr;
        return rc != 0 ? rc : 1;
    }
    return rc;
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
    if (const std::optional<int> status = btdemo::parseOrExitCode(app, argc, argv, "startup")) return *status;
    try {
        if (coldWarm) {
            std::array<char, 64> tmpl{};
            std::snprintf(tmpl.data(), tmpl.size(), "/tmp/btocl-pocl-cache-XXXXXX");
            if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
            const std::string dir = tmpl.data();
            Json out;
            int rc = runChild("/proc/self/exe", dir, withBoost, out["cold"]);
            rc |= runChild("/proc/self/exe", dir, withBoost, out["warm"]);
            std::printf("%s\n", dumpJson(out).c_str());
            const std::string rm = "rm -rf '" + dir + "'";
            if (std::system(rm.c_str()) != 0) std::fprintf(stderr, "startup: could not remove %s\n", dir.c_str());
            return rc;
        }
        std::printf("%s\n", dumpJson(runOnce(withBoost)).c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "startup: %s\n", e.what());
        return 1;
    }
}
