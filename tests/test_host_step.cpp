// Steps solved on the calling thread (hostStepMaxRows, StepMode::Host): chosen by size, forced
// either way by the config or BT_OPENCL_HOST_STEPS, said in the stats, touching no OpenCL call,
// deterministic, and the same physics as the device's whole step, which walks the constraints in
// the same order with the same row code. Split steps solved there (splitStepsOnHost,
// StepMode::HostSplit): the claimed launch's bits, however the timed choice falls.
#include "FaultInjection.h"
#include "HostLaneSolve.h"
#include "JointScenes.h"
#include "ParallelFrom.h"
#include "Scenes.h"
#include "ScopedEnv.h"
#include "StepPolicy.h"
#include "TestDevice.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace testworld;
using btocl::test::ScopedEnv;

namespace {

btOpenCLSolverConfig hostSteps(int maxRows) {
    btOpenCLSolverConfig c;
    c.hostStepMaxRows = maxRows;
    return c;
}

// Every step on the device, whole in one launch on the serial path (one lane, constraint after
// constraint in gather order): the order the host walks too.
btOpenCLSolverConfig wholeOnDevice() {
    btOpenCLSolverConfig c = hostSteps(0);
    c.wholeStepMaxRows = 1000000;
    c.solvePath = btOpenCLSolvePath::Serial;
    return c;
}

// Contacts and joints from the first step: a small pyramid on the ground, a hinge chain pinned
// beside it, a pendulum chain of point-to-point joints.
void pyramidAndChains(World& w) {
    groundAndPyramid(w, 5);
    btscenes::addHingeChain(w, btVector3(6, 4, 0), 6);
    addChain(w, btVector3(-6, 6, 0), 4, 2);
}

float relativeGap(const btVector3& a, const btVector3& b) {
    float gap = 0;
    for (int k = 0; k < 3; ++k) gap = std::max(gap, std::fabs(a[k] - b[k]) / std::max(1.0f, std::fabs(a[k])));
    return gap;
}

}  // namespace

TEST_CASE("a step under hostStepMaxRows is solved on the calling thread, touching no OpenCL call", "[host]") {
    World w(SolverKind::OpenCL, hostSteps(1000000));
    pyramidAndChains(w);
    w.step();  // the solver's buffers and programs are made by now
    btocl::injectDeviceFault(1, true);  // any OpenCL result checked from here on fails
    w.step();
    const long checked = btocl::deviceResultsChecked();
    btocl::injectDeviceFault(0);
    CHECK(checked == 0);
    const btOpenCLSolverStats& s = w.openCL()->getLastStats();
    CHECK(s.solvedOnHost);
    CHECK_FALSE(s.solvedWholeStep);
    CHECK(s.numGroups == 1);
    CHECK(s.numContactPoints > 0);
    CHECK(s.numJointRows > 0);
    CHECK(s.msUpload == 0);
    CHECK(s.numIterationsRun == w.info().m_numIterations);
}

TEST_CASE("a step solved on the host gives the device's whole step, to the rounding of fused multiply-adds",
          "[host]") {
    // Two worlds built alike, one solving every step on the host, the other every step on the
    // device in one launch: the same constraints in the same order, the same row code. The first
    // step starts from the same state, so only the device compiler's fused multiply-adds part them:
    // 1e-4 relative, as the device solve against its host reference (test_device_solve.cpp).
    // In SI's order, in the randomized order (the same seeds on both), and interleaved.
    const int mode = GENERATE(0, int(SOLVER_RANDMIZE_ORDER), int(SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS));
    CAPTURE(mode);
    World host(SolverKind::OpenCL, hostSteps(1000000)), device(SolverKind::OpenCL, wholeOnDevice());
    for (World* w : {&host, &device}) {
        pyramidAndChains(*w);
        w->info().m_solverMode |= mode;
    }
    host.step();
    device.step();
    REQUIRE(host.openCL()->getLastStats().solvedOnHost);
    REQUIRE(device.openCL()->getLastStats().solvedWholeStep);
    float worst = 0;
    for (size_t i = 0; i < host.bodies().size(); ++i) {
        worst = std::max(worst, relativeGap(host.body(i)->getLinearVelocity(), device.body(i)->getLinearVelocity()));
        worst = std::max(worst, relativeGap(host.body(i)->getAngularVelocity(), device.body(i)->getAngularVelocity()));
    }
    INFO("worst relative velocity difference after one step " << worst);
    CHECK(worst < 1e-4f);
    // Two seconds on: the pyramid stands in both, the chains hang from their pins.
    for (int s = 0; s < 120; ++s) {
        host.step();
        device.step();
    }
    CHECK(maxPositionGap(host, device) < 0.05f);
}

