// btocl_bench: steps one scene in two identical worlds, one with Bullet's
// btSequentialImpulseConstraintSolver and one with btOpenCLConstraintSolver, at the same
// iterations, and prints a JSON summary (timings, counts, quality) on stdout. With
// --with-si-randomized a third world is stepped beside them by Bullet's solver with its order
// randomized (SOLVER_RANDMIZE_ORDER), for its quality.
#include "BenchOptions.h"
#include "BenchSummary.h"
#include "PngFile.h"
#include "Quality.h"
#include "ScenePicture.h"
#include "Scenes.h"
#include "SolverSide.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

using namespace btbench;

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void drawFrame(const std::vector<SolverSide*>& sides, const std::string& file, int frame, RunFacts& facts) {
    std::vector<Panel> panels;
    facts.pngPanels.clear();
    for (SolverSide* s : sides)
        if (s && s->alive) {
            panels.push_back({s->scene.get(), solverLabel(*s)});
            facts.pngPanels.push_back(s->name);
        }
    writePng(file, drawWorlds(panels, 640, 480));
    facts.pngFile = file;
    facts.pngFrame = frame;
}

void reportProgress(int step, int steps, const SolverSide* si, const SolverSide* ours, double elapsed) {
    auto lastMs = [](const SolverSide* s) { return s && !s->msPerStep.empty() ? s->msPerStep.back() : 0.0; };
    const double perStep = elapsed / step;
    std::fprintf(stderr, "step %d/%d  solver ms: si %.1f ours %.1f  wall %.0f ms/step  left %.0f s\n", step, steps,
                 lastMs(si), lastMs(ours), perStep * 1000, perStep * (steps - step));
}

