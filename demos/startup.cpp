// Start-up cost as a user meets it: the solver made, then a scene whose contacts start later (a
// drop), stepped at 60 Hz for two seconds of simulated time, each step timed. Prints JSON: the
// construction time, the first second (construction plus its 60 steps, the budget), the
// slowest step against the run's median step, and the first step with contacts.
//   startup --scene drop           one run in the current PoCL cache
//   startup --cold-warm            for each scene, a child process with POCL_CACHE_DIR set to a
//                                  fresh empty directory (cold: programs from the binaries the
//                                  build made, where it made them), then another on the same
//                                  directory (warm), then one on another fresh directory with
//                                  BT_OPENCL_KERNEL_BINARIES=off (cold_compiled: a machine the
//                                  build's binaries do not serve); the runs' JSON in one object
//   startup --kernels              the solver's parts apart, in the current PoCL cache: the
//                                  runtime, the programs built, then each kernel's warm-up launch
//                                  timed on its own (its compile, with an empty cache); with
//                                  --boost also the Boost.Compute backend made (not used by the
//                                  serial path): first, again on the same context, on a new one
// Scenes: basic (Bullet's BasicDemo: 125 boxes of 0.2 m falling 1.9 m onto a ground box) and
// drop (3,000 unit boxes in a lattice, the lowest layer 1 m above the ground: the first contact
// at step 27, a pile of some 30K rows by the end of the first second).
#include "CliChecks.h"
#include "DevicePrimitives.h"
#include "KernelWarmUp.h"
#include "OclRuntime.h"
#include "StepPipeline.h"
#include "btOpenCLConstraintSolver.h"
#include "scenes/World.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

using Json = nlohmann::ordered_json;

namespace {

constexpr btScalar kDt = btScalar(1.0 / 60.0);
constexpr int kStepsPerSecond = 60;
constexpr int kSteps = 2 * kStepsPerSecond;

double rounded(double ms, int decimals = 1) {
    const double scale = std::pow(10.0, decimals);
    return std::round(ms * scale) / scale;
}

std::string dumpJson(const Json& j) { return j.dump(2, ' ', false, Json::error_handler_t::replace); }

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Bullet's BasicDemo: a 5 x 5 x 5 block of boxes of half extent 0.1, 2 m up, on a ground box.
void basicDemo(btscenes::World& w) {
    w.addBox(btVector3(50, 50, 50), 0, btscenes::at(btVector3(0, -50, 0)));
    for (int k = 0; k < 5; ++k)
        for (int i = 0; i < 5; ++i)
            for (int j = 0; j < 5; ++j)
                w.addBox(btVector3(0.1f, 0.1f, 0.1f), 1,
                         btscenes::at(btVector3(0.2f * btScalar(i), 2 + 0.2f * btScalar(k), 0.2f * btScalar(j))));
}

// `boxes` unit boxes in layers of 15 x 15, 1.5 m apart, the lowest 1 m above the ground, each
// layer shifted a little so that the boxes land on each other's edges and pile up.
void dropLattice(btscenes::World& w, int boxes) {
    w.addGround();
    constexpr int side = 15;
    constexpr btScalar spacing = 1.5f;
    for (int n = 0; n < boxes; ++n) {
        const int ix = n % side, iz = (n / side) % side, iy = n / (side * side);
        const btScalar shift = 0.3f * btScalar((iy * 7) % 5 - 2) / 2;
        w.addUnitBox(btVector3(btScalar(ix - side / 2) * spacing + shift, 1.5f + btScalar(iy) * spacing,
                               btScalar(iz - side / 2) * spacing - shift));
    }
}

int contactPoints(btscenes::World& w) {
    int points = 0;
    for (int m = 0; m < w.dispatcher().getNumManifolds(); ++m)
        points += w.dispatcher().getManifoldByIndexInternal(m)->getNumContacts();
    return points;
}

struct StepTimes {
    std::vector<double> ms;
    std::vector<int> rows;  // constraint rows of each step
    int firstContactStep = -1;
};

// One run in this process: the solver made (timed), the scene built and stepped. With `bullet`,
// Bullet's own solver steps the scene: its steps show what the scene costs without ours (a pile
// landing makes slow steps of Bullet's collision detection too).
Json runOnce(const std::string& scene, int boxes, bool bullet) {
    btOpenCLSolverConfig config;
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<btConstraintSolver> solver;
    if (bullet)
        solver = std::make_unique<btSequentialImpulseConstraintSolver>();
    else
        solver = std::make_unique<btOpenCLConstraintSolver>(config);
    const double msConstruct = msSince(t0);
    auto* ours = dynamic_cast<btOpenCLConstraintSolver*>(solver.get());

    btscenes::World w(solver.get());
    if (scene == "basic")
        basicDemo(w);
    else
        dropLattice(w, boxes);

    StepTimes steps;
    for (int i = 0; i < kSteps; ++i) {
        const auto ts = std::chrono::steady_clock::now();
        w.step(kDt);
        steps.ms.push_back(msSince(ts));
        steps.rows.push_back(ours ? ours->getLastStats().numConstraintRows : 0);
        if (steps.firstContactStep < 0 && contactPoints(w) > 0) steps.firstContactStep = i;
    }

    std::vector<double> sorted = steps.ms;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const auto slowest = std::max_element(steps.ms.begin(), steps.ms.end());
    double firstSecond = 0;
    for (int i = 0; i < kStepsPerSecond; ++i) firstSecond += steps.ms[size_t(i)];

    const char* cacheDir = std::getenv("POCL_CACHE_DIR");
    Json out;
    out["scene"] = scene;
    out["bodies"] = w.numDynamicBodies();
    out["solver"] = ours ? "btOpenCLConstraintSolver" : "btSequentialImpulseConstraintSolver";
    if (ours) out["device"] = ours->getDeviceName();
    out["pocl_cache_dir"] = cacheDir ? cacheDir : "(default)";
    const char* binaries = std::getenv("BT_OPENCL_KERNEL_BINARIES");
    out["kernel_binaries"] = binaries ? binaries : "(the build's)";
    out["construct_ms"] = rounded(msConstruct);
    out["first_second_steps_ms"] = rounded(firstSecond);
    out["construct_plus_first_second_ms"] = rounded(msConstruct + firstSecond);
    out["first_contact_step"] = steps.firstContactStep;
    out["first_contact_step_ms"] =
        steps.firstContactStep >= 0 ? rounded(steps.ms[size_t(steps.firstContactStep)], 2) : 0.0;
    out["slowest_step"] = {{"step", int(slowest - steps.ms.begin())}, {"ms", rounded(*slowest, 2)}};
    out["median_step_ms"] = rounded(median, 2);
    out["slowest_over_median"] = rounded(*slowest / median, 2);
    std::vector<int> order(steps.ms.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return steps.ms[size_t(a)] > steps.ms[size_t(b)]; });
    Json slowestFive = Json::array();
    for (size_t k = 0; k < 5 && k < order.size(); ++k)
        slowestFive.push_back({{"step", order[k]}, {"ms", rounded(steps.ms[size_t(order[k])], 2)},
                               {"rows", steps.rows[size_t(order[k])]}});
    out["slowest_steps"] = std::move(slowestFive);
    if (ours) {
        out["last_step_rows"] = ours->getLastStats().numConstraintRows;
        out["last_step_whole"] = ours->getLastStats().solvedWholeStep;
    }
    return out;
}

