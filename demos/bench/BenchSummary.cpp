#include "BenchSummary.h"

#include "Percentiles.h"
#include "Quality.h"

namespace btbench {

namespace {

// A box of a standing stack settles by millimetres (penetration slop, compression of the
// contacts below it); a box of a toppled stack moves by its own size. A quarter of a unit box
// (and half a brick's height) separates the two with a wide margin either way.
const btScalar kStandingDrift = 0.25f;

JsonValue timing(const std::vector<double>& ms) {
    JsonValue t = JsonValue::object();
    t["median"] = quantile(ms, 0.5);
    t["p90"] = quantile(ms, 0.9);
    t["mean"] = mean(ms);
    t["first"] = ms.empty() ? JsonValue() : JsonValue(ms.front());  // includes one-off set-up
    return t;
}

JsonValue quality(const SolverSide& side, const RunFacts& facts) {
    JsonValue q = JsonValue::object();
    q["maxPenetration"] = double(-side.minDistance);  // over the run, impacts included
    q["finalPenetration"] = double(-side.lastMinDistance);
    q["maxDrift"] = double(side.maxDrift);
    q["driftFromStep"] = facts.driftFromStep;
    q["kineticEnergy"] = side.scene ? JsonValue(kineticEnergy(*side.scene)) : JsonValue();
    q["topCentreHeight"] = side.scene ? JsonValue(double(maxCentreHeight(*side.scene))) : JsonValue();
    // Only scenes whose boxes start at rest have stacks that should stand.
    q["stacksStanding"] = facts.scene->startsAtRest && side.stepsDone > 0 ? JsonValue(side.maxDrift < kStandingDrift)
                                                                          : JsonValue();
    return q;
}

JsonValue sideJson(const SolverSide& side, const RunFacts& facts) {
    JsonValue s = JsonValue::object();
    s["solver"] = side.kind == SolverKind::OpenCL ? "btOpenCLConstraintSolver" : "btSequentialImpulseConstraintSolver";
    s["error"] = side.error.empty() ? JsonValue() : JsonValue(side.error);
    s["stepsDone"] = side.stepsDone;
    s["msPerStep"] = timing(side.msPerStep);
    s["contactPoints"] = side.lastCounts.contactPoints;
    s["contactPointsMax"] = side.maxContactPoints;
    s["manifolds"] = side.lastCounts.manifolds;
    s["constraintRows"] = side.lastRows;
    s["solveGroupCalls"] = side.lastCounts.groupCalls;
    if (side.kind == SolverKind::OpenCL && side.ocl) {
        const btOpenCLSolverStats& st = side.lastStats;
        s["groups"] = st.numCellGroups;
        s["batchesMax"] = st.numBatchesMax;
        s["batchesMean"] = st.numBatchesMean;
        s["overflowConstraints"] = st.numOverflowConstraints;
        s["validationFailures"] = side.validationFailures;
        if (!st.lastValidationMessage.empty()) s["validationMessage"] = st.lastValidationMessage;
        // getLastStats() of every step: median and 90th percentile of each phase.
        JsonValue medians = JsonValue::object(), p90s = JsonValue::object();
        const PhaseSamples& p = side.phases;
        const std::pair<const char*, const std::vector<double>*> named[] = {
            {"gather", &p.gather}, {"upload", &p.upload}, {"setup", &p.setup},         {"split", &p.split},
            {"batch", &p.batch},   {"solve", &p.solve},   {"writeback", &p.writeback}, {"download", &p.download},
            {"total", &p.total}};
        for (const auto& [name, samples] : named) {
            medians[name] = quantile(*samples, 0.5);
            p90s[name] = quantile(*samples, 0.9);
        }
        s["phasesMsMedian"] = medians;
        s["phasesMsP90"] = p90s;
    }
    s["quality"] = side.stepsDone > 0 ? quality(side, facts) : JsonValue();  // nothing to judge
    return s;
}

}  // namespace

JsonValue summariseRun(const BenchOptions& options, const RunFacts& facts, const SolverSide* si, const SolverSide* ours) {
    JsonValue j = JsonValue::object();
    j["scene"] = facts.scene->name;
    j["description"] = facts.scene->description;
    j["size"] = facts.size;
    j["steps"] = facts.steps;
    j["iterations"] = options.iterations;
    j["dt"] = options.dt;
    const SolverSide* any = si && si->scene ? si : ours;
    j["bodies"] = any && any->scene ? JsonValue(any->scene->numDynamicBodies()) : JsonValue();
    j["contactPoints"] = any ? JsonValue(any->lastCounts.contactPoints) : JsonValue();
    j["device"] = facts.deviceName.empty() ? JsonValue() : JsonValue(facts.deviceName);
    if (options.standIn) j["standIn"] = "ours is a second btSequentialImpulseConstraintSolver (--stand-in)";
    if (si) j["si"] = sideJson(*si, facts);
    if (ours) j["ours"] = sideJson(*ours, facts);
    if (si && ours && !si->msPerStep.empty() && !ours->msPerStep.empty())
        j["ratioOursOverSi"] = quantile(ours->msPerStep, 0.5) / quantile(si->msPerStep, 0.5);
    else
        j["ratioOursOverSi"] = JsonValue();
    if (facts.compared) {
        JsonValue d = JsonValue::object();
        d["final"] = double(facts.divergenceFinal);
        d["max"] = double(facts.divergenceMax);
        j["trajectoryDivergence"] = d;
    }
    if (!facts.pngFile.empty()) {
        JsonValue png = JsonValue::object();
        png["file"] = facts.pngFile;
        png["frame"] = facts.pngFrame;
        JsonValue panels = JsonValue::array();
        for (const std::string& name : facts.pngPanels) panels.push(name);
        png["panelsLeftToRight"] = panels;
        j["png"] = png;
    }
    j["wallSeconds"] = facts.wallSeconds;
    return j;
}

}  // namespace btbench
