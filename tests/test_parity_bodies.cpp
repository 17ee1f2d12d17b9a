// Parity with btSequentialImpulseConstraintSolver for special bodies and set-ups: a kinematic
// body pushing boxes, a body with a zero linear factor on one axis, two worlds with two solvers.
#include "TestWorld.h"

using namespace testworld;

namespace {

const btVector3 kPusherVelocity(1, 0, 0);

// A kinematic wall moving at 1 m/s into a row of three boxes.
void pusherScene(World& w) {
    w.addGround();
    w.addKinematicBox(btVector3(btScalar(0.5), btScalar(0.5), btScalar(1.5)), at(btVector3(-1.5, btScalar(0.5), 0)),
                      kPusherVelocity);
    for (int i = 0; i < 3; ++i) w.addUnitBox(btVector3(btScalar(0.2) + btScalar(1.2) * i, btScalar(0.5), 0));
}

}  // namespace

TEST_CASE("parity: a kinematic body pushes boxes as with SI", "[parity]") {
    Pair p;
    p.build(pusherScene);
    const std::vector<btVector3> start = positionsOf(p.ref);
    p.step(180);  // 3 s: the pusher covers 3 m
    const double pushed = distance(pos(p.ref.body(2)), start[2]);
    const double excess = worstExcessGap(p.ref, p.ours, start);
    // The kinematic body follows its path and nothing pushes it back.
    const btVector3 expectedPusher = start[1] + kPusherVelocity * p.ours.time();
    const double pusherError = distance(pos(p.ours.body(1)), expectedPusher);
    CAPTURE(pushed, excess, pusherError);
    REQUIRE(pushed > 1);  // the first box was pushed
    REQUIRE(excess <= 0);
    // Bullet moves the kinematic body from its motion state: the solver must leave it alone
    // (float rounding of a 3 m path only).
    REQUIRE(pusherError < 1e-5);
}

namespace {

// Two frictionless spheres on a slope falling along -z: one held by a zero z linear factor.
void lockedAxisScene(World& w) {
    const btQuaternion tilt(btVector3(1, 0, 0), btScalar(30 * SIMD_PI / 180));
    const btVector3 normal = quatRotate(tilt, btVector3(0, 1, 0));
    BodyOptions ground = World::groundOptions();
    ground.friction = 0;
    w.addGround(ground, tilt);
    BodyOptions slick;
    slick.friction = 0;
    btRigidBody* locked = w.addSphere(btScalar(0.5), 1, at(normal * btScalar(0.5)), slick);
    locked->setLinearFactor(btVector3(1, 1, 0));
    w.addSphere(btScalar(0.5), 1, at(normal * btScalar(0.5) + btVector3(3, 0, 0)), slick);
}

}  // namespace

TEST_CASE("parity: a zero linear factor on one axis holds the body on it as with SI", "[parity]") {
    Pair p;
    p.build(lockedAxisScene);
    const std::vector<btVector3> start = positionsOf(p.ref);
    p.step(60);
    const double freeSlid = distance(pos(p.ref.body(2)), start[2]);
    const double lockedZ = std::fabs(pos(p.ours.body(1)).z() - start[1].z());
    const double excess = worstExcessGap(p.ref, p.ours, start);
    CAPTURE(freeSlid, lockedZ, pos(p.ref.body(1)).y() - start[1].y(), pos(p.ours.body(1)).y() - start[1].y(), excess);
    REQUIRE(freeSlid > 1);  // without the factor the sphere slides down the slope
    // Every impulse is multiplied by the factor: 0 on z leaves z exactly where it was; 1e-6 m
    // allows only rounding.
    REQUIRE(lockedZ < 1e-6);
    REQUIRE(std::fabs(p.ours.body(1)->getLinearVelocity().z()) < 1e-6);
    REQUIRE(excess <= 0);
}

TEST_CASE("parity: two worlds with two solvers in one process each match SI", "[parity]") {
    Pair a, b;
    a.build([](World& w) {
        w.addGround();
        BodyOptions slider;
        slider.linearVelocity = btVector3(3, 0, 0);
        w.addUnitBox(btVector3(0, btScalar(0.5), 0), slider);
        w.addUnitBox(btVector3(0, btScalar(0.5), 3));
    });
    b.build([](World& w) {
        w.addGround();
        const btVector3 half(btScalar(0.5), btScalar(0.5), btScalar(0.5));
        for (int i = 0; i < 4; ++i) w.addBox(half, 2, at(btVector3(btScalar(2 * i), btScalar(0.5), 0)));
        w.addBox(half, 2, at(btVector3(0, btScalar(1.5), 0)));
    });
    const std::vector<btVector3> startA = positionsOf(a.ref), startB = positionsOf(b.ref);
    for (int i = 0; i < 90; ++i) {  // interleaved: each solver's state must stay its own
        a.step();
        b.step();
    }
    const double excessA = worstExcessGap(a.ref, a.ours, startA);
    const double excessB = worstExcessGap(b.ref, b.ours, startB);
    CAPTURE(excessA, excessB);
    REQUIRE(distance(pos(a.ref.body(1)), startA[1]) > 0.5);  // world a's slider moved
    REQUIRE(excessA <= 0);
    REQUIRE(excessB <= 0);
    if (a.ours.openCL() && b.ours.openCL()) {
        // Each solver reports its own world's contacts.
        CHECK(a.ours.openCL()->getLastStats().numContactPoints == a.ours.numContactPoints());
        CHECK(b.ours.openCL()->getLastStats().numContactPoints == b.ours.numContactPoints());
    }
}

TEST_CASE("a residual threshold that is never reached changes nothing, with body factors other than 1",
          "[solve][factors]") {
    // A box with linear factor 0.5 on y and angular factor 0.5 dropped corner first: the solve
    // scales impulses by the factors only without SOLVER_SIMD, as SI. Tracking the residual
    // (m_leastSquaresResidualThreshold > 0) must not change that: it once did.
    auto run = [](btScalar threshold, bool simd) {
        World w(SolverKind::OpenCL);
        w.addGround();
        btRigidBody* box = w.addUnitBox(btVector3(0, 2, 0));
        box->setWorldTransform(at(btVector3(0, 2, 0), btQuaternion(btVector3(1, 0, 1).normalized(), 0.6f)));
        box->setLinearFactor(btVector3(1, btScalar(0.5), 1));
        box->setAngularFactor(btScalar(0.5));
        w.info().m_leastSquaresResidualThreshold = threshold;
        if (!simd) w.info().m_solverMode &= ~SOLVER_SIMD;
        for (int s = 0; s < 90; ++s) w.step();
        return std::make_pair(box->getWorldTransform(), box->getLinearVelocity());
    };
    for (const bool simd : {true, false}) {
        INFO("SOLVER_SIMD " << simd);
        const auto plain = run(0, simd), tracked = run(btScalar(1e-30), simd);
        CHECK(distance(plain.first.getOrigin(), tracked.first.getOrigin()) < 1e-6);
        CHECK(distance(plain.second, tracked.second) < 1e-6);
    }
}
