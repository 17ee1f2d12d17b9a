// A step that fails after it began on the device: it leaves the world exactly as it was, in every
// solver mode; nothing it queued outlives the memory it reads (the solver can be swapped out and
// deleted at once); the next step is solved as if the failure had not happened. Device failures
// are injected (FaultInjection.h) at each OpenCL result the step checks.
#include "FaultInjection.h"
#include "SettledPile.h"
#include "WorldSnapshot.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

using namespace testworld;

namespace {

// Device failures need the device: small steps would otherwise be solved on the host.
btOpenCLSolverConfig onTheDevice() {
    btOpenCLSolverConfig c = validatingConfig();
    c.hostStepMaxRows = 0;
    return c;
}

}  // namespace

namespace {

// Turns injected faults off when a test ends, however it ends.
struct NoFaultsAfter {
    ~NoFaultsAfter() { btocl::injectDeviceFault(0); }
};

// OpenCL results one solve of the pile checks, once its buffers exist (a first solve also
// checks their allocations). Solves the pile twice.
long checksPerSolve(SettledPile& p) {
    p.solve();
    btocl::injectDeviceFault(std::numeric_limits<long>::max());  // count, never fail
    p.solve();
    const long n = btocl::deviceResultsChecked();
    btocl::injectDeviceFault(0);
    return n;
}

// Solves with the nth check failing; returns the error's message ("" if nothing was thrown).
std::string solveFailingAt(SettledPile& p, long nth, const btContactSolverInfo& info) {
    btocl::injectDeviceFault(nth);
    std::string message;
    try {
        p.solve(info);
    } catch (const btOpenCLSolverError& e) {
        message = e.what();
    }
    btocl::injectDeviceFault(0);
    return message;
}

// The solver modes whose writes differ: the item-3 modes of issue #12.
struct Mode {
    const char* name;
    std::function<void(World&)> prepare;
};
std::vector<Mode> solverModes() {
    auto mode = [](int bits) { return [bits](World& w) { w.info().m_solverMode |= bits; }; };
    return {
        {"default (warm starting, SIMD)", [](World&) {}},
        {"two friction directions", mode(SOLVER_USE_2_FRICTION_DIRECTIONS)},
        {"two directions, not velocity dependent",
         mode(SOLVER_USE_2_FRICTION_DIRECTIONS | SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION)},
        {"friction direction caching", mode(SOLVER_USE_2_FRICTION_DIRECTIONS | SOLVER_ENABLE_FRICTION_DIRECTION_CACHING)},
        {"anisotropic friction (rows set up on the host)",
         [](World& w) {
             for (btRigidBody* b : w.bodies())
                 b->setAnisotropicFriction(btVector3(1, btScalar(0.5), btScalar(0.2)),
                                           btCollisionObject::CF_ANISOTROPIC_FRICTION);
         }},
        {"split impulse", [](World& w) { w.info().m_splitImpulse = 1; }},
        {"no split impulse", [](World& w) { w.info().m_splitImpulse = 0; }},
        {"rolling and spinning friction",
         [](World& w) {
             for (btRigidBody* b : w.bodies()) {
                 b->setRollingFriction(btScalar(0.1));
                 b->setSpinningFriction(btScalar(0.1));
             }
         }},
    };
}

}  // namespace

TEST_CASE("a rejected step leaves every body and every manifold point bitwise as it was, in every solver mode",
          "[errors][failed-step]") {
    NoFaultsAfter cleanup;
    btOpenCLConstraintSolver solver(onTheDevice());
    for (const Mode& mode : solverModes()) {
        INFO("mode: " << mode.name);
        SettledPile p(solver, mode.prepare);
        const btContactSolverInfo info = p.info();
        auto requireUnchanged = [&](const std::function<std::string()>& failingSolve) {
            const WorldSnapshot before = WorldSnapshot::of(p.w.dyn());
            const std::string message = failingSolve();
            INFO("message: " << message);
            CHECK_FALSE(message.empty());
            CHECK(before.differenceFrom(WorldSnapshot::of(p.w.dyn())) == "");
        };
        // Bad input in the last point the step reads: found after every other point was read.
        btPersistentManifold* last = p.lastManifold();
        REQUIRE(last != nullptr);
        btManifoldPoint& cp = last->getContactPoint(last->getNumContacts() - 1);
        for (btScalar* field : {&cp.m_normalWorldOnB[1], &cp.m_appliedImpulse}) {
            const btScalar good = *field;
            *field = std::numeric_limits<btScalar>::quiet_NaN();
            requireUnchanged([&] {
                try {
                    p.solve(info);
                } catch (const btOpenCLSolverError& e) {
                    return std::string(e.what());
                }
                return std::string();
            });
            *field = good;
        }
        // A device failure at checks spread over the whole step, the last one included (the read-back
        // just before the write-back).
        const long checks = checksPerSolve(p);
        REQUIRE(checks > 10);
        std::vector<long> at;
        for (long nth = 1; nth < checks; nth += std::max(1L, checks / 12)) at.push_back(nth);
        at.push_back(checks);
        for (const long nth : at) {
            INFO("device failure at check " << nth << " of " << checks);
            requireUnchanged([&] { return solveFailingAt(p, nth, info); });
        }
        // The snapshot does see what a solve writes.
        const WorldSnapshot before = WorldSnapshot::of(p.w.dyn());
        p.solve(info);
        CHECK(before.differenceFrom(WorldSnapshot::of(p.w.dyn())) != "");
    }
}

