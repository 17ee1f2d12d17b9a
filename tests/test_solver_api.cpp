// What a user of btOpenCLConstraintSolver sees beside the physics: a clear error for bad input
// and bad configurations, a world that steps on after an
// error, solveGroup called by hand, plausible statistics, a device name. These always run our
// solver.
#include "OclRuntime.h"
#include "ScopedEnv.h"
#include "TestWorld.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

using namespace testworld;
using btocl::test::ScopedEnv;

namespace {

// A box settled on the ground by SI, and our solver driven by hand on its contacts.
struct HandDriven {
    World w{SolverKind::Reference};
    btRigidBody* box = settle(w);
    btOpenCLConstraintSolver solver;
    btContactSolverInfo info = w.stepInfo();
    std::vector<btPersistentManifold*> manifolds = w.manifolds();

    static btRigidBody* settle(World& world) {
        world.addGround();
        btRigidBody* b = world.addUnitBox(btVector3(0, 0.5f, 0));
        for (int s = 0; s < 20; ++s) world.step();
        return b;
    }
    void solveGroup(const btContactSolverInfo& with) {
        btCollisionObject* bodies[] = {box};
        solver.solveGroup(bodies, 1, manifolds.data(), int(manifolds.size()), nullptr, 0, with, nullptr, &w.dispatcher());
    }
};

// Two boxes resting on the ground apart (two islands, as a world that splits islands hands them
// to its solver: a solveGroup call each) and a third in the air, settled by SI; the resting ones
// moving into the ground, the falling one under gravity. A solver is driven by hand on them.
struct Islands {
    World w{SolverKind::Reference};
    btRigidBody* a = nullptr;
    btRigidBody* b = nullptr;
    btRigidBody* air = nullptr;

    Islands() {
        w.addGround();
        a = w.addUnitBox(btVector3(0, btScalar(0.5), 0));
        b = w.addUnitBox(btVector3(5, btScalar(0.5), 0));
        air = w.addUnitBox(btVector3(-5, 20, 0));
        for (int s = 0; s < 20; ++s) w.step();
        for (btRigidBody* box : {a, b}) box->setLinearVelocity(btVector3(0, -1, 0));
        air->applyGravity();
    }
    // One island's call: the body and its manifolds.
    void group(btConstraintSolver& solver, btRigidBody* body, const btContactSolverInfo& info) {
        std::vector<btPersistentManifold*> ofBody;
        for (btPersistentManifold* m : w.manifolds())
            if (m->getBody0() == body || m->getBody1() == body) ofBody.push_back(m);
        btCollisionObject* bodies[] = {body};
        solver.solveGroup(bodies, 1, ofBody.data(), int(ofBody.size()), nullptr, 0, info, nullptr, &w.dispatcher());
    }
};

// The same calls by our solver on `ours` and by Bullet's on `bullets` (twin worlds).
void driveBoth(Islands& ours, btConstraintSolver& solver, Islands& bullets,
               const std::function<void(Islands&, btConstraintSolver&)>& calls) {
    btSequentialImpulseConstraintSolver si;
    calls(ours, solver);
    calls(bullets, si);
}

// Body by body, the same velocity within a hundredth of a millimetre a second (our solver
// against Bullet's on a box resting alone: they agree far closer).
void requireSameVelocities(const Islands& ours, const Islands& bullets) {
    for (size_t i = 0; i < ours.w.bodies().size(); ++i) {
        INFO("body " << i);
        CHECK(distance(ours.w.body(i)->getLinearVelocity(), bullets.w.body(i)->getLinearVelocity()) < 1e-5);
        if (!ours.w.body(i)->isStaticObject()) CHECK(ours.w.body(i)->getCompanionId() == -1);
    }
}

bool finiteState(const btRigidBody* b) {
    const btVector3 p = pos(b), v = b->getLinearVelocity(), w = b->getAngularVelocity();
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(p[k]) || !std::isfinite(v[k]) || !std::isfinite(w[k])) return false;
    return true;
}

}  // namespace

