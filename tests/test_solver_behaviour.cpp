// Solver-level behaviour beyond parity: determinism, bad input, calls outside a step bracket.
#include "Scenes.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>

using namespace testworld;

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

std::vector<btTransform> runPile(int boxes, int steps) {
    World w(SolverKind::OpenCL);
    groundAndPile(w, boxes);
    for (int s = 0; s < steps; ++s) w.step();
    std::vector<btTransform> out;
    for (const btRigidBody* b : w.bodies()) out.push_back(b->getWorldTransform());
    return out;
}

}  // namespace

TEST_CASE("two runs of a 1,000-box pile end bitwise equal", "[determinism]") {
    // Groups of a set run on both cores in any order, but share no dynamic body, and batches
    // inside a group are solved in a fixed order: nothing the scheduler does reaches the result.
    const std::vector<btTransform> a = runPile(1000, 40);
    const std::vector<btTransform> b = runPile(1000, 40);
    REQUIRE(a.size() == b.size());
    size_t differing = 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::memcmp(&a[i], &b[i], sizeof(btTransform)) != 0) ++differing;
    CHECK(differing == 0);
}

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
