// What solveGroup refuses before anything is enqueued or written, and how it names it: a
// non-finite field of a body (by its world index), of a contact point (by the world indices of
// its manifold's objects) or of the solver settings (by field name), negative counts, null arrays
// and null elements. Each refused step leaves the world byte-for-byte as it was; the solver then
// steps on.
#include "ScopedEnv.h"
#include "SettledPile.h"
#include "WorldSnapshot.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

using namespace testworld;

namespace {

const btScalar kNaN = std::numeric_limits<btScalar>::quiet_NaN();
const btScalar kInf = std::numeric_limits<btScalar>::infinity();

// SettledPile (SettledPile.h) with a solver of ours that validates every step.
struct OurPile {
    btOpenCLConstraintSolver solver{validatingConfig()};
    SettledPile pile{solver};
};

// Runs a step that must be refused with a btOpenCLSolverError holding every one of `pieces`, and
// leave every body and manifold byte-for-byte as it was.
void requireRefused(SettledPile& p, const btContactSolverInfo& info, const std::vector<std::string>& pieces) {
    const WorldSnapshot before = WorldSnapshot::of(p.w.dyn());
    std::string message;
    try {
        p.solve(info);
    } catch (const btOpenCLSolverError& e) {
        message = e.what();
    }
    INFO("message: " << message);
    REQUIRE_FALSE(message.empty());
    for (const std::string& piece : pieces) CHECK(message.find(piece) != std::string::npos);
    CHECK(before.differenceFrom(WorldSnapshot::of(p.w.dyn())) == "");
}

// Solves the world's objects and `joint` with the world's solver alone (a world's step changes
// velocities before its solver runs): the step must be refused with a btOpenCLSolverError
// holding every one of `pieces`, and the world left byte for byte as it was.
void requireJointRefused(World& w, btTypedConstraint* joint, const std::vector<std::string>& pieces) {
    btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
    btTypedConstraint* joints[] = {joint};
    const WorldSnapshot before = WorldSnapshot::of(w.dyn());
    std::string message;
    try {
        w.dyn().getConstraintSolver()->solveGroup(&objects[0], objects.size(), nullptr, 0, joints, 1,
                                                  w.dyn().getSolverInfo(), nullptr, nullptr);
    } catch (const btOpenCLSolverError& e) {
        message = e.what();
    }
    INFO("message: " << message);
    REQUIRE_FALSE(message.empty());
    for (const std::string& piece : pieces) CHECK(message.find(piece) != std::string::npos);
    CHECK(before.differenceFrom(WorldSnapshot::of(w.dyn())) == "");
}

// Runs `check` on a world of our solver (validating) with a ground, with and without
// fallbackToBullet: bad input is refused either way.
void withAndWithoutFallback(const std::function<void(World&)>& check) {
    for (const bool fallback : {false, true}) {
        INFO("fallbackToBullet " << fallback);
        btOpenCLSolverConfig config = validatingConfig();
        config.fallbackToBullet = fallback;
        World w(SolverKind::OpenCL, config);
        w.addGround();
        check(w);
    }
}

// A joint whose getInfo1 asks for a negative number of rows.
class NegativeRowsJoint : public btTypedConstraint {
public:
    NegativeRowsJoint(btRigidBody& a, btRigidBody& b) : btTypedConstraint(POINT2POINT_CONSTRAINT_TYPE, a, b) {}
    void getInfo1(btConstraintInfo1* info) override {
        info->m_numConstraintRows = -3;
        info->nub = 9;
    }
    void getInfo2(btConstraintInfo2*) override {}
    void setParam(int, btScalar, int) override {}
    btScalar getParam(int, int) const override { return 0; }
};

std::string bodyAt(const btCollisionObject* o) { return "at index " + std::to_string(o->getWorldArrayIndex()) + " of"; }
std::string pointOf(const btPersistentManifold* m) {
    return "between the objects at indices " + std::to_string(m->getBody0()->getWorldArrayIndex()) + " and " +
           std::to_string(m->getBody1()->getWorldArrayIndex());
}

}  // namespace

