#include "BenchSummary.h"

#include "Percentiles.h"
#include "Quality.h"

#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <cstdint>

namespace btbench {

namespace {

// Keys stay in the order they are set, so the summary reads top to bottom.
using Json = nlohmann::ordered_json;

// A box of a standing stack settles by millimetres (penetration slop, compression of the
// contacts below it); a box of a toppled stack moves by its own size. A quarter of a unit box
// (and half a brick's height) separates the two with a wide margin either way.
const btScalar kStandingDrift = 0.25f;

// The worst steps are taken after the first few, which include one-off set-up (first touch of
// fresh memory, kernels a run meets for the first time): a game feels them once, at load.
constexpr size_t kTailFromStep = 5;

Json timing(const std::vector<double>& ms) {
    Json t = Json::object();
    t["median"] = quantile(ms, 0.5);
    t["p90"] = quantile(ms, 0.9);
    const std::vector<double> later(ms.begin() + long(std::min(kTailFromStep, ms.size())), ms.end());
    t["p99"] = later.empty() ? Json() : Json(quantile(later, 0.99));
    t["max"] = later.empty() ? Json() : Json(quantile(later, 1.0));
    t["tailFromStep"] = kTailFromStep;
    t["mean"] = mean(ms);
    t["first"] = ms.empty() ? Json() : Json(ms.front());  // includes one-off set-up
    return t;
}

Json quality(const SolverSide& side, const RunFacts& facts) {
    Json q = Json::object();
    q["maxPenetration"] = double(-side.minDistance);  // over the run, impacts included
    q["finalPenetration"] = double(-side.lastMinDistance);
    // Joints that hold two points together: how far apart the two came (null without such joints).
    q["maxJointError"] = side.maxJointError >= 0 ? Json(double(side.maxJointError)) : Json();
    q["finalJointError"] = side.lastJointError >= 0 ? Json(double(side.lastJointError)) : Json();
    q["maxDrift"] = double(side.maxDrift);
    q["driftFromStep"] = facts.driftFromStep;
    q["kineticEnergy"] = side.scene ? Json(kineticEnergy(*side.scene)) : Json();  // the last state only
    // The mean over the states of the run's last quarter: the last state alone is one sample of
    // a jitter that swings by orders of magnitude from step to step in a resting stack.
    q["restingKineticEnergy"] =
        side.restingEnergySamples > 0 ? Json(side.restingEnergySum / side.restingEnergySamples) : Json();
    q["restingFromStep"] = facts.restingFromStep;
    q["topCentreHeight"] = side.scene ? Json(double(maxCentreHeight(*side.scene))) : Json();
    // Only scenes whose boxes start at rest have stacks that should stand.
    q["stacksStanding"] = facts.scene->startsAtRest && side.stepsDone > 0 ? Json(side.maxDrift < kStandingDrift)
                                                                          : Json();
    return q;
}

Json sideJson(const SolverSide& side, const RunFacts& facts) {
    Json s = Json::object();
    s["solver"] = side.kind == SolverKind::OpenCL ? "btOpenCLConstraintSolver" : "btSequentialImpulseConstraintSolver";
    // The Gauss-Seidel order: fixed, randomized (SOLVER_RANDMIZE_ORDER, either solver) or, ours, rotated.
    const bool randomized = side.scene && (side.scene->info().m_solverMode & SOLVER_RANDMIZE_ORDER);
    s["order"] = randomized ? "randomized" : side.ocl && side.ocl->getConfig().rotatePoints ? "rotated" : "fixed";
    s["error"] = side.error.empty() ? Json() : Json(side.error);
    s["stepsDone"] = side.stepsDone;
    s["msPerStep"] = timing(side.msPerStep);
    // Median over the steps with contacts of the step's time per 1,000 contact points.
    s["msPer1000ContactPoints"] = quantile(side.msPer1000ContactPoints, 0.5);
    s["contactPoints"] = side.lastCounts.contactPoints;
    s["contactPointsMax"] = side.maxContactPoints;
    s["manifolds"] = side.lastCounts.manifolds;
    s["constraintRows"] = side.lastRows;
    s["jointRows"] = side.lastJointRows;
    s["solveGroupCalls"] = side.lastCounts.groupCalls;
    if (side.kind == SolverKind::OpenCL && side.ocl) {
        const btOpenCLSolverStats& st = side.lastStats;
        s["groups"] = st.numCellGroups;
        s["stepsOnHost"] = side.stepsOnHost;
        s["stepsOnHostSplit"] = side.stepsOnHostSplit;
        s["stepsWholeOnDevice"] = side.stepsWhole;
        s["batchesMax"] = st.numBatchesMax;
        s["batchesMean"] = st.numBatchesMean;
        s["overflowConstraints"] = st.numOverflowConstraints;
        // The last step's lanes (simdLanes): W (0: none), and how full its slots' lanes and row blocks were.
        s["simdLanes"] = st.simdLanes;
        s["laneFill"] = st.laneFill;
        s["laneRowFill"] = st.laneRowFill;
        s["validationFailures"] = side.validationFailures;
        // Device memory held by our buffers: the most over the run, and per contact point after
        // the step with the most contact points.
        s["deviceBytes"] = int64_t(side.maxDeviceBytes);
        s["deviceBytesPerContactPoint"] =
            side.maxContactPoints > 0 ? Json(side.deviceBytesAtMostContactPoints / side.maxContactPoints) : Json();
        if (!st.lastValidationMessage.empty()) s["validationMessage"] = st.lastValidationMessage;
        // getLastStats() of every step: median and 90th percentile of each phase.
        Json medians = Json::object(), p90s = Json::object();
        const PhaseSamples& p = side.phases;
        const std::pair<const char*, const std::vector<double>*> named[] = {
            {"gather", &p.gather}, {"device", &p.device}, {"upload", &p.upload}, {"setup", &p.setup},         {"split", &p.split},
            {"batch", &p.batch},   {"solve", &p.solve},   {"writeback", &p.writeback}, {"download", &p.download},
            {"total", &p.total}};
        for (const auto& [name, samples] : named) {
            medians[name] = quantile(*samples, 0.5);
            p90s[name] = quantile(*samples, 0.9);
        }
        s["phasesMsMedian"] = medians;
        s["phasesMsP90"] = p90s;
    } else if (side.si && !side.phases.total.empty()) {
        // Bullet's phases: set-up (its rows, the warm start), solve (its iterations), writeback
        // (its finish), total (the timed share of the step, as ours).
        const PhaseSamples& p = side.phases;
        s["phasesMsMedian"] = {{"setup", quantile(p.setup, 0.5)}, {"solve", quantile(p.solve, 0.5)},
                               {"writeback", quantile(p.writeback, 0.5)}, {"total", quantile(p.total, 0.5)}};
    }
    s["quality"] = side.stepsDone > 0 ? quality(side, facts) : Json();  // nothing to judge
    return s;
}

}  // namespace

std::string summariseRun(const BenchOptions& options, const RunFacts& facts, const SolverSide* si,
                         const SolverSide* ours, const SolverSide* siRandomized) {
    Json j = Json::object();
    j["scene"] = facts.scene->name;
    j["description"] = facts.scene->description;
    j["size"] = facts.size;
    j["steps"] = facts.steps;
    j["iterations"] = options.iterations;
    j["dt"] = options.dt;
    const SolverSide* any = si && si->scene ? si : ours;
    j["bodies"] = any && any->scene ? Json(any->scene->numDynamicBodies()) : Json();
    j["joints"] = any && any->scene ? Json(any->scene->constraints().size()) : Json();
    j["contactPoints"] = any ? Json(any->lastCounts.contactPoints) : Json();
    j["device"] = facts.deviceName.empty() ? Json() : Json(facts.deviceName);
    j["solvePath"] = facts.solvePath.empty() ? Json() : Json(facts.solvePath);
    j["sortAndScan"] = facts.sortAndScan.empty() ? Json() : Json(facts.sortAndScan);
    if (options.standIn) j["standIn"] = "ours is a second btSequentialImpulseConstraintSolver (--stand-in)";
    if (si) j["si"] = sideJson(*si, facts);
    if (ours) j["ours"] = sideJson(*ours, facts);
    if (siRandomized) j["siRandomized"] = sideJson(*siRandomized, facts);
    if (si && ours && !si->msPerStep.empty() && !ours->msPerStep.empty())
        j["ratioOursOverSi"] = quantile(ours->msPerStep, 0.5) / quantile(si->msPerStep, 0.5);
    else
        j["ratioOursOverSi"] = Json();
    if (facts.compared) {
        Json d = Json::object();
        d["final"] = double(facts.divergenceFinal);
        d["max"] = double(facts.divergenceMax);
        j["trajectoryDivergence"] = d;
    }
    if (!facts.pngFile.empty()) {
        Json png = Json::object();
        png["file"] = facts.pngFile;
        png["frame"] = facts.pngFrame;
        png["panelsLeftToRight"] = facts.pngPanels;
        j["png"] = png;
    }
    j["wallSeconds"] = facts.wallSeconds;
    // The process's peak resident memory (getrusage's ru_maxrss): every world of the run shares
    // the process, so run one solver alone (--solver si or ocl) to attribute it.
    rusage usage{};
    j["peakRssBytes"] = getrusage(RUSAGE_SELF, &usage) == 0 ? Json(int64_t(usage.ru_maxrss) * 1024) : Json();
    // NaN (a quantile of no samples) comes out as null. Bytes that are not UTF-8 (a driver's
    // error message) are replaced rather than thrown on.
    return j.dump(2, ' ', false, Json::error_handler_t::replace);
}

}  // namespace btbench