int run(const BenchOptions& options) {
    const SceneInfo* scene = findScene(options.scene);
    if (!scene) {
        std::ostringstream names;
        for (auto& s : allScenes()) names << ' ' << s.name;
        std::fprintf(stderr, "btocl_bench: unknown scene '%s'; scenes:%s\n", options.scene.c_str(), names.str().c_str());
        return 2;
    }
    RunFacts facts;
    facts.scene = scene;
    facts.size = options.size > 0 ? options.size : options.smoke ? scene->smokeSize : scene->defaultSize;
    facts.steps = options.steps >= 0 ? options.steps : options.smoke ? 20 : scene->defaultSteps;
    const int frame = options.frame >= 0 ? options.frame : facts.steps;
    if (!options.pngFile.empty() && frame > facts.steps) {
        std::fprintf(stderr, "btocl_bench: --frame %d is past the last step (%d)\n", frame, facts.steps);
        return 2;
    }
    // Scenes that start at rest should not move at all; the others are judged once settled.
    facts.driftFromStep = scene->startsAtRest ? 0 : facts.steps * 3 / 4;
    // Resting kinetic energy: the mean over the states of the last quarter of the run.
    facts.restingFromStep = facts.steps * 3 / 4;

    btOpenCLSolverConfig config;
    config.validate = options.validate;
    config.solvePath = options.solvePath == "serial" ? btOpenCLSolvePath::Serial
                       : options.solvePath == "wide" ? btOpenCLSolvePath::Wide
                                                     : btOpenCLSolvePath::Auto;
    config.rotatePoints = options.order == "rotated";
    config.wholeStepMaxRows = options.wholeStepMaxRows;
    config.hostStepMaxRows = options.hostStepMaxRows;
    config.splitStepsOnHost = options.splitStepsOnHost;
    std::unique_ptr<SolverSide> si, ours, siRandomized;
    if (options.runSi) si = makeSolverSide("si", SolverKind::BulletSI, *scene, facts.size, options.iterations, config);
    if (options.runOurs)
        ours = makeSolverSide("ours", options.standIn ? SolverKind::BulletSI : SolverKind::OpenCL, *scene, facts.size,
                              options.iterations, config);
    if (ours && ours->scene && options.order == "randomized") ours->scene->info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
    if (options.withSiRandomized)
        siRandomized = makeSolverSide("siRandomized", SolverKind::BulletSIRandomized, *scene, facts.size,
                                      options.iterations, config);
    if (ours && ours->ocl) {
        facts.deviceName = ours->ocl->getDeviceName();
        facts.solvePath = ours->ocl->getSolvePath() == btOpenCLSolvePath::Serial ? "serial" : "wide";
        facts.sortAndScan = ours->ocl->getSortAndScanName();
    }
    const std::vector<SolverSide*> sides = {si.get(), ours.get(), siRandomized.get()};
    const std::vector<SolverSide*> drawn = {si.get(), ours.get()};  // the picture has SI and ours only

    const Clock::time_point start = Clock::now();
    double lastReport = 0;
    for (int step = 0; step <= facts.steps; ++step) {
        if (step > 0)
            for (SolverSide* s : sides)
                if (s) stepSolverSide(*s, options.dt);
        for (SolverSide* s : sides)
            if (s && s->alive) trackQuality(*s, step == facts.driftFromStep, step >= facts.restingFromStep);
        if (si && ours && si->alive && ours->alive) {
            facts.divergenceFinal = maxDistance(dynamicPositions(*si->scene), dynamicPositions(*ours->scene));
            facts.divergenceMax = std::max(facts.divergenceMax, facts.divergenceFinal);
            facts.compared = step > 0;
        }
        if (!options.pngFile.empty() && step == frame) drawFrame(drawn, options.pngFile, frame, facts);
        const double elapsed = secondsSince(start);
        if (step > 0 && elapsed > 2 && elapsed - lastReport > 2) {
            reportProgress(step, facts.steps, si.get(), ours.get(), elapsed);
            lastReport = elapsed;
        }
        const bool anyAlive = std::any_of(sides.begin(), sides.end(), [](const SolverSide* s) { return s && s->alive; });
        if (!anyAlive) break;
    }
    facts.wallSeconds = secondsSince(start);

    const std::string summary = summariseRun(options, facts, si.get(), ours.get(), siRandomized.get());
    std::cout << summary << std::endl;
    if (!options.jsonFile.empty()) {
        std::ofstream out(options.jsonFile);
        out << summary << '\n';
        if (!out) {
            std::fprintf(stderr, "btocl_bench: cannot write %s\n", options.jsonFile.c_str());
            return 1;
        }
    }

    int status = 0;
    if (si && !si->error.empty()) {
        std::fprintf(stderr, "btocl_bench: Bullet's solver side failed: %s\n", si->error.c_str());
        status = 1;
    }
    if (siRandomized && !siRandomized->error.empty()) {
        std::fprintf(stderr, "btocl_bench: Bullet's randomized-order side failed: %s\n", siRandomized->error.c_str());
        status = 1;
    }
    if (ours && !ours->error.empty()) {
        std::fprintf(stderr, "btocl_bench: our solver reported an error%s: %s\n",
                     options.allowOclError ? " (allowed by --allow-ocl-error)" : "", ours->error.c_str());
        if (!options.allowOclError) status = 1;
    }
    if (ours && ours->validationFailures > 0) {
        std::fprintf(stderr, "btocl_bench: %d split/batch invariant failures; first: %s\n", ours->validationFailures,
                     ours->firstValidationFailure.c_str());
        status = 4;
    }
    if (status == 0 && options.maxDivergence >= 0 && facts.divergenceMax > options.maxDivergence) {
        std::fprintf(stderr, "btocl_bench: trajectories parted by %g, more than --max-divergence %g\n",
                     double(facts.divergenceMax), options.maxDivergence);
        status = 3;
    }
    return status;
}

}  // namespace

int main(int argc, char** argv) {
    BenchOptions options;
    try {
        options = parseBenchOptions(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "btocl_bench: %s\nRun btocl_bench --help for the options.\n", e.what());
        return 2;
    }
    if (options.help) {
        std::fputs(benchUsage().c_str(), stdout);
        return 0;
    }
    if (options.listScenes) {
        for (auto& s : allScenes())
            std::printf("%-11s size %5d, %4d steps: %s\n", s.name, s.defaultSize, s.defaultSteps, s.description);
        return 0;
    }
    try {
        return run(options);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "btocl_bench: %s\n", e.what());
        return 1;
    }
}