TEST_CASE("a non-finite field of a body is refused, naming the body by its world index", "[errors][input]") {
    OurPile our;
    SettledPile& p = our.pile;
    btRigidBody& b = *p.top;
    struct Field {
        const char* name;  // as the message names it
        std::function<btScalar&()> ref;
    };
    const std::vector<Field> fields = {
        {"position", [&]() -> btScalar& { return b.getWorldTransform().getOrigin()[1]; }},
        {"rotation", [&]() -> btScalar& { return b.getWorldTransform().getBasis()[1][2]; }},
        {"linear velocity", [&]() -> btScalar& { return const_cast<btVector3&>(b.getLinearVelocity())[0]; }},
        {"angular velocity", [&]() -> btScalar& { return const_cast<btVector3&>(b.getAngularVelocity())[2]; }},
        {"total force", [&]() -> btScalar& { return const_cast<btVector3&>(b.getTotalForce())[1]; }},
        {"total torque", [&]() -> btScalar& { return const_cast<btVector3&>(b.getTotalTorque())[0]; }},
        {"local inverse inertia", [&]() -> btScalar& { return const_cast<btVector3&>(b.getInvInertiaDiagLocal())[2]; }},
        {"world inverse inertia tensor",
         [&]() -> btScalar& { return const_cast<btMatrix3x3&>(b.getInvInertiaTensorWorld())[2][0]; }},
        {"linear factor", [&]() -> btScalar& { return const_cast<btVector3&>(b.getLinearFactor())[1]; }},
        {"angular factor", [&]() -> btScalar& { return const_cast<btVector3&>(b.getAngularFactor())[0]; }},
    };
    for (const Field& f : fields)
        for (const btScalar bad : {kNaN, kInf, -kInf}) {
            INFO(f.name << " = " << bad);
            btScalar& value = f.ref();
            const btScalar good = value;
            value = bad;
            requireRefused(p, p.w.stepInfo(), {"non-finite", bodyAt(&b), f.name});
            value = good;
        }
    // A NaN mass (setMassProps) makes the inverse mass NaN.
    const btVector3 inertia(btScalar(1) / 6, btScalar(1) / 6, btScalar(1) / 6);
    b.setMassProps(kNaN, inertia);
    requireRefused(p, p.w.stepInfo(), {"non-finite", bodyAt(&b), "inverse mass"});
    b.setMassProps(1, inertia);
    // All restored: the step is solved.
    p.solve(p.w.stepInfo());
    CHECK(our.solver.getLastStats().numContactPoints > 0);
}

TEST_CASE("a negative mass or inertia is refused, naming the body, with or without the fallback", "[errors][input]") {
    // Bullet's solver takes either without a word and throws the body and its neighbours about.
    for (const bool fallback : {false, true}) {
        INFO("fallbackToBullet " << fallback);
        btOpenCLSolverConfig config = validatingConfig();
        config.fallbackToBullet = fallback;
        btOpenCLConstraintSolver solver(config);
        SettledPile p(solver);
        btRigidBody& b = *p.top;
        const btVector3 inertia(btScalar(1) / 6, btScalar(1) / 6, btScalar(1) / 6);
        b.setMassProps(-1, inertia);
        requireRefused(p, p.w.stepInfo(), {"negative inverse mass", bodyAt(&b)});
        b.setMassProps(1, btVector3(inertia.x(), -inertia.y(), inertia.z()));
        b.updateInertiaTensor();
        requireRefused(p, p.w.stepInfo(), {"negative local inverse inertia", bodyAt(&b)});
        b.setMassProps(1, inertia);
        b.updateInertiaTensor();
        p.solve(p.w.stepInfo());
        CHECK(solver.getLastStats().numContactPoints > 0);
        CHECK(solver.getLastStats().numFallbackSteps == 0);
    }
}