TEST_CASE("a step solved on the host is deterministic", "[host][determinism]") {
    auto run = [] {
        World w(SolverKind::OpenCL, hostSteps(1000000));
        pyramidAndChains(w);
        for (int s = 0; s < 60; ++s) w.step();
        std::vector<btTransform> out;
        for (const btRigidBody* b : w.bodies()) out.push_back(b->getWorldTransform());
        return out;
    };
    const std::vector<btTransform> a = run(), b = run();
    REQUIRE(a.size() == b.size());
    CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(btTransform)) == 0);
}

TEST_CASE("hostStepMaxRows and BT_OPENCL_HOST_STEPS choose where small steps are solved", "[host][api]") {
    auto onHost = [](const btOpenCLSolverConfig& config, int pyramidBase) {
        World w(SolverKind::OpenCL, config);
        groundAndPyramid(w, pyramidBase);
        w.step();
        return w.openCL()->getLastStats().solvedOnHost;
    };
    {
        // As the solver decides: a few boxes on the host, a large pyramid on the device (past
        // a GPU's bound too: about 40K rows).
        ScopedEnv env("BT_OPENCL_HOST_STEPS", "auto");
        CHECK(onHost(btOpenCLSolverConfig{}, 3));
        CHECK_FALSE(onHost(btOpenCLSolverConfig{}, 60));
    }
    CHECK_FALSE(onHost(hostSteps(0), 3));       // never
    CHECK(onHost(hostSteps(1000000), 40));      // a bound above the step's rows
    {
        ScopedEnv env("BT_OPENCL_HOST_STEPS", "never");
        CHECK_FALSE(onHost(btOpenCLSolverConfig{}, 3));
        CHECK(onHost(hostSteps(1000000), 3));  // the config's own bound wins over the variable
    }
    {
        ScopedEnv env("BT_OPENCL_HOST_STEPS", "always");
        CHECK(onHost(btOpenCLSolverConfig{}, 40));
    }
    {
        ScopedEnv env("BT_OPENCL_HOST_STEPS", "sometimes");
        CHECK_THROWS_WITH(btOpenCLConstraintSolver(), Catch::Contains("BT_OPENCL_HOST_STEPS"));
    }
    btOpenCLSolverConfig bad;
    bad.hostStepMaxRows = -2;
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(bad), Catch::Contains("hostStepMaxRows"));
}

