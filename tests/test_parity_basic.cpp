// Parity with btSequentialImpulseConstraintSolver on single bodies: free fall, a tumbling box
// landing, resting contact, sliding friction on flat ground and on a slope, restitution.
#include "TestWorld.h"

#include <cfloat>

using namespace testworld;

namespace {

// Accumulated rounding after n steps: each step adds at most a few (4) roundings of relative
// size FLT_EPSILON to each state value, and these add up at most linearly over the steps.
double floatTolerance(int steps, double magnitude) {
    return steps * 4.0 * FLT_EPSILON * std::max(magnitude, 1.0);
}

void requireVectorsClose(const btVector3& a, const btVector3& b, int steps, const char* what) {
    for (int k = 0; k < 3; ++k) {
        const double tol = floatTolerance(steps, std::max(std::fabs(a[k]), std::fabs(b[k])));
        INFO(what << "[" << k << "]: SI " << a[k] << ", ours " << b[k] << ", tolerance " << tol);
        REQUIRE(std::fabs(a[k] - b[k]) <= tol);
    }
}

// Speed along the unit direction d.
btScalar speedAlong(const btRigidBody* b, const btVector3& d) { return b->getLinearVelocity().dot(d); }

}  // namespace

TEST_CASE("parity: free fall without contacts matches SI to float precision", "[parity]") {
    Pair p;
    p.build([](World& w) {
        BodyOptions tumbling;  // three distinct inertias: SI adds the implicit gyroscopic impulse
        tumbling.linearVelocity = btVector3(1, 5, -2);
        tumbling.angularVelocity = btVector3(3, -1, 2);
        w.addBox(btVector3(btScalar(0.3), btScalar(0.5), btScalar(0.8)), 2, at(btVector3(0, 10, 0)), tumbling);
        BodyOptions thrown;
        thrown.linearVelocity = btVector3(-3, 0, 1);
        w.addSphere(btScalar(0.4), btScalar(0.5), at(btVector3(5, 20, 5)), thrown);
        w.addBox(btVector3(1, 1, 1), 10, at(btVector3(-5, 30, 0), btQuaternion(btVector3(1, 1, 0).normalized(), 0.7f)));
    });
    const int steps = 60;
    p.step(steps);
    for (size_t i = 0; i < p.ref.bodies().size(); ++i) {
        const btRigidBody* a = p.ref.body(i);
        const btRigidBody* b = p.ours.body(i);
        INFO("body " << i);
        requireVectorsClose(pos(a), pos(b), steps, "position");
        requireVectorsClose(a->getLinearVelocity(), b->getLinearVelocity(), steps, "linear velocity");
        requireVectorsClose(a->getAngularVelocity(), b->getAngularVelocity(), steps, "angular velocity");
        const btQuaternion qa = a->getOrientation(), qb = b->getOrientation();
        for (int k = 0; k < 4; ++k) REQUIRE(std::fabs(qa[k] - qb[k]) <= floatTolerance(steps, 1));
    }
    // The scene must fall as physics says, or the comparison above proves nothing.
    const double t = steps * kDt;
    REQUIRE(p.ref.body(1)->getLinearVelocity().y() == Approx(-kG * t).epsilon(1e-4));
}

TEST_CASE("a box dropped on the ground moves as with SI", "[parity][si]") {
    // The bound below is no order tolerance: SI with its order shuffled (=shuffle) parts by 2 mm
    // here, so under BTOCL_PARITY_REFERENCE_ONLY=shuffle the candidate keeps SI's own order.
    Pair p(candidateKind() == SolverKind::ReferenceShuffled ? SolverKind::Reference : candidateKind());
    p.build([](World& w) {
        w.addGround();
        w.addUnitBox(btVector3(0, 2, 0))->setAngularVelocity(btVector3(1, 2, 0.5f));
    });
    double gap = 0;
    p.run(180, [&](World& r, World& o) { gap = std::max(gap, double(maxPositionGap(r, o))); });
    // One body: the rows and their order are SI's; only float rounding differs (fused multiply-adds).
    INFO("max position gap " << gap);
    CHECK(gap < 1e-3f);
    CHECK(std::fabs(pos(p.ours.body(1)).y() - 0.5f) < 0.02f);
}