TEST_CASE("a non-finite field of a contact point is refused, naming the two objects of its manifold", "[errors][input]") {
    OurPile our;
    SettledPile& p = our.pile;
    btPersistentManifold* m = p.manifoldOfTop();
    REQUIRE(m != nullptr);
    btManifoldPoint& cp = m->getContactPoint(m->getNumContacts() - 1);  // the last point read
    struct Field {
        const char* name;
        std::function<btScalar&()> ref;
        int flags = 0;       // contact point flags under which the field is read
        int solverMode = 0;  // solver mode bits ditto
    };
    const int cached = SOLVER_ENABLE_FRICTION_DIRECTION_CACHING;
    const int initialized = BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
    const std::vector<Field> fields = {
        {"m_positionWorldOnA", [&]() -> btScalar& { return cp.m_positionWorldOnA[0]; }},
        {"m_positionWorldOnB", [&]() -> btScalar& { return cp.m_positionWorldOnB[1]; }},
        {"m_normalWorldOnB", [&]() -> btScalar& { return cp.m_normalWorldOnB[2]; }},
        {"distance", [&]() -> btScalar& { return cp.m_distance1; }},
        {"m_combinedFriction", [&]() -> btScalar& { return cp.m_combinedFriction; }},
        {"m_combinedRestitution", [&]() -> btScalar& { return cp.m_combinedRestitution; }},
        {"m_combinedRollingFriction", [&]() -> btScalar& { return cp.m_combinedRollingFriction; }},
        {"m_combinedSpinningFriction", [&]() -> btScalar& { return cp.m_combinedSpinningFriction; }},
        {"m_appliedImpulse", [&]() -> btScalar& { return cp.m_appliedImpulse; }, 0, SOLVER_USE_WARMSTARTING},
        {"m_contactCFM", [&]() -> btScalar& { return cp.m_contactCFM; }, BT_CONTACT_FLAG_HAS_CONTACT_CFM},
        {"m_contactERP", [&]() -> btScalar& { return cp.m_contactERP; }, BT_CONTACT_FLAG_HAS_CONTACT_ERP},
        {"m_combinedContactStiffness1", [&]() -> btScalar& { return cp.m_combinedContactStiffness1; },
         BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING},
        {"m_combinedContactDamping1", [&]() -> btScalar& { return cp.m_combinedContactDamping1; },
         BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING},
        {"m_lateralFrictionDir1", [&]() -> btScalar& { return cp.m_lateralFrictionDir1[0]; }, initialized, cached},
        {"m_lateralFrictionDir2", [&]() -> btScalar& { return cp.m_lateralFrictionDir2[1]; }, initialized, cached},
        {"m_contactMotion1", [&]() -> btScalar& { return cp.m_contactMotion1; }, initialized, cached},
        {"m_contactMotion2", [&]() -> btScalar& { return cp.m_contactMotion2; }, initialized, cached},
        {"m_frictionCFM", [&]() -> btScalar& { return cp.m_frictionCFM; }, initialized, cached},
    };
    const int flagsBefore = cp.m_contactPointFlags;
    for (const Field& f : fields)
        for (const btScalar bad : {kNaN, -kInf}) {  // (+Inf distance: beyond reach, not solved, as in SI)
            INFO(f.name << " = " << bad);
            btContactSolverInfo info = p.w.stepInfo();
            info.m_solverMode |= f.solverMode;
            cp.m_contactPointFlags = flagsBefore | f.flags;
            btScalar& value = f.ref();
            const btScalar good = value;
            value = bad;
            requireRefused(p, info, {"non-finite", pointOf(m), f.name});
            value = good;
            cp.m_contactPointFlags = flagsBefore;
        }
    p.solve(p.w.stepInfo());
    CHECK(our.solver.getLastStats().numContactPoints > 0);
}

// Anisotropic friction is read of both objects of a manifold, a static one too (it is not a
// solver body): a non-finite factor there is refused, naming the object; without the flag the
// factors are not read.
TEST_CASE("a non-finite anisotropic friction is refused and names its object (static or dynamic)", "[errors][input]") {
    OurPile our;
    SettledPile& p = our.pile;
    btPersistentManifold* m = p.manifoldOfTop();
    REQUIRE(m != nullptr);
    btCollisionObject* ground = nullptr;  // what a box of the lower layer rests on
    for (int i = 0; i < p.w.dispatcher().getNumManifolds() && !ground; ++i) {
        btPersistentManifold* g = p.w.dispatcher().getManifoldByIndexInternal(i);
        for (const btCollisionObject* o : {g->getBody0(), g->getBody1()})
            if (o->isStaticObject() && g->getNumContacts() > 0) ground = const_cast<btCollisionObject*>(o);
    }
    REQUIRE(ground != nullptr);
    for (btCollisionObject* o : {static_cast<btCollisionObject*>(p.top), ground}) {
        INFO("static: " << o->isStaticObject());
        o->setAnisotropicFriction(btVector3(1, kNaN, 1), btCollisionObject::CF_ANISOTROPIC_FRICTION);
        requireRefused(p, p.w.stepInfo(), {"non-finite", bodyAt(o), "anisotropic friction"});
        o->setAnisotropicFriction(btVector3(1, kNaN, 1), 0);  // the same factors, the flag off: not read
        REQUIRE_NOTHROW(p.solve(p.w.stepInfo()));
        o->setAnisotropicFriction(btVector3(1, 1, 1), 0);
    }
    p.solve(p.w.stepInfo());
    CHECK(our.solver.getLastStats().numContactPoints > 0);
}

