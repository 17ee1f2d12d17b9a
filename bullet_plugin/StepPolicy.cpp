#include "StepPolicy.h"

#include "HostLaneSolve.h"

#include "LaneLayout.h"
#include "row_solve.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>

namespace btocl {
namespace {

// When a step runs whole in one launch of one work-group (no global split, no sets): when the
// split and the sets' groups solved side by side would save less than they cost.
// - Wide path (a GPU's): at most 1,024 constraints, a few batches of one work-group's lanes.
// - Serial path (a CPU's, one work-item per group): the split spreads the solve over the compute
//   units in one claimed launch. Split on the host, it won over the whole step from the host
//   steps' bound on (docs/performance.md): a whole step only on one unit. Split on the device
//   (a GPU's serial path), the crossover measured on PoCL, about 30K rows on 2 units, falls as
//   units are added, so the whole step takes at most 16K x units / (units - 1) rows.
constexpr int kWholeStepMaxConstraintsWide = 1024;
constexpr double kWholeStepRowsPerUnitShare = 16384;

double wholeStepMaxRowsSerial(const OclRuntime& runtime, bool splitOnHost) {
    const double units = double(runtime.computeUnits());
    if (units <= 1) return std::numeric_limits<double>::infinity();
    if (splitOnHost) return 0;
    return kWholeStepRowsPerUnitShare * units / (units - 1);
}

// The host's split against the device's on PoCL: the host's costs a constraint more, the
// device's a fixed sum of launches (docs/performance.md, "The split on the host").
constexpr size_t kHostSplitMaxConstraints = 16384;

// Steps of at most this many rows are solved on the host when the solver decides (measured
// against the device's whole and split steps, docs/performance.md). A CPU device solves on the
// host's own cores, so it wins early; a GPU pays more a launch and runs a whole step in one
// work-group's lanes (docs/performance.md, "On a GPU").
constexpr long long kHostStepMaxRowsCpu = 3584;
constexpr long long kHostStepMaxRowsGpu = 16384;

long long resolveHostStepMaxRows(int asked, const OclRuntime& runtime) {
    constexpr long long never = -1, always = std::numeric_limits<long long>::max();
    if (asked == 0) return never;
    if (asked > 0) return asked;
    if (const char* env = std::getenv("BT_OPENCL_HOST_STEPS"); env && *env) {
        const std::string value = lowerCase(env);
        if (value == "never") return never;
        if (value == "always") return always;
        if (value != "auto")
            throw btOpenCLSolverError("btOpenCLConstraintSolver: BT_OPENCL_HOST_STEPS is '" + std::string(env) +
                                      "'; it takes auto, never or always");
    }
    return runtime.isCpu() ? kHostStepMaxRowsCpu : kHostStepMaxRowsGpu;
}

// Timed where the device's claimed launch and the host give the same bits (a CPU device, whose
// program contracts no multiply-add: docs/architecture.md) and host steps are not switched off.
SplitStepsOnHost resolveSplitStepsOnHost(int asked, long long hostStepMaxRows, bool claimedLaunch,
                                         const OclRuntime& runtime) {
    if (asked == 0 || !claimedLaunch) return SplitStepsOnHost::Never;
    if (asked == 1) return SplitStepsOnHost::Always;
    return runtime.isCpu() && hostStepMaxRows >= 0 ? SplitStepsOnHost::Timed : SplitStepsOnHost::Never;
}

btOpenCLSolvePath resolveSolvePath(btOpenCLSolvePath asked, const OclRuntime& runtime) {
    if (asked != btOpenCLSolvePath::Auto) return asked;
    if (const char* env = std::getenv("BT_OPENCL_SOLVE_PATH"); env && *env) {
        const std::string value = env, key = lowerCase(value);
        if (key == "serial") return btOpenCLSolvePath::Serial;
        if (key == "wide") return btOpenCLSolvePath::Wide;
        if (key != "auto")
            throw btOpenCLSolverError("btOpenCLConstraintSolver: BT_OPENCL_SOLVE_PATH is '" + value +
                                      "'; it takes auto, serial or wide");
    }
    return runtime.isCpu() ? btOpenCLSolvePath::Serial : btOpenCLSolvePath::Wide;
}

}  // namespace

namespace {

// Contact rows as the lanes solve them (kernels/lane_solve.h, HostLaneSolve.h): each point's
// friction rows after its normal row's, no rolling rows, set up from the points, every body's
// angular change kept scaled (the rows' 13 floats: BTOCL_LANE_ROW_FLOATS), in a pass order
// the lanes keep (each group's constraints go through the lanes in its order, each as
// btoclSolveConstraint solves it in passes that pair: btoclPassPairs), and the contacts'
// iterations all there are.
bool contactsFitLanes(const StepProblem& p, const SolveSettings& settings, const btoclPassSchedule& passes) {
    return p.rowsOnDevice && p.unscaledBodies == 0 && contactRowsFitLanes(p.regions, p.frictionRowsPerPoint()) &&
           passes.maxIterations == passes.numIterations &&
           btoclPassPairs(BTOCL_PASS_NORMAL, settings.flags, 0, passes.numIterations);
}

}  // namespace

// The lanes solve every row of a step: contact rows alone.
bool stepFitsLanes(const StepProblem& p, const SolveSettings& settings, const btoclPassSchedule& passes) {
    return p.rows.empty() && rowsFitLanes(p.regions, p.frictionRowsPerPoint()) && contactsFitLanes(p, settings, passes);
}

// The host's lanes also take a step whose joints' rows the gather set up (p.rows: theirs alone)
// beside its contacts, each set's joints after its contacts in lanes of their own (HostLaneSolve).
bool stepFitsHostLanes(const StepProblem& p, const SolveSettings& settings, const btoclPassSchedule& passes) {
    return p.rows.size() == size_t(p.numJointRows()) && (p.rows.empty() || p.numContactPoints() > 0) &&
           contactsFitLanes(p, settings, passes);
}

int resolveSimdLanes(int asked, const OclRuntime& runtime, bool* automatic) {
    if (automatic) *automatic = false;
    if (asked < 0) {
        if (const char* env = std::getenv("BT_OPENCL_SIMD_LANES"); env && *env) {
            const std::string value = lowerCase(env);
            if (value != "auto") {
                char* end = nullptr;
                const long lanes = std::strtol(value.c_str(), &end, 10);
                if (end == value.c_str() || *end != '\0')
                    throw btOpenCLSolverError("btOpenCLConstraintSolver: BT_OPENCL_SIMD_LANES is '" +
                                              std::string(env) + "'; it takes auto, 1, 4, 8 or 16");
                asked = int(lanes);
            }
        }
    }
    if (asked >= 0 && asked != 1 && asked != 4 && asked != 8 && asked != 16)
        throw btOpenCLSolverError("btOpenCLConstraintSolver: simdLanes is " + std::to_string(asked) +
                                  "; it takes -1 (automatic), 1, 4, 8 or 16");
    if (!runtime.isCpu()) return 1;  // a GPU's lanes are the wide path's work-items
    if (asked > 0) return asked;
    if (automatic) *automatic = true;
    // Automatic: eight where the host sets their rows up in the CPU's vector unit and hands them
    // over in place (AVX2, a device in the host's memory: StepPipeline::solveInLanes); elsewhere
    // one group a work-item, the lanes' faster solve being given back in the setup kernel
    // (docs/performance.md, "Lanes").
    return hostSetsUpLaneRows(HostLaneSolve::kLanes, runtime) ? HostLaneSolve::kLanes : 1;
}

bool hostSetsUpLaneRows(int lanes, const OclRuntime& runtime) {
    return lanes == HostLaneSolve::kLanes && HostLaneSolve::available() && runtime.hostUnifiedMemory();
}

SolverPlan planSolver(const btOpenCLSolverConfig& config, const OclRuntime& runtime) {
    using Backend = DevicePrimitives::Backend;
    SolverPlan plan;
    plan.path = resolveSolvePath(config.solvePath, runtime);
    plan.lanes = plan.wide() ? GroupLanes::wide(config.workGroupSize) : GroupLanes::serial();
    // The serial path sorts and scans with our chunked kernels. The wide path takes on a GPU the
    // faster of the two there, measured (DevicePrimitives::fasterBackend), and on a CPU device,
    // which runs it for the tests, Boost.Compute's, so that they cover what a GPU may get.
    plan.sortAndScan = !plan.wide() ? Backend::Chunked : runtime.isCpu() ? Backend::BoostCompute : Backend::Auto;
    plan.wholeStepMaxRows = config.wholeStepMaxRows;
    plan.hostStepMaxRows = resolveHostStepMaxRows(config.hostStepMaxRows, runtime);
    plan.claimedLaunch = runtime.isCpu();
    plan.hostSplitMaxConstraints = runtime.isCpu() && !plan.wide() ? kHostSplitMaxConstraints : 0;
    plan.autoWholeStepMaxRows = wholeStepMaxRowsSerial(runtime, plan.hostSplitMaxConstraints > 0);
    bool automaticLanes = false;
    const int simdLanes = resolveSimdLanes(config.simdLanes, runtime, &automaticLanes);  // checked on every path
    plan.simdLanes = !plan.wide() && plan.claimedLaunch ? simdLanes : 1;
    plan.lanesWhereTheyFill = automaticLanes;
    plan.splitStepsOnHost = resolveSplitStepsOnHost(config.splitStepsOnHost, plan.hostStepMaxRows,
                                                    plan.claimedLaunch && !plan.wide(), runtime);
    return plan;
}

bool StepWayTimes::nextIsSecond() {
    m_trying = false;
    if (++m_sinceRetime >= kRetime) {  // the way not taken timed afresh: its old times may be stale
        m_ways[!m_second].count = 0;
        m_sinceRetime = 0;
    }
    // Each way timed a few steps first, by turns.
    if (std::min(m_ways[0].count, m_ways[1].count) < kFirstSteps) return m_ways[1].count < m_ways[0].count;
    m_trying = ++m_sinceTry >= m_tryEvery;
    return m_trying != m_second;
}

double StepWayTimes::Way::mean() const {
    const int n = std::min(count, kWindow);
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += msPerRow[i];
    return n > 0 ? sum / n : 0;
}

void StepWayTimes::record(bool second, double ms, int rows) {
    Way& way = m_ways[second];
    if (!way.ran) {  // a way's first step sets its arrays up: not its pace
        way.ran = true;
        return;
    }
    // A tried way's times from before (steps ago: the scene has grown or settled since) are left
    // out: the try alone stands for it.
    if (m_trying)
        way.fill(ms / std::max(1, rows));
    else
        way.add(ms / std::max(1, rows));
    const Way& other = m_ways[!second];
    if (std::min(way.count, other.count) < kFirstSteps) return;
    const bool faster = way.mean() < other.mean() ? second : !second;
    if (m_trying) {  // the way not taken, tried: tried less often while it loses
        m_sinceTry = 0;
        m_tryEvery = faster == m_second ? std::min(2 * m_tryEvery, kLastTry) : kFirstTry;
    } else if (faster != m_second) {
        m_sinceTry = 0;
        m_tryEvery = kFirstTry;
    }
    m_second = faster;
    m_trying = false;
}

StepPlan planStep(const SolverPlan& solver, const StepProblem& p, const SolveSettings& settings,
                  SplitStepTimes* times) {
    const btoclPassSchedule passes = passScheduleOf(settings, p);
    if (p.numRows() <= solver.hostStepMaxRows) return StepPlan::onHost(passes);
    const bool whole = solver.wholeStepMaxRows >= 0 ? p.numRows() <= solver.wholeStepMaxRows
                       : solver.wide()             ? int(p.constraints.size()) <= kWholeStepMaxConstraintsWide
                                                   : double(p.numRows()) <= solver.autoWholeStepMaxRows;
    if (whole) return StepPlan::wholeStep(solver.lanes, passes);
    // A split step on the serial path runs in one claimed launch on a CPU (the per-set launches,
    // about a hundred a step, each cost PoCL more than a small group's work; docs/performance.md);
    // the wide path, and the serial path on a GPU, launch once per set and pass.
    if (solver.wide() || !solver.claimedLaunch) return StepPlan::perSet(solver.lanes, passes);
    const StepPlan claimed = StepPlan::claimed(passes);
    const StepPlan device = solver.simdLanes > 1 && stepFitsLanes(p, settings, passes)
                                ? StepPlan::claimedInLanes(passes, solver.simdLanes)
                                : claimed;
    // The host walks the host's split alone (the device's, past hostSplitMaxConstraints, is
    // another layout; the lanes' layout is the host's split's, at any size).
    if (solver.splitStepsOnHost == SplitStepsOnHost::Never || !splitsOnHost(solver, p, device)) return device;
    if (solver.splitStepsOnHost == SplitStepsOnHost::Always) return StepPlan::onHostSplit(passes);
    if (!times) return device;
    return (times->nextIsSecond() ? StepPlan::onHostSplit(passes) : device).asTimed();
}

bool splitsOnHost(const SolverPlan& solver, const StepProblem& p, const StepPlan& step) {
    // The lane layout is the host's, from the host's split; a split step on the host splits there.
    if (step.inLanes() || step.mode() == StepMode::HostSplit) return true;
    return !step.oneGroup() && !step.onHost() && !step.localBatches() &&
           p.constraints.size() <= solver.hostSplitMaxConstraints;
}

}  // namespace btocl
