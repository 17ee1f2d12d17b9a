// Every choice of how a step is solved, in one place: per solver, the path and what follows from
// it (planSolver); per step, the launch mode and the passes (planStep).
#pragma once

#include "DevicePrimitives.h"
#include "OclRuntime.h"
#include "StepPlan.h"
#include "btOpenCLConstraintSolver.h"

namespace btocl {

// What a solver fixes when it is made.
struct SolverPlan {
    btOpenCLSolvePath path = btOpenCLSolvePath::Serial;  // never Auto
    GroupLanes lanes;
    DevicePrimitives::Backend sortAndScan = DevicePrimitives::Backend::Chunked;
    int wholeStepMaxRows = -1;           // the config's: -1 automatic, 0 never, n: steps of at most n rows
    double autoWholeStepMaxRows = 0;     // serial path, automatic: by the device's compute units
    long long hostStepMaxRows = -1;      // steps of at most this many rows on the host; -1: none
    // The claimed launch's work-groups read what the others wrote through plain loads: a CPU's
    // caches keep them coherent, a GPU's need not (docs/performance.md, "On a GPU").
    bool claimedLaunch = true;
    // The serial path on a CPU device splits steps of at most this many constraints on the host
    // (HostSplit.h): the device's split is a dozen launches, each a fixed cost on PoCL, for work
    // the host does in less; past it the device's split, on every core, is faster. 0: never.
    size_t hostSplitMaxConstraints = 0;
    // Split steps' groups solved this many at a time in the vector unit's lanes where the step's
    // rows allow (LaneLayout.h); 1: one group a work-item.
    int simdLanes = 1;
    bool wide() const { return path == btOpenCLSolvePath::Wide; }
};

// The path asked for (or BT_OPENCL_SOLVE_PATH's, or the device type's) and its lanes, sort and
// scan; the steps solved on the host. Throws btOpenCLSolverError for an unknown
// BT_OPENCL_SOLVE_PATH or BT_OPENCL_HOST_STEPS.
SolverPlan planSolver(const btOpenCLSolverConfig& config, const OclRuntime& runtime);

// How this step runs: on the host where a device launch would cost more than the step's work;
// whole in one launch where the split would cost more than it saves; else split and launched as
// the path does. And its passes.
StepPlan planStep(const SolverPlan& solver, const StepProblem& p, const SolveSettings& settings);

// The lanes a solver on `runtime` asks for (config.simdLanes, or BT_OPENCL_SIMD_LANES): 1 on a
// device that is not a CPU, and where neither asks. Throws btOpenCLSolverError for a width other
// than 1, 4, 8 or 16.
int resolveSimdLanes(int asked, const OclRuntime& runtime);

// Whether a step split as `step` says is split on the host (HostSplit.h) rather than the device.
bool splitsOnHost(const SolverPlan& solver, const StepProblem& p, const StepPlan& step);

}  // namespace btocl