TEST_CASE("a non-finite body velocity is a clear error and the world steps on once it is fixed", "[errors]") {
    World w(SolverKind::OpenCL);
    w.addGround();
    btRigidBody* box = w.addUnitBox(btVector3(0, 0.5f, 0));
    btRigidBody* other = w.addUnitBox(btVector3(3, 0.5f, 0));
    for (int s = 0; s < 10; ++s) w.step();
    const btVector3 otherBefore = other->getWorldTransform().getOrigin();
    box->setLinearVelocity(btVector3(std::numeric_limits<btScalar>::quiet_NaN(), 0, 0));
    try {
        w.step();
        FAIL("a NaN velocity should be reported");
    } catch (const btOpenCLSolverError& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find("non-finite") != std::string::npos);
    }
    // The solver changed nothing: the healthy box kept its place, and neither box is left marked
    // as being in a solver (Bullet's own mark for the static ground is its business).
    CHECK((other->getWorldTransform().getOrigin() - otherBefore).length() < 1e-3f);
    CHECK(box->getCompanionId() == -1);
    CHECK(other->getCompanionId() == -1);
    box->setLinearVelocity(btVector3(0, 0, 0));
    box->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.5f, 0)));
    for (int s = 0; s < 30; ++s) w.step();
    CHECK(std::fabs(box->getWorldTransform().getOrigin().y() - 0.5f) < 0.02f);
}

TEST_CASE("bad configurations are refused with a message", "[errors]") {
    btOpenCLSolverConfig config;
    config.workGroupSize = 48;
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(config), Catch::Contains("workGroupSize"));
    config = btOpenCLSolverConfig{};
    config.batchIterations = 0;
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(config), Catch::Contains("batchIterations"));
    config = btOpenCLSolverConfig{};
    config.cellSize = -1;
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(config), Catch::Contains("cellSize"));
    config = btOpenCLSolverConfig{};
    config.wholeStepMaxRows = -2;
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(config), Catch::Contains("wholeStepMaxRows"));
}

TEST_CASE("solveGroup called outside prepareSolve/allSolved solves at once", "[api]") {
    // Some users drive a solver by hand; then each solveGroup call is a whole step.
    HandDriven h;
    REQUIRE_FALSE(h.manifolds.empty());
    h.box->setLinearVelocity(btVector3(0, -1, 0));  // moving into the ground
    h.solveGroup(h.info);
    CHECK(h.solver.getLastStats().numContactPoints == 4);
    CHECK(h.box->getLinearVelocity().y() > -0.05f);  // the contacts stopped it
    CHECK(h.box->getCompanionId() == -1);
}

TEST_CASE("after an error inside a step, a hand-driven solveGroup still solves at once", "[errors]") {
    // The error ends the step's prepareSolve/allSolved bracket: the solver must not wait for an
    // allSolved that will never come.
    HandDriven h;
    h.solver.prepareSolve(1, int(h.manifolds.size()));
    btContactSolverInfo bad = h.info;
    bad.m_timeStep = 0;
    CHECK_THROWS_AS(h.solveGroup(bad), btOpenCLSolverError);
    CHECK(h.box->getCompanionId() == -1);
    h.box->setLinearVelocity(btVector3(0, -1, 0));
    h.solveGroup(h.info);
    CHECK(h.solver.getLastStats().numContactPoints == 4);
    CHECK(h.box->getLinearVelocity().y() > -0.05f);
}

TEST_CASE("two boxes joined by a point-to-point joint fall together and stay joined", "[api]") {
    World w(SolverKind::OpenCL);
    w.addGround();
    btRigidBody* a = w.addUnitBox(btVector3(0, 3, 0));
    btRigidBody* b = w.addUnitBox(btVector3(1, 3, 0));
    const btVector3 pivotA(btScalar(0.5), 0, 0), pivotB(btScalar(-0.5), 0, 0);
    w.addConstraint(std::make_unique<btPoint2PointConstraint>(*a, *b, pivotA, pivotB));
    for (int i = 0; i < 90; ++i) w.step();
    REQUIRE(finiteState(a));
    REQUIRE(finiteState(b));
    REQUIRE(pos(a).y() < 1);  // they fell and landed
    REQUIRE(w.openCL()->getLastStats().numJointRows == 3);
    // The pivots stay together: a few millimetres of joint error, as Bullet's solver leaves.
    const btVector3 gap = a->getWorldTransform() * pivotA - b->getWorldTransform() * pivotB;
    REQUIRE(gap.length() < 0.01);
}