TEST_CASE("a contact point field the step does not read may be anything", "[input]") {
    // Bullet leaves such fields as they are; refusing them would refuse valid worlds.
    OurPile our;
    SettledPile& p = our.pile;
    btPersistentManifold* m = p.manifoldOfTop();
    REQUIRE(m != nullptr);
    btManifoldPoint& cp = m->getContactPoint(0);
    cp.m_contactPointFlags = 0;
    cp.m_contactCFM = kNaN;  // read only with BT_CONTACT_FLAG_HAS_CONTACT_CFM
    cp.m_contactMotion1 = kNaN;  // read only for cached friction directions
    btContactSolverInfo info = p.w.stepInfo();
    info.m_solverMode &= ~SOLVER_USE_WARMSTARTING;
    cp.m_appliedImpulse = kNaN;  // read only when warm starting
    info.m_warmstartingFactor = kNaN;
    info.m_splitImpulse = 0;
    info.m_splitImpulseTurnErp = kNaN;  // read only with split impulse
    REQUIRE_NOTHROW(p.solve(info));
    CHECK(std::isfinite(p.top->getLinearVelocity().y()));
}

TEST_CASE("a non-finite or out-of-range solver setting is refused, naming the field", "[errors][input]") {
    OurPile our;
    SettledPile& p = our.pile;
    struct Setting {
        const char* name;
        std::function<void(btContactSolverInfo&, btScalar)> set;
    };
    const std::vector<Setting> settings = {
        {"m_timeStep", [](btContactSolverInfo& i, btScalar v) { i.m_timeStep = v; }},
        {"m_erp2", [](btContactSolverInfo& i, btScalar v) { i.m_erp2 = v; }},
        {"m_sor", [](btContactSolverInfo& i, btScalar v) { i.m_sor = v; }},
        {"m_globalCfm", [](btContactSolverInfo& i, btScalar v) { i.m_globalCfm = v; }},
        {"m_warmstartingFactor", [](btContactSolverInfo& i, btScalar v) { i.m_warmstartingFactor = v; }},
        {"m_linearSlop", [](btContactSolverInfo& i, btScalar v) { i.m_linearSlop = v; }},
        {"m_restitutionVelocityThreshold", [](btContactSolverInfo& i, btScalar v) { i.m_restitutionVelocityThreshold = v; }},
        {"m_frictionERP", [](btContactSolverInfo& i, btScalar v) { i.m_frictionERP = v; }},
        {"m_leastSquaresResidualThreshold",
         [](btContactSolverInfo& i, btScalar v) { i.m_leastSquaresResidualThreshold = v; }},
        {"m_maxGyroscopicForce", [](btContactSolverInfo& i, btScalar v) { i.m_maxGyroscopicForce = v; }},
        {"m_splitImpulsePenetrationThreshold",
         [](btContactSolverInfo& i, btScalar v) { i.m_splitImpulse = 1; i.m_splitImpulsePenetrationThreshold = v; }},
        {"m_splitImpulseTurnErp", [](btContactSolverInfo& i, btScalar v) { i.m_splitImpulse = 1; i.m_splitImpulseTurnErp = v; }},
    };
    for (const Setting& s : settings)
        for (const btScalar bad : {kNaN, kInf, -kInf}) {
            INFO(s.name << " = " << bad);
            btContactSolverInfo info = p.w.stepInfo();
            info.m_solverMode |= SOLVER_USE_WARMSTARTING;
            s.set(info, bad);
            requireRefused(p, info, {s.name});
        }
    btContactSolverInfo info = p.w.stepInfo();
    info.m_timeStep = 0;
    requireRefused(p, info, {"m_timeStep", "positive"});
    info.m_timeStep = -kDt;
    requireRefused(p, info, {"m_timeStep", "positive"});
    info = p.w.stepInfo();
    info.m_numIterations = -1;
    requireRefused(p, info, {"m_numIterations", "negative"});
    p.solve(p.w.stepInfo());
    CHECK(our.solver.getLastStats().numContactPoints > 0);
}

