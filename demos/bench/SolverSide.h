// One side of the side-by-side run: a solver (Bullet's SI or ours), the timing decorator around
// it, the world it steps, and what was measured on it step by step.
#pragma once

#include "CountingSISolver.h"
#include "Scenes.h"
#include "TimedSolver.h"

#include <btOpenCLConstraintSolver.h>

#include <memory>
#include <string>
#include <vector>

namespace btbench {

// BulletSIRandomized: Bullet's solver with SOLVER_RANDMIZE_ORDER, which shuffles the order of its
// rows every iteration (from its own seed, so the same from run to run).
enum class SolverKind { BulletSI, BulletSIRandomized, OpenCL };

// Phases of ours, read from getLastStats() after every step.
struct PhaseSamples {
    std::vector<double> gather, device, upload, setup, split, batch, solve, writeback, download, total;
};

struct SolverSide {
    std::string name;  // "si", "siRandomized" or "ours"
    SolverKind kind = SolverKind::BulletSI;
    std::unique_ptr<CountingSISolver> si;
    std::unique_ptr<btOpenCLConstraintSolver> ocl;
    std::unique_ptr<TimedSolver> timed;
    std::unique_ptr<World> scene;

    bool alive = false;       // false once the solver threw (the world is not stepped again)
    std::string error;        // what it threw, or why it could not be made
    int stepsDone = 0;

    std::vector<double> msPerStep;  // solver wall time of each step
    std::vector<double> msPer1000ContactPoints;  // the same per 1,000 contact points (steps with contacts)
    PhaseSamples phases;
    SolverStepCounts lastCounts;
    int lastRows = 0, lastJointRows = 0, maxContactPoints = 0;
    btOpenCLSolverStats lastStats;
    double maxDeviceBytes = 0;                   // ours: largest deviceBytes of any step
    int stepsOnHost = 0, stepsWhole = 0;          // ours: steps solved on the host, whole on the device
    int stepsOnHostSplit = 0;                     // ours: of those on the host, split (splitStepsOnHost)
    double deviceBytesAtMostContactPoints = 0;   // ours: deviceBytes after the step with the most contact points
    int validationFailures = 0;         // over all steps (with --validate)
    std::string firstValidationFailure;

    // Quality, tracked over the run.
    btScalar minDistance = 0;               // most negative contact distance seen
    btScalar lastMinDistance = 0;           // the same, in the last state tracked
    std::vector<btVector3> driftReference;  // positions at the drift reference step
    btScalar maxDrift = 0;
    btScalar maxJointError = -1;            // largest joint pivot gap seen (-1: no such joint)
    btScalar lastJointError = -1;           // the same, in the last state tracked
    double restingEnergySum = 0;            // kinetic energy summed over the states of the resting window
    int restingEnergySamples = 0;
};

// Builds the solver and the scene's world around it. A solver that cannot be made (no OpenCL
// device, kernel build failure) leaves the side not alive with the reason in `error`.
std::unique_ptr<SolverSide> makeSolverSide(const std::string& name, SolverKind kind, const SceneInfo& scene, int size,
                                           int iterations, const btOpenCLSolverConfig& config);

// The side's solver as a picture labels its panel: "Bullet SI", "btOpenCLConstraintSolver", or
// "Bullet SI, randomized order"; Bullet's solver standing in for ours (--stand-in) says so.
std::string solverLabel(const SolverSide& side);

// One world step of dt; records the timings and counts. Catches what the solver throws.
void stepSolverSide(SolverSide& side, double dt);

// Quality bookkeeping after a step: penetration, joint error, drift from the reference once set,
// and the kinetic energy of the states in the resting window (the run's last quarter).
void trackQuality(SolverSide& side, bool setDriftReference, bool inRestingWindow);

}  // namespace btbench
