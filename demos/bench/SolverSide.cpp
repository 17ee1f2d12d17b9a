#include "SolverSide.h"

#include "Quality.h"

#include <algorithm>
#include <exception>

namespace btbench {

namespace {

// The benchmark's gravity since its first figures (the tests' worlds use 9.81).
constexpr btScalar kGravity = 10;

}  // namespace


std::unique_ptr<SolverSide> makeSolverSide(const std::string& name, SolverKind kind, const SceneInfo& sceneInfo, int size,
                                           int iterations, const btOpenCLSolverConfig& config) {
    auto side = std::make_unique<SolverSide>();
    side->name = name;
    side->kind = kind;
    btConstraintSolver* inner = nullptr;
    try {
        if (kind == SolverKind::OpenCL) {
            side->ocl = std::make_unique<btOpenCLConstraintSolver>(config);
            inner = side->ocl.get();
        } else {  // BulletSI, BulletSIRandomized
            side->si = std::make_unique<CountingSISolver>();
            inner = side->si.get();
        }
    } catch (const std::exception& e) {
        side->error = std::string("constructing the solver: ") + e.what();
        return side;
    }
    side->timed = std::make_unique<TimedSolver>(*inner);
    side->scene = std::make_unique<World>(side->timed.get(), kGravity);
    side->scene->info().m_numIterations = iterations;
    if (kind == SolverKind::BulletSIRandomized) side->scene->info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
    sceneInfo.build(*side->scene, size);
    side->alive = true;
    return side;
}

std::string solverLabel(const SolverSide& side) {
    switch (side.kind) {
        case SolverKind::OpenCL: return "btOpenCLConstraintSolver";
        case SolverKind::BulletSIRandomized: return "Bullet SI, randomized order";
        case SolverKind::BulletSI: break;
    }
    return side.name == "ours" ? "Bullet SI (stand-in for ours)" : "Bullet SI";
}

void stepSolverSide(SolverSide& side, double dt) {
    if (!side.alive) return;
    side.timed->beginStep();
    try {
        side.scene->step(btScalar(dt));  // exactly one internal step of dt, no interpolation
    } catch (const std::exception& e) {
        side.alive = false;
        side.error = "step " + std::to_string(side.stepsDone + 1) + ": " + e.what();
        return;
    }
    side.stepsDone += 1;
    const SolverStepCounts& c = side.timed->step();
    side.msPerStep.push_back(c.ms);
    if (c.contactPoints > 0) side.msPer1000ContactPoints.push_back(c.ms * 1000.0 / c.contactPoints);
    side.lastCounts = c;
    const bool mostContactPoints = c.contactPoints > side.maxContactPoints;
    side.maxContactPoints = std::max(side.maxContactPoints, c.contactPoints);
    if (side.si) {
        side.lastRows = side.si->rowsThisStep();
        side.lastJointRows = side.si->jointRowsThisStep();
        // SI's phases under our phases' names: its set-up, its iterations, its finish.
        PhaseSamples& p = side.phases;
        p.setup.push_back(side.si->msSetup());
        p.solve.push_back(side.si->msIterations());
        p.writeback.push_back(side.si->msFinish());
        p.total.push_back(c.ms);
    }
    if (side.ocl) {
        const btOpenCLSolverStats& s = side.ocl->getLastStats();
        side.lastStats = s;
        side.lastRows = s.numConstraintRows;
        side.lastJointRows = s.numJointRows;
        side.maxDeviceBytes = std::max(side.maxDeviceBytes, s.deviceBytes);
        side.stepsOnHost += s.solvedOnHost ? 1 : 0;
        side.stepsOnHostSplit += s.solvedOnHostSplit ? 1 : 0;
        side.stepsWhole += s.solvedWholeStep ? 1 : 0;
        if (mostContactPoints) side.deviceBytesAtMostContactPoints = s.deviceBytes;
        if (s.validationFailures > 0 && side.validationFailures == 0)
            side.firstValidationFailure = "step " + std::to_string(side.stepsDone) + ": " + s.lastValidationMessage;
        side.validationFailures += s.validationFailures;
        PhaseSamples& p = side.phases;
        p.gather.push_back(s.msGather);
        p.device.push_back(s.msDevice);
        p.upload.push_back(s.msUpload);
        p.setup.push_back(s.msSetup);
        p.split.push_back(s.msSplit);
        p.batch.push_back(s.msBatch);
        p.solve.push_back(s.msSolve);
        p.writeback.push_back(s.msWriteback);
        p.download.push_back(s.msDownload);
        p.total.push_back(s.msTotal);
    }
}

void trackQuality(SolverSide& side, bool setDriftReference, bool inRestingWindow) {
    if (!side.scene) return;
    side.lastMinDistance = minContactDistance(*side.scene);
    side.minDistance = std::min(side.minDistance, side.lastMinDistance);
    side.lastJointError = maxJointError(*side.scene);
    side.maxJointError = std::max(side.maxJointError, side.lastJointError);
    if (setDriftReference) side.driftReference = dynamicPositions(*side.scene);
    if (!side.driftReference.empty())
        side.maxDrift = std::max(side.maxDrift, maxDistance(dynamicPositions(*side.scene), side.driftReference));
    if (inRestingWindow) {
        side.restingEnergySum += kineticEnergy(*side.scene);
        side.restingEnergySamples += 1;
    }
}

}  // namespace btbench