// The solver's start-up in its parts: the pipeline made (device, programs, kernel objects), the
// sort and scan warmed up, then each kernel's warm-up launch on its own.
Json kernelTimes(bool withBoost) {
    btOpenCLSolverConfig config;
    auto t0 = std::chrono::steady_clock::now();
    btocl::StepPipeline pipeline(config);
    const double msPipeline = msSince(t0);
    btocl::KernelWarmUp timed(pipeline.runtime(), true);
    t0 = std::chrono::steady_clock::now();
    pipeline.warmUp(&timed);
    const double msWarmUp = msSince(t0);
    Json kernels = Json::array();
    double msKernels = 0;
    for (const btocl::KernelWarmUp::Timing& t : timed.timings()) {
        kernels.push_back({{"kernel", t.kernel}, {"local", t.local}, {"ms", rounded(t.ms)}});
        msKernels += t.ms;
    }
    Json programs = Json::array();
    for (const btocl::OclRuntime::ProgramBuild& b : pipeline.runtime().programBuilds())
        programs.push_back({{"program", b.name}, {"ms", rounded(b.ms)}, {"from_binary", b.fromBinary}});
    const char* cacheDir = std::getenv("POCL_CACHE_DIR");
    Json out;
    out["device"] = pipeline.runtime().deviceName();
    out["pocl_cache_dir"] = cacheDir ? cacheDir : "(default)";
    out["path"] = pipeline.plan().wide() ? "wide" : "serial";
    out["pipeline_made_ms"] = rounded(msPipeline);
    out["programs"] = std::move(programs);
    out["warm_up_ms"] = rounded(msWarmUp);
    out["sort_and_scan_warm_up_ms"] = rounded(msWarmUp - msKernels);
    out["kernels"] = std::move(kernels);
    if (withBoost) {
        // Boost.Compute keeps its compiled programs per OpenCL context, in memory only.
        using btocl::DevicePrimitives;
        t0 = std::chrono::steady_clock::now();
        DevicePrimitives first(pipeline.runtime(), DevicePrimitives::Backend::BoostCompute);
        const double msFirst = msSince(t0);
        t0 = std::chrono::steady_clock::now();
        DevicePrimitives sameContext(pipeline.runtime(), DevicePrimitives::Backend::BoostCompute);
        const double msSame = msSince(t0);
        btocl::OclRuntime other("");
        t0 = std::chrono::steady_clock::now();
        DevicePrimitives newContext(other, DevicePrimitives::Backend::BoostCompute);
        out["boost_compute_construct_ms"] = {{"first", rounded(msFirst)},
                                             {"again_same_context", rounded(msSame)},
                                             {"new_context", rounded(msSince(t0))}};
    }
    return out;
}