namespace {

// Every step split (no whole step, no step under hostStepMaxRows but those of one row), solved
// on the host split alike (1), in a claimed launch (0), or where the recent steps ran faster (-1).
btOpenCLSolverConfig splitSteps(int onHost) {
    btOpenCLSolverConfig c = validatingConfig();
    c.hostStepMaxRows = 1;  // not 0: that would switch the timed choice off
    c.wholeStepMaxRows = 0;
    c.splitStepsOnHost = onHost;
    return c;
}

// The options that change what a step's rows are or the order the passes walk them in.
enum class Variant { Plain, Randomized, TwoFriction, SplitImpulse, Interleaved, Rolling, Residual, Count };

void applyVariant(World& w, Variant v) {
    btContactSolverInfo& info = w.info();
    switch (v) {
        case Variant::Randomized: info.m_solverMode |= SOLVER_RANDMIZE_ORDER; break;
        case Variant::TwoFriction: info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS; break;
        case Variant::SplitImpulse: info.m_splitImpulse = 1; break;
        case Variant::Interleaved: info.m_solverMode |= SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS; break;
        case Variant::Rolling:
            for (btRigidBody* b : w.bodies()) b->setRollingFriction(0.05f);
            break;
        case Variant::Residual: info.m_leastSquaresResidualThreshold = 1e-4f; break;
        default: break;
    }
}

// Every body's transform and velocities (bodyBytes), then every contact point's impulse, as bytes.
std::vector<unsigned char> stateBytes(World& w) {
    std::vector<unsigned char> out = bodyBytes(w);
    btDispatcher* d = &w.dispatcher();
    for (int i = 0; i < d->getNumManifolds(); ++i) {
        const btPersistentManifold* m = d->getManifoldByIndexInternal(i);
        for (int k = 0; k < m->getNumContacts(); ++k) {
            const auto* c = reinterpret_cast<const unsigned char*>(&m->getContactPoint(k).m_appliedImpulse);
            out.insert(out.end(), c, c + sizeof(btScalar));
        }
    }
    for (btTypedConstraint* joint : w.constraints()) {  // as the write-back leaves each joint's rows
        const btScalar impulse = joint->getAppliedImpulse();
        const auto* c = reinterpret_cast<const unsigned char*>(&impulse);
        out.insert(out.end(), c, c + sizeof(btScalar));
    }
    return out;
}

struct SplitRun {
    std::vector<unsigned char> state;
    int stepsOnHost = 0, stepsOnDevice = 0, stepsInLanes = 0, validationFailures = 0;
};

// Contacts and joints (pyramidAndChains), the same with every other joint taking part in the
// first 3 iterations alone, or contacts alone (a pyramid, whose split steps on the host may run in
// lanes), or a pyramid built sunk into itself and the ground (every row 0.08 m into the one below),
// whose points take push impulses for many steps.
enum class SplitScene { WithJoints, JointsOfFewIterations, ContactsOnly, SunkPyramid };

void sunkPyramid(World& w, int base) {
    w.addGround();
    for (int row = 0; row < base; ++row)
        for (int i = 0; i < base - row; ++i)
            w.addUnitBox(btVector3(btScalar(i + 0.5 * row - 0.5 * (base - 1)), btScalar(0.45) + btScalar(0.92) * row, 0),
                         btscenes::stackedBox());
}

SplitRun runSplit(int onHost, Variant v, int steps, size_t parallelFrom = btocl::kMinParallelItems,
                  SplitScene scene = SplitScene::WithJoints) {
    btocl::test::ParallelFrom threshold(parallelFrom);
    World w(SolverKind::OpenCL, splitSteps(onHost));
    if (scene == SplitScene::SunkPyramid) {
        sunkPyramid(w, 10);
    } else if (scene != SplitScene::ContactsOnly) {
        pyramidAndChains(w);
        if (scene == SplitScene::JointsOfFewIterations)
            for (size_t k = 0; k < w.constraints().size(); k += 2) w.constraints()[k]->setOverrideNumSolverIterations(3);
    } else {
        groundAndPyramid(w, 10);
    }
    applyVariant(w, v);
    SplitRun run;
    for (int s = 0; s < steps; ++s) {
        w.step();
        const btOpenCLSolverStats& stats = w.openCL()->getLastStats();
        if (stats.numGroups > 1) (stats.solvedOnHostSplit ? run.stepsOnHost : run.stepsOnDevice) += 1;
        if (stats.solvedOnHostSplit && stats.simdLanes > 1) run.stepsInLanes += 1;
        run.validationFailures += stats.validationFailures;
    }
    run.state = stateBytes(w);
    return run;
}

// The timed choice driven by synthetic times: run(n) takes n steps of 1,000 rows each, at the
// device's and the host's times as set, and returns how many ran on the host.
struct TimedChoice {
    btocl::SplitStepTimes times;
    double deviceMs = 1.0, hostMs = 1.5;
    int run(int n) {
        int host = 0;
        for (int i = 0; i < n; ++i) {
            const bool onHost = times.nextIsSecond();
            host += onHost ? 1 : 0;
            times.record(onHost, onHost ? hostMs : deviceMs, 1000);
        }
        return host;
    }
};

}  // namespace