TEST_CASE("negative counts, null arrays and null elements given to solveGroup are a btOpenCLSolverError",
          "[errors][input]") {
    OurPile our;
    SettledPile& p = our.pile;
    const btContactSolverInfo info = p.w.stepInfo();
    btCollisionObject** bodies = p.objects.data();
    btPersistentManifold** manifolds = p.manifolds.data();
    const int nb = int(p.objects.size()), nm = int(p.manifolds.size());
    auto solveGroup = [&](btCollisionObject** b, int numBodies, btPersistentManifold** m, int numManifolds,
                          int numConstraints) {
        our.solver.solveGroup(b, numBodies, m, numManifolds, nullptr, numConstraints, info, nullptr, &p.w.dispatcher());
    };
    CHECK_THROWS_WITH(solveGroup(bodies, -1, manifolds, nm, 0), Catch::Contains("numBodies is -1"));
    CHECK_THROWS_WITH(solveGroup(bodies, nb, manifolds, -2, 0), Catch::Contains("numManifolds is -2"));
    CHECK_THROWS_WITH(solveGroup(bodies, nb, manifolds, nm, -3), Catch::Contains("numConstraints is -3"));
    CHECK_THROWS_WITH(solveGroup(nullptr, nb, manifolds, nm, 0), Catch::Contains("numBodies"));
    CHECK_THROWS_WITH(solveGroup(bodies, nb, nullptr, nm, 0), Catch::Contains("numManifolds"));
    CHECK_THROWS_AS(solveGroup(bodies, nb, manifolds, nm, 1), btOpenCLSolverError);  // a null constraint array
    // A null element: the gather would read through it.
    const WorldSnapshot before = WorldSnapshot::of(p.w.dyn());
    std::vector<btCollisionObject*> someBodies(bodies, bodies + nb);
    someBodies[1] = nullptr;
    CHECK_THROWS_WITH(solveGroup(someBodies.data(), nb, manifolds, nm, 0), Catch::Contains("bodies[1] is null"));
    std::vector<btPersistentManifold*> someManifolds(manifolds, manifolds + nm);
    someManifolds[nm - 1] = nullptr;
    CHECK_THROWS_WITH(solveGroup(bodies, nb, someManifolds.data(), nm, 0),
                      Catch::Contains("manifolds[" + std::to_string(nm - 1) + "] is null"));
    btTypedConstraint* noJoint = nullptr;
    our.solver.prepareSolve(nb, nm);
    CHECK_THROWS_WITH(our.solver.solveGroup(bodies, nb, manifolds, nm, &noJoint, 1, info, nullptr, &p.w.dispatcher()),
                      Catch::Contains("constraints[0] is null"));
    CHECK(before.differenceFrom(WorldSnapshot::of(p.w.dyn())) == "");
    solveGroup(bodies, nb, manifolds, nm, 0);  // outside prepareSolve/allSolved: solved at once
    CHECK(our.solver.getLastStats().numContactPoints > 0);
}