TEST_CASE("parity: a box resting on the ground stays and carries m*g*dt per step", "[parity]") {
    const btScalar mass = 3;
    Pair p;
    p.build([&](World& w) {
        w.addGround();
        w.addBox(btVector3(btScalar(0.5), btScalar(0.5), btScalar(0.5)), mass, at(btVector3(0, btScalar(0.5), 0)));
    });
    const btVector3 start = pos(p.ref.body(1));
    const double expected = mass * kG * kDt;
    const int steps = 600;  // 10 s
    double worstRef = 0, worstOurs = 0, worstGap = 0;
    p.run(steps, [&](World& r, World& o) {
        if (r.stepsTaken() <= 30) return;  // the first half second settles the contact
        const double ir = r.normalImpulseBetween(r.body(0), r.body(1));
        const double io = o.normalImpulseBetween(o.body(0), o.body(1));
        worstRef = std::max(worstRef, std::fabs(ir - expected));
        worstOurs = std::max(worstOurs, std::fabs(io - expected));
        worstGap = std::max(worstGap, std::fabs(io - ir));
    });
    const double driftRef = distance(pos(p.ref.body(1)), start);
    const double driftOurs = distance(pos(p.ours.body(1)), start);
    CAPTURE(expected, worstRef, worstOurs, worstGap, driftRef, driftOurs);
    REQUIRE(driftRef < 1e-3);
    REQUIRE(driftOurs < 1e-3);
    REQUIRE(p.ours.numContactPointsBetween(p.ours.body(0), p.ours.body(1)) == 4);
    // At rest the normal impulses cancel gravity's m*g*dt each step. 10 warm-started Gauss-Seidel
    // iterations leave a residual far below 1% of it on four points under one body.
    REQUIRE(worstRef <= 0.01 * expected);
    REQUIRE(worstOurs <= 0.01 * expected);
    REQUIRE(worstGap <= 0.01 * expected);
}

TEST_CASE("parity: a box sliding on flat ground slows at mu*g as with SI", "[parity]") {
    const btScalar mu = btScalar(0.5);  // the ground's friction is 1: the product is mu
    Pair p;
    p.build([&](World& w) {
        w.addGround();
        BodyOptions o;
        o.friction = mu;
        o.linearVelocity = btVector3(5, 0, 0);
        w.addUnitBox(btVector3(0, btScalar(0.5), 0), o);
    });
    // Deceleration from the speeds at steps 6 and 36 (the box stops near step 61).
    p.step(6);
    const double r0 = p.ref.body(1)->getLinearVelocity().x(), o0 = p.ours.body(1)->getLinearVelocity().x();
    p.step(30);
    const double span = 30 * kDt;
    const double aRef = (r0 - p.ref.body(1)->getLinearVelocity().x()) / span;
    const double aOurs = (o0 - p.ours.body(1)->getLinearVelocity().x()) / span;
    const double analytic = mu * kG;
    CAPTURE(analytic, aRef, aOurs);
    // 5%: Coulomb friction is exact in the limit; the discrete contact patch and one friction
    // direction per point leave a few percent.
    REQUIRE(closeRel(aRef, analytic, 0.05, 0));
    REQUIRE(closeRel(aOurs, analytic, 0.05, 0));
    REQUIRE(closeRel(aOurs, aRef, 0.05, 0));
    // Sideways the box must not wander: friction acts along the relative velocity; only the order
    // in which the four points are solved turns the box a little, far below 1% of its speed.
    REQUIRE(std::fabs(p.ours.body(1)->getLinearVelocity().z()) < 0.01 * 5);
}

namespace {

// A box of friction mu on a slope tilted by `degrees` about z; returns the pair after `steps`
// and the downhill unit direction.
struct SlopeRun {
    btVector3 downhill;
    btVector3 startRef, startOurs;
};

SlopeRun buildSlope(Pair& p, double degrees, btScalar mu) {
    const btQuaternion tilt(btVector3(0, 0, 1), btScalar(degrees * SIMD_PI / 180.0));
    const btVector3 normal = quatRotate(tilt, btVector3(0, 1, 0));
    p.build([&](World& w) {
        w.addGround(World::groundOptions(), tilt);
        BodyOptions o;
        o.friction = mu;
        w.addBox(btVector3(btScalar(0.5), btScalar(0.5), btScalar(0.5)), 1, at(normal * btScalar(0.5), tilt), o);
    });
    SlopeRun s;
    s.downhill = quatRotate(tilt, btVector3(-1, 0, 0));  // tilting about +z lowers the -x side
    s.startRef = pos(p.ref.body(1));
    s.startOurs = pos(p.ours.body(1));
    return s;
}

}  // namespace