TEST_CASE("a split step solved on the calling thread gives the claimed launch's bits", "[host][determinism]") {
    // Both walk the same split (the host's) in the same order with the same row code, and a CPU
    // device's program contracts no multiply-add: the same bits, step after step, whatever the
    // options. Elsewhere (a GPU, the wide path) no split step is solved on the host. The host's
    // loops run on its threads here (this scene is below their threshold): each constraint's
    // rows are set up alone. Where the CPU has AVX2 and the options let the contacts pair, the
    // host's lanes take the contacts and each set's joints follow them in lanes of their own
    // (HostLaneSolve), shared out to the host's threads or not.
    const Variant v = Variant(GENERATE(range(0, int(Variant::Count))));
    CAPTURE(int(v));
    const SplitRun host = runSplit(1, v, 40, 1), device = runSplit(0, v, 40);
    CHECK(host.validationFailures == 0);
    CHECK(device.validationFailures == 0);
    CHECK(device.stepsOnHost == 0);
    if (!btocl::test::claimedRunsHere()) {
        CHECK(host.stepsOnHost == 0);
        return;
    }
    CHECK(host.stepsOnDevice == 0);
    REQUIRE(host.stepsOnHost == 40);
    const bool lanes = btocl::HostLaneSolve::available() &&
                       (v == Variant::Plain || v == Variant::TwoFriction || v == Variant::SplitImpulse);
    CHECK(host.stepsInLanes == (lanes ? 40 : 0));
    REQUIRE(host.state.size() == device.state.size());
    CHECK(host.state == device.state);
}

namespace {

// `scene`'s split steps in the host's lanes (where the CPU has AVX2) against the claimed launch:
// the same bits.
void checkHostLanesBits(SplitScene scene) {
    const SplitRun host = runSplit(1, Variant::Plain, 40, 1, scene);
    const SplitRun device = runSplit(0, Variant::Plain, 40, btocl::kMinParallelItems, scene);
    CHECK(host.validationFailures == 0);
    if (!btocl::test::claimedRunsHere()) return;
    REQUIRE(host.stepsOnHost == 40);
    CHECK(host.stepsInLanes == (btocl::HostLaneSolve::available() ? 40 : 0));
    REQUIRE(host.state.size() == device.state.size());
    CHECK(host.state == device.state);
}

}  // namespace

TEST_CASE("joints of fewer iterations than the contacts' in the host's lanes give the claimed launch's bits",
          "[host][determinism][lanes]") {
    // A joint's rows take part while the iteration is under its own count: in the host's lanes a
    // lane whose joint has stopped is masked, its bodies left as they are.
    checkHostLanesBits(SplitScene::JointsOfFewIterations);
}

TEST_CASE("push iterations in the host's lanes end where SI's would and give the claimed launch's bits",
          "[host][determinism][lanes]") {
    // SI ends its push iterations after one that changed no push impulse; the host's lanes pass
    // over the rest (they would change nothing), the claimed launch walks them all: the same bits.
    checkHostLanesBits(SplitScene::SunkPyramid);
}

TEST_CASE("a split step in the host's lanes gives the claimed launch's bits", "[host][determinism][lanes]") {
    // Contact rows alone, in passes that pair: where the CPU has AVX2 the host walks eight groups
    // at a time in its vector unit's lanes, each lane as the one-lane walk (HostLaneSolve.h), its
    // rows set up on the host's threads. The options that do not fit lanes (a shuffled order,
    // residuals, interleaved friction, rolling rows) walk one group at a time, as above.
    const Variant v = GENERATE(Variant::Plain, Variant::TwoFriction, Variant::SplitImpulse, Variant::Randomized);
    CAPTURE(int(v));
    const SplitRun host = runSplit(1, v, 40, 1, SplitScene::ContactsOnly);
    const SplitRun device = runSplit(0, v, 40, btocl::kMinParallelItems, SplitScene::ContactsOnly);
    CHECK(host.validationFailures == 0);
    if (!btocl::test::claimedRunsHere()) return;
    REQUIRE(host.stepsOnHost == 40);
    const bool lanes = btocl::HostLaneSolve::available() && v != Variant::Randomized;
    CHECK(host.stepsInLanes == (lanes ? 40 : 0));
    CHECK(device.stepsInLanes == 0);
    REQUIRE(host.state.size() == device.state.size());
    CHECK(host.state == device.state);
}

