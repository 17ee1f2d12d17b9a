// Steps solved on the calling thread (hostStepMaxRows, StepMode::Host): chosen by size, forced
// either way by the config or BT_OPENCL_HOST_STEPS, said in the stats, touching no OpenCL call,
// deterministic, and the same physics as the device's whole step, which walks the constraints in
// the same order with the same row code.
#include "FaultInjection.h"
#include "JointScenes.h"
#include "Scenes.h"
#include "ScopedEnv.h"
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