// Runs this program again for one scene (single mode) with POCL_CACHE_DIR=dir (and, with
// `compiled`, BT_OPENCL_KERNEL_BINARIES=off), its stdout read through a pipe (its stderr is
// ours); `result` gets the JSON it printed, or null when that does not parse. Returns its exit
// status, 1 when it exited 0 but printed no JSON.
int runChild(const char* self, const std::string& dir, bool compiled, const std::string& scene, int boxes,
             Json& result) {
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
        if (compiled) setenv("BT_OPENCL_KERNEL_BINARIES", "off", 1);
        const std::string boxesText = std::to_string(boxes);
        execl(self, self, "--scene", scene.c_str(), "--boxes", boxesText.c_str(), static_cast<char*>(nullptr));
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

std::string freshCacheDir() {
    std::array<char, 64> tmpl{};
    std::snprintf(tmpl.data(), tmpl.size(), "/tmp/btocl-pocl-cache-XXXXXX");
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    return tmpl.data();
}

}  // namespace

int main(int argc, char** argv) {
    bool coldWarm = false, kernels = false, bullet = false, withBoost = false;
    std::vector<std::string> scenes;
    int boxes = 3000;
    CLI::App app("Start-up cost as a user meets it: makes a btOpenCLConstraintSolver (timed), then steps a\n"
                 "scene whose contacts start later for two seconds at 60 Hz, each step timed. Prints JSON.",
                 "startup");
    app.add_flag("--cold-warm", coldWarm,
                 "per scene, three runs in child processes: cold (a fresh POCL_CACHE_DIR), warm (the same one), "
                 "cold_compiled (another fresh one, BT_OPENCL_KERNEL_BINARIES=off)");
    app.add_flag("--kernels", kernels, "the solver's start-up in its parts, each kernel's warm-up timed apart");
    app.add_option("--scene", scenes, "basic (BasicDemo's 125 boxes) or drop (a lattice of --boxes unit boxes); "
                                      "default: drop alone, or both with --cold-warm")
        ->check(CLI::IsMember({"basic", "drop"}));
    app.add_flag("--boost", withBoost, "with --kernels: also time making the Boost.Compute backend");
    app.add_flag("--bullet", bullet, "step the scene with Bullet's own solver instead (for the scene's own slow steps)");
    app.add_option("--boxes", boxes, "boxes of the drop scene (default 3000)")->transform(btdemo::integerIn(1, 1000000));
    if (const std::optional<int> status = btdemo::parseOrExitCode(app, argc, argv, "startup")) return *status;
    try {
        if (coldWarm) {
            if (scenes.empty()) scenes = {"basic", "drop"};
            Json out = Json::array();
            int rc = 0;
            auto remove = [](const std::string& dir) {
                const std::string rm = "rm -rf '" + dir + "'";
                if (std::system(rm.c_str()) != 0) std::fprintf(stderr, "startup: could not remove %s\n", dir.c_str());
            };
            for (const std::string& scene : scenes) {
                const std::string dir = freshCacheDir(), other = freshCacheDir();
                Json run;
                rc |= runChild("/proc/self/exe", dir, false, scene, boxes, run["cold"]);
                rc |= runChild("/proc/self/exe", dir, false, scene, boxes, run["warm"]);
                rc |= runChild("/proc/self/exe", other, true, scene, boxes, run["cold_compiled"]);
                out.push_back(run);
                remove(dir);
                remove(other);
            }
            std::printf("%s\n", dumpJson(out).c_str());
            return rc;
        }
        if (kernels) {
            std::printf("%s\n", dumpJson(kernelTimes(withBoost)).c_str());
            return 0;
        }
        if (scenes.size() > 1) throw std::runtime_error("one --scene at a time without --cold-warm");
        std::printf("%s\n", dumpJson(runOnce(scenes.empty() ? "drop" : scenes.front(), boxes, bullet)).c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "startup: %s\n", e.what());
        return 1;
    }
}