TEST_CASE("after a device failure at any point of a step, the next step is solved as if it had not happened",
          "[errors][failed-step]") {
    // Twin piles, each with its own solver: one fails at check k of a step, then both solve; the
    // two must agree bitwise (nothing of the failed step lingers in buffers, flags or queues).
    NoFaultsAfter cleanup;
    btOpenCLConstraintSolver failingSolver(onTheDevice()), healthySolver(onTheDevice());
    SettledPile failing(failingSolver), healthy(healthySolver);
    const long checks = checksPerSolve(failing);
    healthy.solve();
    healthy.solve();
    REQUIRE(solveOutputsOf(failing.w.bodies(), failing.manifolds) == solveOutputsOf(healthy.w.bodies(), healthy.manifolds));
    for (long nth = 1; nth <= checks; ++nth) {
        INFO("device failure at check " << nth << " of " << checks);
        const std::string message = solveFailingAt(failing, nth, failing.info());
        REQUIRE(message.find("CL_OUT_OF_RESOURCES") != std::string::npos);
        failing.solve();
        healthy.solve();
        REQUIRE(solveOutputsOf(failing.w.bodies(), failing.manifolds) == solveOutputsOf(healthy.w.bodies(), healthy.manifolds));
    }
    CHECK(failingSolver.getLastStats().numContactPoints == healthySolver.getLastStats().numContactPoints);
}

TEST_CASE("after a failed step the solver can be swapped for Bullet's and deleted at once", "[errors][failed-step]") {
    // The crash: copies queued by the upload still read the step's host vectors when the
    // solver is deleted. Under AddressSanitizer (BTOCL_SANITIZE) a copy that outlives them is a
    // heap-use-after-free. Failures at the first checks of the step, among the upload's copies.
    NoFaultsAfter cleanup;
    World w(SolverKind::Reference);
    groundAndPile(w, 200);
    btConstraintSolver* bullets = w.dyn().getConstraintSolver();
    for (long nth = 2; nth <= 12; nth += 2) {
        INFO("device failure at check " << nth);
        auto* ours = new btOpenCLConstraintSolver(onTheDevice());
        w.dyn().setConstraintSolver(ours);
        w.step();  // the buffers exist: the next step's checks are the copies and launches
        btocl::injectDeviceFault(nth);
        CHECK_THROWS_AS(w.step(), btOpenCLSolverError);
        btocl::injectDeviceFault(0);
        w.dyn().setConstraintSolver(bullets);
        delete ours;
        w.dyn().clearForces();  // Bullet skipped it when the step threw
        w.step();
    }
    for (const btRigidBody* b : w.bodies()) REQUIRE(std::isfinite(b->getLinearVelocity().length()));
}

TEST_CASE("what a failed step queued is finished before the solver's memory goes", "[errors][failed-step]") {
    // 40,000 free boxes, no world: the upload copies megabytes, which takes longer than the throw
    // and the delete that follow a failure among its first checks. A copy still queued then
    // reads freed memory (under AddressSanitizer, BTOCL_SANITIZE: a heap-use-after-free in the
    // OpenCL driver's thread), unless the error path waited for the queue.
    NoFaultsAfter cleanup;
    btBoxShape shape(btVector3(btScalar(0.5), btScalar(0.5), btScalar(0.5)));
    std::vector<std::unique_ptr<btRigidBody>> boxes;
    std::vector<btCollisionObject*> objects;
    for (int i = 0; i < 40000; ++i) {
        btRigidBody::btRigidBodyConstructionInfo ci(1, nullptr, &shape, btVector3(btScalar(1) / 6, btScalar(1) / 6, btScalar(1) / 6));
        ci.m_startWorldTransform.setOrigin(btVector3(btScalar(2 * (i % 200)), 10, btScalar(2 * (i / 200))));
        boxes.push_back(std::make_unique<btRigidBody>(ci));
        boxes.back()->setLinearVelocity(btVector3(0, -1, 0));
        objects.push_back(boxes.back().get());
    }
    btContactSolverInfo info;
    info.m_timeStep = kDt;
    // A step of free bodies has few checks; each of its first six fails once.
    long checks = 0;
    {
        btOpenCLConstraintSolver counting(onTheDevice());
        counting.solveGroup(objects.data(), int(objects.size()), nullptr, 0, nullptr, 0, info, nullptr, nullptr);
        btocl::injectDeviceFault(std::numeric_limits<long>::max());  // count, never fail
        counting.solveGroup(objects.data(), int(objects.size()), nullptr, 0, nullptr, 0, info, nullptr, nullptr);
        checks = btocl::deviceResultsChecked();
        btocl::injectDeviceFault(0);
    }
    REQUIRE(checks >= 2);
    for (long nth = 1; nth <= std::min(checks, 6L); ++nth) {
        INFO("device failure at check " << nth << " of " << checks);
        auto solver = std::make_unique<btOpenCLConstraintSolver>(onTheDevice());
        auto solve = [&] { solver->solveGroup(objects.data(), int(objects.size()), nullptr, 0, nullptr, 0, info, nullptr, nullptr); };
        solve();  // buffers made: the next solve's first checks are its copies
        const btVector3 before = boxes[123]->getLinearVelocity();
        btocl::injectDeviceFault(nth);
        CHECK_THROWS_AS(solve(), btOpenCLSolverError);
        btocl::injectDeviceFault(0);
        solver.reset();
        CHECK(boxes[123]->getLinearVelocity() == before);
    }
}