namespace {

// Two layers of 30 x 30 unit boxes on the ground, a little apart: 1,800 manifolds.
void addTwoLayersOf30By30(World& w) {
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 30; ++x)
            for (int z = 0; z < 30; ++z)
                w.addUnitBox(btVector3(btScalar(x) * 1.05f, btScalar(0.5) + btScalar(y), btScalar(z) * 1.05f));
}

}  // namespace

TEST_CASE("getLastStats counts the bodies and contact points of a known scene", "[api]") {
    World w(SolverKind::OpenCL);
    w.addGround();
    for (int i = 0; i < 3; ++i) w.addUnitBox(btVector3(btScalar(3 * i), btScalar(0.5), 0));
    for (int i = 0; i < 10; ++i) w.step();
    const btOpenCLSolverStats& s = w.openCL()->getLastStats();
    CAPTURE(s.numBodies, s.numContactPoints, s.numJointRows, s.numConstraintRows, s.numCellGroups,
            s.numBatchesMax, s.numBatchesMean, s.msTotal);
    // A box resting flat on a box gets 4 points (btBoxBoxDetector clips the faces).
    REQUIRE(w.numContactPoints() == 12);
    REQUIRE(s.numContactPoints == w.numContactPoints());
    // Three dynamic boxes, plus the ground if the solver counts static bodies it touches.
    REQUIRE(s.numBodies >= 3);
    REQUIRE(s.numBodies <= 4);
    REQUIRE(s.numJointRows == 0);
    // Each point has a normal row and (friction > 0) at least one friction row.
    REQUIRE(s.numConstraintRows >= 2 * s.numContactPoints);
    // Three manifolds: a step this small is solved whole, as one group, on the device or the host.
    REQUIRE(s.solvedWholeStep != s.solvedOnHost);
    REQUIRE(s.numGroups == 1);
    REQUIRE(s.numCellGroups == 0);
    REQUIRE(s.numBatchesMax >= 1);
    REQUIRE(s.validationFailures == 0);
    REQUIRE(s.msTotal > 0);
}

TEST_CASE("a step of many constraints is split into cell groups", "[api]") {
    btOpenCLSolverConfig onDevice;
    onDevice.hostStepMaxRows = 0;  // a GPU's host would take it
    World w(SolverKind::OpenCL, onDevice);
    w.addGround();
    // Two layers of 30 x 30 boxes: 1,800 manifolds, over the whole-step limit of 1,024.
    addTwoLayersOf30By30(w);
    for (int i = 0; i < 3; ++i) w.step();
    const btOpenCLSolverStats& s = w.openCL()->getLastStats();
    CAPTURE(s.numContactPoints, s.numGroups, s.numCellGroups, s.numBatchesMax, s.numOverflowConstraints);
    REQUIRE_FALSE(s.solvedWholeStep);
    REQUIRE(s.numCellGroups > 4);  // a pile wider than a cell spreads over cells of every set
    REQUIRE(s.numGroups >= s.numCellGroups);
    REQUIRE(s.numBatchesMax >= 1);
}

TEST_CASE("by default a step is solved whole up to a size that depends on the solve path", "[api]") {
    // 1,800 manifolds, about 14,000 rows: past the wide path's 1,024 constraints. The serial
    // path splits every device step where its split is the host's (a CPU device of two or more
    // compute units: StepPolicy.cpp), and otherwise takes at least 16K rows whole.
    const btocl::OclRuntime rt("");
    const bool serialSplits = rt.isCpu() && rt.computeUnits() > 1;
    btOpenCLSolverConfig config;  // wholeStepMaxRows automatic
    World w(SolverKind::OpenCL, config);
    w.addGround();
    addTwoLayersOf30By30(w);
    for (int i = 0; i < 3; ++i) w.step();
    const btOpenCLSolverStats& s = w.openCL()->getLastStats();
    CAPTURE(s.numConstraintRows, s.numGroups);
    REQUIRE(s.numConstraintRows > 4096);
    REQUIRE(s.numConstraintRows < 16384);
    CHECK(s.solvedWholeStep == (w.openCL()->getSolvePath() == btOpenCLSolvePath::Serial && !serialSplits));
    // Asked for, every step is split.
    config.wholeStepMaxRows = 0;
    World split(SolverKind::OpenCL, config);
    split.addGround();
    for (int i = 0; i < 3; ++i) split.addUnitBox(btVector3(btScalar(3 * i), btScalar(0.5), 0));
    for (int i = 0; i < 3; ++i) split.step();
    CHECK_FALSE(split.openCL()->getLastStats().solvedWholeStep);
}