TEST_CASE("split steps placed by their times take both ways and give the claimed launch's bits",
          "[host][determinism]") {
    // The timed choice runs the first steps each way by turns, so both ways are taken in a run
    // of any length; where later steps go depends on the machine, but no result does.
    const SplitRun timed = runSplit(-1, Variant::Plain, 60), device = runSplit(0, Variant::Plain, 60);
    CHECK(timed.validationFailures == 0);
    if (!btocl::test::claimedRunsHere()) {
        CHECK(timed.stepsOnHost == 0);
        return;
    }
    CHECK(timed.stepsOnHost >= btocl::SplitStepTimes::kFirstSteps);
    CHECK(timed.stepsOnDevice >= btocl::SplitStepTimes::kFirstSteps);
    CHECK(timed.stepsOnHost + timed.stepsOnDevice == 60);
    CHECK(timed.state == device.state);
}

TEST_CASE("splitStepsOnHost is checked, and off where host steps are off", "[host][api]") {
    btOpenCLSolverConfig bad;
    bad.splitStepsOnHost = 2;
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(bad), Catch::Contains("splitStepsOnHost"));
    auto stepsOnHost = [](const btOpenCLSolverConfig& c) {
        World w(SolverKind::OpenCL, c);
        pyramidAndChains(w);
        int n = 0;
        for (int s = 0; s < 12; ++s) {
            w.step();
            n += w.openCL()->getLastStats().solvedOnHostSplit ? 1 : 0;
        }
        return n;
    };
    btOpenCLSolverConfig off = splitSteps(-1);
    off.hostStepMaxRows = 0;
    CHECK(stepsOnHost(off) == 0);
    {
        ScopedEnv env("BT_OPENCL_HOST_STEPS", "never");
        btOpenCLSolverConfig automatic = splitSteps(-1);
        automatic.hostStepMaxRows = -1;
        CHECK(stepsOnHost(automatic) == 0);
    }
    if (btocl::test::claimedRunsHere()) CHECK(stepsOnHost(splitSteps(-1)) > 0);
}

TEST_CASE("the timed choice takes the faster way, tries the other, and follows a load", "[host][policy]") {
    using btocl::SplitStepTimes;
    TimedChoice c;
    // Timed by turns first: a first step and kFirstSteps timed ones each way.
    const int firstSteps = 1 + SplitStepTimes::kFirstSteps;
    CHECK(c.run(2 * firstSteps) == firstSteps);
    // The device faster: the host tried now and then, less often while it loses.
    const int tries = c.run(1000);
    CHECK(tries > 0);
    CHECK(tries <= 1000 / SplitStepTimes::kFirstTry);
    // The device's steps stalled (another process on its cores): the host once the stalls have
    // lifted the device's mean past the host's (here the second).
    c.deviceMs = 6.0;
    CHECK(c.run(3) >= 1);
    const int underLoad = c.run(1000);
    CHECK(underLoad > 1000 - 1000 / SplitStepTimes::kFirstTry);
    // The load gone: back on the device once it is timed afresh, if not at an earlier try.
    c.deviceMs = 1.0;
    c.run(SplitStepTimes::kRetime + 2 * firstSteps);
    CHECK(c.run(200) <= 200 / SplitStepTimes::kFirstTry + SplitStepTimes::kFirstSteps + 1);
}

TEST_CASE("a tried way's time stands for its older times", "[host][policy]") {
    // A scene that grows or settles changes both ways' times; the way not taken is known only by
    // its tries, so a try is taken as that way's time now, not averaged with steps long past.
    using btocl::SplitStepTimes;
    TimedChoice c;
    c.run(2 * (1 + SplitStepTimes::kFirstSteps) + 40);  // timed by turns, then the device
    c.deviceMs = 3.0;  // slower for a while: the host takes the steps
    c.run(8);
    c.deviceMs = 1.0;  // the device's next try, a kFirstTry steps on, takes them back
    CHECK(c.run(100) <= SplitStepTimes::kFirstTry + 2);
}