namespace {

btOpenCLSolverConfig fallingBack() {
    btOpenCLSolverConfig c = onTheDevice();
    c.fallbackToBullet = true;
    return c;
}

// Bodies' transforms, velocities and companion ids, bitwise.
std::vector<unsigned char> stateOf(const World& w) {
    return solveOutputsOf(w.bodies(), std::vector<const btPersistentManifold*>{});
}

}  // namespace

TEST_CASE("with fallbackToBullet, steps our solver fails are solved by Bullet's solver, bitwise as Bullet's own",
          "[errors][failed-step][fallback]") {
    NoFaultsAfter cleanup;
    World ours(SolverKind::OpenCL, fallingBack()), bullets(SolverKind::Reference);
    for (World* w : {&ours, &bullets}) groundAndPile(*w, 64);
    btocl::injectDeviceFault(1, true);  // every OpenCL check fails: every step falls back
    for (int s = 0; s < 60; ++s) {
        INFO("step " << s);
        ours.step();
        bullets.step();
        REQUIRE(stateOf(ours) == stateOf(bullets));
    }
    btocl::injectDeviceFault(0);
    const btOpenCLSolverStats& stats = ours.openCL()->getLastStats();
    CHECK(stats.solvedByBullet);
    CHECK(stats.numFallbackSteps == 60);
    CHECK(stats.lastFallbackReason.find("CL_OUT_OF_RESOURCES") != std::string::npos);
    CHECK(stats.msTotal > 0);
    // The device works again: our solver takes the steps back, the count stays.
    ours.step();
    CHECK_FALSE(ours.openCL()->getLastStats().solvedByBullet);
    CHECK(ours.openCL()->getLastStats().numContactPoints > 0);
    CHECK(ours.openCL()->getLastStats().numFallbackSteps == 60);
}

TEST_CASE("fallbackToBullet does not hide bad input", "[errors][failed-step][fallback]") {
    World w(SolverKind::OpenCL, fallingBack());
    groundAndPile(w, 20);
    for (int s = 0; s < 5; ++s) w.step();
    w.body(3)->setAngularVelocity(btVector3(0, std::numeric_limits<btScalar>::quiet_NaN(), 0));
    CHECK_THROWS_WITH(w.step(), Catch::Contains("angular velocity") && Catch::Contains("index 3 of"));
    CHECK(w.openCL()->getLastStats().numFallbackSteps == 0);
}

TEST_CASE("a caller who catches a failed step and calls clearForces() steps on as if it had not happened",
          "[errors][failed-step]") {
    // stepSimulation skips clearForces() when the solver throws: without the call the next step
    // applies gravity twice (the header and the README say so).
    NoFaultsAfter cleanup;
    World failing(SolverKind::OpenCL, onTheDevice()), healthy(SolverKind::OpenCL, onTheDevice()),
        forgetful(SolverKind::OpenCL, onTheDevice());
    for (World* w : {&failing, &healthy, &forgetful}) {
        groundAndPile(*w, 20);
        for (int s = 0; s < 20; ++s) w->step();
    }
    for (World* w : {&failing, &forgetful}) {
        btocl::injectDeviceFault(40);
        CHECK_THROWS_AS(w->step(), btOpenCLSolverError);
        btocl::injectDeviceFault(0);
    }
    failing.dyn().clearForces();
    for (int s = 0; s < 20; ++s) {
        failing.step();
        healthy.step();
        forgetful.step();
    }
    CHECK(stateOf(failing) == stateOf(healthy));
    // Without clearForces() a box of the upper layer, resting, took a double gravity impulse.
    CHECK(stateOf(forgetful) != stateOf(healthy));
}