TEST_CASE("getDeviceName names the device", "[api]") {
    btOpenCLConstraintSolver solver(validatingConfig());
    REQUIRE_FALSE(solver.getDeviceName().empty());
}

TEST_CASE("the environment's solve path and transfers are read in any case, as device names are", "[api]") {
    for (const char* wide : {"WIDE", "Wide"}) {
        const ScopedEnv path("BT_OPENCL_SOLVE_PATH", wide);
        CHECK(btOpenCLConstraintSolver().getSolvePath() == btOpenCLSolvePath::Wide);
    }
    {
        const ScopedEnv path("BT_OPENCL_SOLVE_PATH", "Serial");
        CHECK(btOpenCLConstraintSolver().getSolvePath() == btOpenCLSolvePath::Serial);
    }
    {
        const ScopedEnv transfers("BT_OPENCL_TRANSFERS", "COPY");
        CHECK_NOTHROW(btOpenCLConstraintSolver());
    }
    const ScopedEnv path("BT_OPENCL_SOLVE_PATH", "Widest");
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(), Catch::Contains("BT_OPENCL_SOLVE_PATH is 'Widest'"));
}

TEST_CASE("a second prepareSolve inside a step solves the groups gathered before it, as Bullet's solver does",
          "[api]") {
    // It dropped them: their bodies went unsolved, and kept their companion ids.
    Islands ours, bullets;
    btOpenCLConstraintSolver solver(validatingConfig());
    const btContactSolverInfo info = ours.w.stepInfo();
    driveBoth(ours, solver, bullets, [&info](Islands& islands, btConstraintSolver& s) {
        s.prepareSolve(2, 2);
        islands.group(s, islands.a, info);
        s.prepareSolve(2, 2);
        islands.group(s, islands.b, info);
        s.allSolved(info, nullptr);
    });
    CHECK(ours.a->getLinearVelocity().y() > btScalar(-0.05));  // its contacts stopped it
    requireSameVelocities(ours, bullets);
}

TEST_CASE("solveGroup calls of one step with other settings are each solved with their own, as Bullet's solver does",
          "[api]") {
    // The falling box's call asks for a 30 Hz step: it gains a 30th of a second of gravity, not a
    // 60th (the first call's settings, which it was solved with).
    Islands ours, bullets;
    btOpenCLConstraintSolver solver(validatingConfig());
    const btContactSolverInfo at60 = ours.w.stepInfo();
    btContactSolverInfo at30 = at60;
    at30.m_timeStep = btScalar(1) / 30;
    at30.m_numIterations = 4;
    driveBoth(ours, solver, bullets, [&](Islands& islands, btConstraintSolver& s) {
        s.prepareSolve(3, 2);
        islands.group(s, islands.a, at60);
        islands.group(s, islands.air, at30);
        islands.group(s, islands.b, at60);
        s.allSolved(at60, nullptr);
    });
    CHECK(ours.air->getLinearVelocity().y() < btScalar(-0.3));
    requireSameVelocities(ours, bullets);

    // Settings equal in every field (copies, not one object): the calls are gathered into one solve.
    Islands again;
    const btContactSolverInfo copy = at60;
    solver.prepareSolve(2, 2);
    again.group(solver, again.a, at60);
    again.group(solver, again.b, copy);
    solver.allSolved(at60, nullptr);
    CHECK(solver.getLastStats().numContactPoints == 8);
}