TEST_CASE("parity: a box on a slope below atan(mu) sticks as with SI", "[parity]") {
    const btScalar mu = btScalar(0.5);  // atan(0.5) = 26.6 degrees
    Pair p;
    const SlopeRun s = buildSlope(p, 20, mu);
    p.step(120);
    const double slipRef = distance(pos(p.ref.body(1)), s.startRef);
    const double slipOurs = distance(pos(p.ours.body(1)), s.startOurs);
    CAPTURE(slipRef, slipOurs);
    // Static friction holds: a sliding box would cover g(sin t - mu cos t) t^2/2 > 0 only above
    // atan(mu); 5 mm in 2 s allows the settling of the contact, not sliding.
    REQUIRE(slipRef < 5e-3);
    REQUIRE(slipOurs < 5e-3);
}

TEST_CASE("parity: a box on a slope above atan(mu) slides at g(sin t - mu cos t) as SI", "[parity]") {
    const btScalar mu = btScalar(0.5);
    const double degrees = 35;
    Pair p;
    const SlopeRun s = buildSlope(p, degrees, mu);
    p.step(10);
    const double r0 = speedAlong(p.ref.body(1), s.downhill), o0 = speedAlong(p.ours.body(1), s.downhill);
    p.step(60);
    const double span = 60 * kDt;
    const double aRef = (speedAlong(p.ref.body(1), s.downhill) - r0) / span;
    const double aOurs = (speedAlong(p.ours.body(1), s.downhill) - o0) / span;
    const double t = degrees * SIMD_PI / 180.0;
    const double analytic = kG * (std::sin(t) - mu * std::cos(t));
    CAPTURE(analytic, aRef, aOurs);
    // Against the physics: the error lies in the friction term (as on flat ground, 5% of it);
    // the net acceleration is a small difference of two large terms, so bound it by the friction.
    const double friction = mu * kG * std::cos(t);
    REQUIRE(std::fabs(aRef - analytic) <= 0.05 * friction);
    REQUIRE(std::fabs(aOurs - analytic) <= 0.05 * friction);
    // Against SI: 5% of the net acceleration, as the brief asks (the ordering of Gauss-Seidel
    // changes the friction by far less).
    REQUIRE(closeRel(aOurs, aRef, 0.05, 0));
}

TEST_CASE("parity: a sphere with restitution 0.5 rebounds as with SI", "[parity]") {
    const btScalar e = btScalar(0.5);  // the ground's restitution is 1: the product is e
    Pair p;
    p.build([&](World& w) {
        w.addGround();
        BodyOptions o;
        o.restitution = e;
        w.addSphere(btScalar(0.5), 1, at(btVector3(0, 3, 0)), o);
    });
    double impactRef = 0, impactOurs = 0, reboundRef = 0, reboundOurs = 0, apexRef = 0, apexOurs = 0;
    p.run(120, [&](World& r, World& o) {
        const double vr = r.body(1)->getLinearVelocity().y(), vo = o.body(1)->getLinearVelocity().y();
        impactRef = std::min(impactRef, vr);
        impactOurs = std::min(impactOurs, vo);
        reboundRef = std::max(reboundRef, vr);
        reboundOurs = std::max(reboundOurs, vo);
        if (reboundRef > 0) apexRef = std::max(apexRef, double(pos(r.body(1)).y()));
        if (reboundOurs > 0) apexOurs = std::max(apexOurs, double(pos(o.body(1)).y()));
    });
    CAPTURE(impactRef, impactOurs, reboundRef, reboundOurs, apexRef, apexOurs);
    // The scene must bounce at about e (the contact starts between steps, so not exactly).
    REQUIRE(closeRel(reboundRef / -impactRef, e, 0.15, 0));
    // 5%: restitution comes from the relative normal velocity at setup, the same input both ways.
    REQUIRE(closeRel(reboundOurs, reboundRef, 0.05, 0));
    REQUIRE(closeRel(apexOurs - 0.5, apexRef - 0.5, 0.05, 0));
}