TEST_CASE("a NaN inverse inertia in a world is reported at its body, not at the box it touches", "[errors][input]") {
    // Unchecked, the NaN reached the contact partner through the solve, and the next step's error
    // named the partner.
    World w(SolverKind::OpenCL);
    groundAndPile(w, 20);
    for (int s = 0; s < 30; ++s) w.step();
    btRigidBody* b = w.body(17);
    const btVector3 good = b->getInvInertiaDiagLocal();
    b->setInvInertiaDiagLocal(btVector3(kNaN, good.y(), good.z()));
    b->updateInertiaTensor();
    std::string message;
    try {
        w.step();
    } catch (const btOpenCLSolverError& e) {
        message = e.what();
    }
    INFO("message: " << message);
    CHECK(message.find(bodyAt(b) + " the world has a non-finite") != std::string::npos);
    // Fixed, the world steps on (clearForces: Bullet skipped it when the step threw).
    w.dyn().clearForces();
    b->setInvInertiaDiagLocal(good);
    b->updateInertiaTensor();
    for (int s = 0; s < 10; ++s) w.step();
    for (const btRigidBody* body : w.bodies()) REQUIRE(std::isfinite(body->getLinearVelocity().length()));
}

TEST_CASE("a NaN warm-start impulse in a world is refused, naming the manifold's objects", "[errors][input]") {
    World w(SolverKind::OpenCL);
    groundAndPile(w, 20);
    for (int s = 0; s < 30; ++s) w.step();
    btPersistentManifold* m = nullptr;
    for (btPersistentManifold* candidate : w.manifolds())
        if ((candidate->getBody0() == w.body(17) || candidate->getBody1() == w.body(17)) && candidate->getNumContacts() > 0)
            m = candidate;
    REQUIRE(m != nullptr);
    // Every point: collision detection may replace some of them before the solver runs.
    for (int j = 0; j < m->getNumContacts(); ++j) m->getContactPoint(j).m_appliedImpulse = kNaN;
    CHECK_THROWS_WITH(w.step(), Catch::Contains("m_appliedImpulse") && Catch::Contains(pointOf(m)));
}

TEST_CASE("a disabled joint is skipped, as Bullet's solver skips it", "[input][joints]") {
    // Two boxes dropped on the ground, apart, step bitwise as they do without the joint between
    // them; enabled, the joint is solved, as Bullet's solver solves it.
    auto run = [](bool withJoint, bool enabled, SolverKind kind = SolverKind::OpenCL) {
        World w(kind);
        w.addGround();
        btRigidBody* a = w.addUnitBox(btVector3(0, 2, 0));
        btRigidBody* b = w.addUnitBox(btVector3(3, 3, 0));
        if (withJoint) {
            btPoint2PointConstraint* joint = w.addConstraint(std::make_unique<btPoint2PointConstraint>(
                *a, *b, btVector3(btScalar(1.5), 0, 0), btVector3(btScalar(-1.5), 0, 0)));
            joint->setEnabled(enabled);
        }
        for (int s = 0; s < 60; ++s) w.step();
        std::vector<btTransform> out;
        for (const btRigidBody* body : w.bodies()) out.push_back(body->getWorldTransform());
        return out;
    };
    const std::vector<btTransform> without = run(false, false), disabled = run(true, false);
    REQUIRE(without.size() == disabled.size());
    for (size_t i = 0; i < without.size(); ++i) {
        INFO("body " << i);
        CHECK(std::memcmp(&without[i], &disabled[i], sizeof(btTransform)) == 0);
    }
    CHECK(without[1].getOrigin().y() < btScalar(0.6));  // it fell and landed
    const std::vector<btTransform> enabled = run(true, true), enabledSI = run(true, true, SolverKind::Reference);
    CHECK(std::memcmp(&without[2], &enabled[2], sizeof(btTransform)) != 0);
    for (size_t i = 0; i < enabled.size(); ++i) {
        INFO("body " << i << " with the joint enabled, against SI");
        CHECK((enabled[i].getOrigin() - enabledSI[i].getOrigin()).length() < 0.02);
    }
}

TEST_CASE("a joint with a non-finite pivot is refused, naming the joint, with or without the fallback", "[errors][input][joints]") {
    withAndWithoutFallback([](World& w) {
        btRigidBody* a = w.addUnitBox(btVector3(0, 2, 0));
        btRigidBody* b = w.addUnitBox(btVector3(3, 2, 0));
        btPoint2PointConstraint* joint = w.addConstraint(std::make_unique<btPoint2PointConstraint>(
            *a, *b, btVector3(btScalar(1.5), 0, 0), btVector3(btScalar(-1.5), 0, 0)));
        for (int s = 0; s < 5; ++s) w.step();
        joint->setPivotA(btVector3(kNaN, 0, 0));
        CHECK_THROWS_WITH(w.step(), Catch::Contains("joint 0") && Catch::Contains("non-finite"));
        requireJointRefused(w, joint, {"joint 0", "non-finite"});
    });
}

