// Every choice of how a step is solved, in one place: per solver, the path and what follows from
// it (planSolver); per step, the launch mode and the passes (planStep).
#pragma once

#include "DevicePrimitives.h"
#include "OclRuntime.h"
#include "StepPlan.h"
#include "btOpenCLConstraintSolver.h"

#include <algorithm>

namespace btocl {

// Where a split step that a claimed launch would solve runs (btOpenCLSolverConfig::splitStepsOnHost).
enum class SplitStepsOnHost { Never, Timed, Always };

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
    // rows allow (LaneLayout.h); 1: one group a work-item. Chosen automatically, the lanes take a
    // step only where its layout fills them (StepPipeline::solveOnDevice); asked for, always.
    int simdLanes = 1;
    bool lanesWhereTheyFill = false;
    // Such a claimed step solved on the calling thread instead (StepPlan::onHostSplit), to the
    // same bits on a CPU device: never, always, or as the recent steps' times say.
    SplitStepsOnHost splitStepsOnHost = SplitStepsOnHost::Never;
    bool wide() const { return path == btOpenCLSolvePath::Wide; }
};

// The path asked for (or BT_OPENCL_SOLVE_PATH's, or the device type's) and its lanes, sort and
// scan; the steps solved on the host. Throws btOpenCLSolverError for an unknown
// BT_OPENCL_SOLVE_PATH or BT_OPENCL_HOST_STEPS.
SolverPlan planSolver(const btOpenCLSolverConfig& config, const OclRuntime& runtime);

// Two ways of solving a kind of step to the same bits, taken where the recent steps ran faster,
// by the mean time a row of the last kWindow steps each way ran. The mean counts the worst steps:
// another process busy on a core stalls a step that waits on work of that core's thread until it
// runs again (docs/performance.md, "Split steps on the host"). Each way is timed first for
// kFirstSteps steps by turns (a way's first step, which sizes its arrays, not counted); the way
// not taken is then tried every kFirstTry steps, less often while it loses (up to kLastTry), a
// try's time standing for that way's window (its older times may be of another scene, a growing
// pile's), and timed afresh every kRetime steps, so that the choice follows a load that comes and
// goes. No result depends on it: both ways give the same bits.
// Its uses: a split step on the device's claimed launch (first) or the calling thread (second;
// SplitStepsOnHost::Timed, tests/test_host_step.cpp); a host step in lanes on the calling thread
// alone (first) or shared out to the host's threads (second; HostLaneSolve, tests/test_lanes.cpp).
class StepWayTimes {
public:
    static constexpr int kWindow = 16, kFirstSteps = 3, kFirstTry = 32, kLastTry = 256, kRetime = 512;

    // secondFirst: the way taken as the faster before any is timed.
    explicit StepWayTimes(bool secondFirst = false) : m_second(secondFirst) {}

    // Whether the next step takes the second way: the faster so far, or the other on its turn to be tried.
    bool nextIsSecond();
    // The way taken as the faster so far (true: the second), with no turn to be tried.
    bool prefersSecond() const { return m_second; }
    // The time of the step that nextIsSecond placed, over its rows.
    void record(bool second, double ms, int rows);

private:
    struct Way {
        double msPerRow[kWindow] = {};
        bool ran = false;  // a step has run this way (its first, which sizes its arrays, is not timed)
        int count = 0;     // times kept since the way was last timed afresh
        void add(double value) { msPerRow[count++ % kWindow] = value; }
        void fill(double value) {
            for (double& v : msPerRow) v = value;
            count = std::max(count, int(kWindow));
        }
        double mean() const;
    };
    Way m_ways[2];  // [0] the first way, [1] the second
    bool m_second, m_trying = false;
    int m_sinceTry = 0, m_tryEvery = kFirstTry, m_sinceRetime = 0;
};
// Where split steps ran faster of late: the device (first) or the host (second).
using SplitStepTimes = StepWayTimes;

// How this step runs: on the host where a device launch would cost more than the step's work;
// whole in one launch where the split would cost more than it saves; else split and launched as
// the path does, or split on the host and solved there (solver.splitStepsOnHost; with `times`
// where Timed). And its passes.
StepPlan planStep(const SolverPlan& solver, const StepProblem& p, const SolveSettings& settings,
                  SplitStepTimes* times = nullptr);

// The lanes a solver on `runtime` asks for (config.simdLanes, or BT_OPENCL_SIMD_LANES): 1 on a
// device that is not a CPU; where neither asks, 8 on a CPU device in the host's memory whose host
// has AVX2 (the host sets the lanes' rows up), else 1, and *automatic says so. Throws
// btOpenCLSolverError for a width other than 1, 4, 8 or 16.
int resolveSimdLanes(int asked, const OclRuntime& runtime, bool* automatic = nullptr);
// Whether the host sets a lane layout of `lanes` up for the device (setUpLaneRows): eight lanes,
// the CPU's AVX2, a device in the host's memory that reads the host's arrays in place.
bool hostSetsUpLaneRows(int lanes, const OclRuntime& runtime);

// Whether a step's rows can be solved in lanes (LaneLayout.h): contact rows alone, set up from
// the points, in passes that pair (StepPolicy.cpp).
bool stepFitsLanes(const StepProblem& p, const SolveSettings& settings, const btoclPassSchedule& passes);
// The same, or joints' rows beside such contact rows, where the joints take no iteration past the
// contacts': the host's lanes (HostLaneSolve), given a split whose groups lead with their contacts.
bool stepFitsHostLanes(const StepProblem& p, const SolveSettings& settings, const btoclPassSchedule& passes);

// Whether a step split as `step` says is split on the host (HostSplit.h) rather than the device.
bool splitsOnHost(const SolverPlan& solver, const StepProblem& p, const StepPlan& step);

}  // namespace btocl