TEST_CASE("a joint between a body and itself is refused, naming the joint and the body", "[errors][input][joints]") {
    // Unrefused, the solve kept one side's change of the two and flung the body (about 60 m/s a
    // step); Bullet's solver adds both sides' changes. Such a joint means nothing: an error.
    withAndWithoutFallback([](World& w) {
        w.addUnitBox(btVector3(3, btScalar(0.5), 0));
        btRigidBody* box = w.addUnitBox(btVector3(0, btScalar(0.5), 0));
        const btVector3 pivot(btScalar(0.5), btScalar(0.5), 0);
        btPoint2PointConstraint* joint =
            w.addConstraint(std::make_unique<btPoint2PointConstraint>(*box, *box, pivot, pivot));
        const std::string itself = "joins the rigid body at index " + std::to_string(box->getWorldArrayIndex()) +
                                   " of the world to itself";
        CHECK_THROWS_WITH(w.step(), Catch::Contains("joint 0 of the step") && Catch::Contains(itself));
        requireJointRefused(w, joint, {"joint 0 of the step", itself});
        CHECK(w.openCL()->getLastStats().numFallbackSteps == 0);
    });
}

TEST_CASE("a manifold between a body and itself is refused, naming the body", "[errors][input]") {
    OurPile our;
    SettledPile& p = our.pile;
    btPersistentManifold* self = p.w.dispatcher().getNewManifold(p.top, p.top);
    btManifoldPoint point(btVector3(0, btScalar(-0.5), 0), btVector3(0, btScalar(0.5), 0), btVector3(0, 1, 0),
                          btScalar(-0.01));
    point.m_positionWorldOnA = p.top->getWorldTransform() * point.m_localPointA;
    point.m_positionWorldOnB = p.top->getWorldTransform() * point.m_localPointB;
    self->addManifoldPoint(point);
    p.manifolds.push_back(self);
    requireRefused(p, p.w.stepInfo(),
                   {"manifold between the object " + bodyAt(p.top) + " the world and itself"});
    p.manifolds.pop_back();
    p.w.dispatcher().releaseManifold(self);
    p.solve();
    CHECK(our.solver.getLastStats().numContactPoints > 0);
}

TEST_CASE("a joint that asks for a negative number of rows is refused, naming the joint", "[errors][input][joints]") {
    World w(SolverKind::OpenCL);
    w.addGround();
    btRigidBody* a = w.addUnitBox(btVector3(0, btScalar(0.5), 0));
    btRigidBody* b = w.addUnitBox(btVector3(3, btScalar(0.5), 0));
    NegativeRowsJoint* joint = w.addConstraint(std::make_unique<NegativeRowsJoint>(*a, *b));
    requireJointRefused(w, joint, {"joint 0 of the step", "asks for -3 rows"});
    CHECK_THROWS_AS(w.step(), btOpenCLSolverError);
}

TEST_CASE("a device name that matches nothing is reported with where it came from", "[errors][device]") {
    std::string fromEnv, fromConfig;
    {
        const btocl::test::ScopedEnv device("BT_OPENCL_DEVICE", "no-such-device-xyz");
        try {
            btOpenCLConstraintSolver solver;  // config.device empty: the environment decides
        } catch (const btOpenCLSolverError& e) {
            fromEnv = e.what();
        }
        btOpenCLSolverConfig config;
        config.device = "no-such-device-abc";
        try {
            btOpenCLConstraintSolver solver(config);
        } catch (const btOpenCLSolverError& e) {
            fromConfig = e.what();
        }
    }
    INFO("from the environment: " << fromEnv << "\nfrom the config: " << fromConfig);
    CHECK(fromEnv.find("'no-such-device-xyz' (the environment variable BT_OPENCL_DEVICE") != std::string::npos);
    CHECK(fromConfig.find("'no-such-device-abc' (btOpenCLSolverConfig::device)") != std::string::npos);
    CHECK(fromConfig.find("BT_OPENCL_DEVICE") == std::string::npos);
}
