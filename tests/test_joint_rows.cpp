// Joint rows as btSequentialImpulseConstraintSolver makes them: ours (JointRows, from the shared
// row math of kernels/row_setup.h) against the rows of Bullet's own solver stopped after its
// set-up, for every joint type; then the host reference solve (row_solve.h) and the joints'
// write-back (JointWriteBack) against SI's full solve, step by step.
#include "BulletConversions.h"
#include "BulletGather.h"
#include "GatherAndSolve.h"
#include "HostSolve.h"
#include "JointRows.h"
#include "JointScenes.h"
#include "JointWriteBack.h"
#include "SerialLayout.h"
#include "Scenes.h"
#include "StepPlan.h"
#include "StepPolicy.h"
#include "StepProblem.h"
#include "row_setup.h"
#include "row_solve.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <map>

using namespace btocl;
using namespace btocl::test;
using testworld::SolverKind;
using testworld::World;

namespace {

// Bullet's solver, stopped after its set-up: its joint rows and solver bodies as it made them.
class SetupOnlySI : public btSequentialImpulseConstraintSolver {
public:
    void setUp(World& w, std::vector<btTypedConstraint*>& joints, const btContactSolverInfo& info) {
        btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
        solveGroupCacheFriendlySetup(&objects[0], objects.size(), nullptr, 0, joints.data(), int(joints.size()), info,
                                     nullptr);
    }
    const btConstraintArray& jointRows() const { return m_tmpSolverNonContactConstraintPool; }
    const btSolverBody& body(int id) const { return m_tmpSolverBodyPool[id]; }
};

// One step's bodies and joint rows, gathered as the solver will: bodies first, then each joint's
// two solver bodies (a kinematic one may join here), then the rows from the finished records.
struct GatheredJoints {
    StepProblem problem;
    std::vector<btRigidBody*> original;     // per solver body (BulletStep::original)
    std::vector<btTransform> worldTransforms;  // per solver body (BulletStep::worldTransforms)
    std::vector<btVector3> boxLo, boxHi;       // per solver body (BulletStep::boxLo, boxHi)
    JointRowSet joints;
};

GatheredJoints gatherJoints(btCollisionObject** objects, int numObjects, btPersistentManifold** manifolds,
                            int numManifolds, btTypedConstraint** joints, int numJoints,
                            const btContactSolverInfo& info) {
    StepGatherer g;
    g.begin(info, RowSetup::Host);
    g.addBodies(objects, numObjects);
    g.addManifolds(manifolds, numManifolds);
    std::vector<JointBodies> bodies(size_t(std::max(0, numJoints)));
    for (int i = 0; i < numJoints; ++i)
        bodies[size_t(i)] = {g.solverBodyOf(&joints[i]->getRigidBodyA()), g.solverBodyOf(&joints[i]->getRigidBodyB())};
    GatheredJoints out;
    out.problem = g.finish();
    out.original = g.bullet().original;
    out.worldTransforms = g.bullet().worldTransforms;
    out.boxLo = g.bullet().boxLo;
    out.boxHi = g.bullet().boxHi;
    out.joints = setUpJointRows(joints, numJoints, bodies.data(), out.problem.bodies, info);
    g.releaseBodies();
    return out;
}

GatheredJoints gatherJoints(World& w, std::vector<btTypedConstraint*>& joints, const btContactSolverInfo& info) {
    btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
    std::vector<btPersistentManifold*> manifolds = w.manifolds();
    return gatherJoints(&objects[0], objects.size(), manifolds.data(), int(manifolds.size()), joints.data(),
                        int(joints.size()), info);
}

// The largest relative gap between one of SI's joint rows and ours over every field the solve
// reads; `same` is cleared when they differ in bodies or iteration count.
float rowGap(const btSolverConstraint& si, const btoclRow& r, const SetupOnlySI& bullet,
             const std::vector<btRigidBody*>& original, bool& same) {
    if (bullet.body(si.m_solverBodyIdA).m_originalBody != original[size_t(r.bodyA)] ||
        bullet.body(si.m_solverBodyIdB).m_originalBody != original[size_t(r.bodyB)] ||
        si.m_overrideNumSolverIterations != BTOCL_ROW_ITERATIONS(r) || r.frictionIndex != -1)
        same = false;
    return fieldGap(si, r);
}

}  // namespace

TEST_CASE("joint rows of every joint type are set up as SI sets them up", "[joints][setup]") {
    auto mode = GENERATE(0, 1, 2);
    CAPTURE(mode);
    World w(SolverKind::Reference);
    const std::vector<std::string> names = testworld::addJointZoo(w);
    if (mode == 1) {  // the world's ERP, CFM and damping; static bodies that report a velocity
        w.info().m_erp = btScalar(0.4);
        w.info().m_globalCfm = btScalar(0.002);
        w.info().m_damping = btScalar(0.7);
        for (btRigidBody* b : w.bodies())
            if (b->isStaticObject() && !b->isKinematicObject()) {
                b->setLinearVelocity(btVector3(btScalar(0.3), 0, btScalar(-0.2)));  // SI's joint rows read it
                b->setAngularVelocity(btVector3(0, btScalar(0.5), 0));
            }
    }
    if (mode == 2) w.info().m_numIterations = 4;  // fewer than the two overrides (20 and 5)
    for (int i = 0; i < 12; ++i) w.step();
    const btContactSolverInfo info = w.stepInfo();
    std::vector<btTypedConstraint*> joints = w.constraints();
    REQUIRE(joints.size() == names.size());
    auto jointNamed = [&](const char* name) {
        return size_t(std::find(names.begin(), names.end(), name) - names.begin());
    };
    const size_t breakable = jointNamed("point2point breakable"), disabled = jointNamed("hinge disabled");
    REQUIRE(breakable < joints.size());
    REQUIRE(disabled < joints.size());
    joints[breakable]->setEnabled(true);  // it broke in the first step: its rows again, clamped

    const GatheredJoints ours = gatherJoints(w, joints, info);
    SetupOnlySI bullet;  // last: it clears the joints' feedback and applied impulses
    bullet.setUp(w, joints, info);
    const btConstraintArray& siRows = bullet.jointRows();
    REQUIRE(int(ours.joints.rows.size()) == siRows.size());
    REQUIRE(ours.joints.joints.size() == joints.size());

    // The same getInfo2 and the same formulas in the same order: Bullet's vector code may
    // associate a dot product differently, so the last bits only; 1e-5 relative (absolute below 1),
    // as for contact rows.
    std::map<std::string, float> worstByType;
    bool same = true;
    int withRows = 0;
    for (size_t i = 0; i < joints.size(); ++i) {
        const StepJoint& j = ours.joints.joints[i];
        CHECK(j.constraint == joints[i]);
        CHECK(j.feedback == joints[i]->getJointFeedback());
        float& worst = worstByType[names[i]];
        for (int r = j.firstRow; r < j.firstRow + j.numRows; ++r)
            worst = std::max(worst, rowGap(siRows[r], ours.joints.rows[size_t(r)], bullet, ours.original, same));
        if (j.numRows == 0) {
            CHECK(j.constraintIndex == -1);
            continue;
        }
        // One btoclConstraint per joint with rows, its rows of kind joint only.
        REQUIRE(j.constraintIndex == withRows++);
        const btoclConstraint& c = ours.joints.constraints[size_t(j.constraintIndex)];
        CHECK(c.firstRow[BTOCL_ROWS_JOINT] == j.firstRow);
        CHECK(c.numRows[BTOCL_ROWS_JOINT] == j.numRows);
        CHECK(c.numRows[BTOCL_ROWS_NORMAL] + c.numRows[BTOCL_ROWS_FRICTION] + c.numRows[BTOCL_ROWS_ROLLING] == 0);
        CHECK(c.bodyA == j.bodyA);
        CHECK(c.bodyB == j.bodyB);
    }
    CHECK(same);
    CHECK(withRows == int(ours.joints.constraints.size()));
    CHECK(ours.joints.joints[disabled].numRows == 0);
    int maxIterations = info.m_numIterations;
    for (const StepJoint& j : ours.joints.joints)
        if (j.numRows > 0) maxIterations = std::max(maxIterations, j.numIterations);
    CHECK(ours.joints.maxIterations == maxIterations);
    CHECK(ours.joints.maxIterations == std::max(info.m_numIterations, 20));
    for (const auto& [type, worst] : worstByType) {
        INFO(type << ": worst relative row difference " << worst);
        CHECK(worst < 1e-5f);
    }
    // The breakable joint's rows are clamped to its threshold, as SI clamps them.
    const StepJoint& clamped = ours.joints.joints[breakable];
    REQUIRE(clamped.numRows == 3);
    for (int r = clamped.firstRow; r < clamped.firstRow + clamped.numRows; ++r) {
        CHECK(BTOCL_ROW_UPPER(ours.joints.rows[size_t(r)]) == btScalar(0.05));
        CHECK(BTOCL_ROW_LOWER(ours.joints.rows[size_t(r)]) == btScalar(-0.05));
    }
}

TEST_CASE("a joint's split point lies where both bodies reach", "[joints][split]") {
    World w(SolverKind::Reference);
    // A chain of touching boxes: each joint point is on the faces they share, so no body reaches
    // further than its own AABB.
    const std::vector<btRigidBody*> chain = testworld::addChain(w, btVector3(0, 10, 0), 4);
    // Two spheres of radius 0.5, 3 m apart, joined across the 2 m gap: the point is halfway.
    btRigidBody* s1 = w.addSphere(btScalar(0.5), 1, testworld::at(btVector3(10, 10, 0)));
    btRigidBody* s2 = w.addSphere(btScalar(0.5), 1, testworld::at(btVector3(13, 10, 0)));
    w.addConstraint(std::make_unique<btPoint2PointConstraint>(*s1, *s2, btVector3(btScalar(1.5), 0, 0),
                                                              btVector3(btScalar(-1.5), 0, 0)));
    std::vector<btTypedConstraint*> joints = w.constraints();
    const GatheredJoints g = gatherJoints(w, joints, w.stepInfo());
    const JointRowSet& set = g.joints;
    REQUIRE(set.constraints.size() == 5);
    for (const btoclConstraint& c : set.constraints) CHECK(c.position.w == float(w.stepInfo().m_numIterations));
    // Placed as for a split step: the joints' constraints after the gathered ones, as the gather
    // puts them.
    StepProblem p = g.problem;
    p.constraints.insert(p.constraints.end(), set.constraints.begin(), set.constraints.end());
    BulletStep bullet;
    bullet.original = g.original;
    bullet.worldTransforms = g.worldTransforms;
    bullet.boxLo = g.boxLo;
    bullet.boxHi = g.boxHi;
    bullet.joints = set;
    addSplitGeometry(p, bullet);
    const btoclConstraint* placed = &p.constraints[p.constraints.size() - set.constraints.size()];

    // The top joint, to the fixed body: the middle of the top link's AABB.
    CHECK(placed[0].position.y == Approx(9.75f));
    CHECK_FALSE(placed[0].dynamicB);
    for (int i = 1; i < 4; ++i) {
        const btoclConstraint& c = placed[size_t(i)];
        CHECK(c.dynamicA);
        CHECK(c.dynamicB);
        CHECK(c.position.y == Approx(10.0f - 0.5f * float(i)));  // the shared face
        CHECK(c.position.w == set.constraints[size_t(i)].position.w);  // the iterations kept
    }
    for (size_t b = 1; b < g.problem.bodies.size(); ++b) {
        if (g.original[b] == s1 || g.original[b] == s2)
            CHECK(p.splitBodies[b].extent == Approx(2.0f));  // its own 1 m and half the 2 m gap
        else
            CHECK(p.splitBodies[b].extent == Approx(0.5f));  // its AABB's edge: nothing added
    }
    CHECK(placed[4].position.x == Approx(11.5f));
    (void)chain;
}

TEST_CASE("a joint whose rows are not finite is refused before anything is written", "[joints][setup]") {
    World w(SolverKind::Reference);
    btRigidBody* b = w.addSphere(btScalar(0.2), 1, testworld::at(btVector3(0, 5, 0)));
    const btScalar nan = std::numeric_limits<btScalar>::quiet_NaN();
    w.addConstraint(std::make_unique<btPoint2PointConstraint>(*b, btVector3(nan, 0, 0)));
    std::vector<btTypedConstraint*> joints = w.constraints();
    CHECK_THROWS_AS(gatherJoints(w, joints, w.stepInfo()), btOpenCLSolverError);
}

namespace {

// SI, with a prediction of its step made before it runs: our gather, joint rows and host
// reference solve on a serial layout (joints first, then the manifolds: SI's order), and our
// joint write-back on the result. Each call compares both with what SI then does.
class PredictedSI : public btSequentialImpulseConstraintSolver {
public:
    struct Worst {
        float velocity = 0, impulse = 0, feedback = 0;
        int breaks = 0, breakMismatches = 0, calls = 0, joints = 0;
    } worst;

    btScalar solveGroup(btCollisionObject** bodies, int numBodies, btPersistentManifold** manifolds, int numManifolds,
                        btTypedConstraint** joints, int numJoints, const btContactSolverInfo& info,
                        btIDebugDraw* debugDrawer, btDispatcher* dispatcher) override {
        GatheredJoints g = gatherJoints(bodies, numBodies, manifolds, numManifolds, joints, numJoints, info);
        StepProblem& p = g.problem;
        // The joints' constraints before the manifolds', their rows after the contact rows.
        const int base = int(p.rows.size());
        p.rows.insert(p.rows.end(), g.joints.rows.begin(), g.joints.rows.end());
        std::vector<btoclConstraint> jointConstraints = g.joints.constraints;
        for (btoclConstraint& c : jointConstraints) c.firstRow[BTOCL_ROWS_JOINT] += base;
        p.constraints.insert(p.constraints.begin(), jointConstraints.begin(), jointConstraints.end());
        p.regions = btoclRowRegionsOf(p.numRowsOf(BTOCL_ROWS_NORMAL), p.numRowsOf(BTOCL_ROWS_FRICTION),
                                      p.numRowsOf(BTOCL_ROWS_ROLLING), int(g.joints.rows.size()));
        p.jointIterations = g.joints.maxIterations;  // the step's iteration count, as SI's (passScheduleOf)
        solveOnHost(p, buildSerialLayout(int(p.constraints.size())), solveSettingsOf(info, false));

        std::vector<btVector3> linear, angular;
        for (size_t i = 1; i < g.original.size(); ++i) {
            const btoclBody& b = p.bodies[i];
            const btoclBodyDelta& d = p.deltas[i];
            linear.push_back(toVector3(b.linearVelocity) + toVector3(d.deltaLinearVelocity) + toVector3(b.externalForceImpulse));
            angular.push_back(toVector3(b.angularVelocity) + toVector3(btoclAngularChange(&b, d.deltaAngularVelocity)) +
                              toVector3(b.externalTorqueImpulse));
        }
        // Our write-back, read, then undone: SI starts from the joints as they were.
        btocl::writeBackJoints(g.joints, p.rows.data() + base, p.appliedImpulses.data() + base, info);  // not SI's member
        struct After {
            btScalar impulse;
            btJointFeedback feedback;
            bool enabled;
        };
        std::vector<After> ours;
        for (int i = 0; i < numJoints; ++i) {
            After a{joints[i]->getAppliedImpulse(), {}, joints[i]->isEnabled()};
            if (joints[i]->getJointFeedback()) a.feedback = *joints[i]->getJointFeedback();
            ours.push_back(a);
            joints[i]->setEnabled(g.joints.joints[size_t(i)].numRows > 0 || joints[i]->isEnabled());
        }

        const btScalar r = btSequentialImpulseConstraintSolver::solveGroup(bodies, numBodies, manifolds, numManifolds,
                                                                           joints, numJoints, info, debugDrawer,
                                                                           dispatcher);
        ++worst.calls;
        worst.joints += numJoints;
        for (size_t i = 1; i < g.original.size(); ++i) {
            const btRigidBody* rb = g.original[i];
            if (rb->getInvMass() == 0) continue;
            worst.velocity = std::max({worst.velocity, gap(rb->getLinearVelocity(), linear[i - 1]),
                                       gap(rb->getAngularVelocity(), angular[i - 1])});
        }
        for (int i = 0; i < numJoints; ++i) {
            worst.impulse = std::max(worst.impulse, relDiff(joints[i]->getAppliedImpulse(), ours[size_t(i)].impulse));
            if (const btJointFeedback* fb = joints[i]->getJointFeedback()) {
                const btJointFeedback& o = ours[size_t(i)].feedback;
                worst.feedback = std::max({worst.feedback, gap(fb->m_appliedForceBodyA, o.m_appliedForceBodyA),
                                           gap(fb->m_appliedForceBodyB, o.m_appliedForceBodyB),
                                           gap(fb->m_appliedTorqueBodyA, o.m_appliedTorqueBodyA),
                                           gap(fb->m_appliedTorqueBodyB, o.m_appliedTorqueBodyB)});
            }
            if (!joints[i]->isEnabled() && g.joints.joints[size_t(i)].numRows > 0) ++worst.breaks;
            if (joints[i]->isEnabled() != ours[size_t(i)].enabled) ++worst.breakMismatches;
        }
        return r;
    }

private:
    static float gap(const btVector3& a, const btVector3& b) {
        return std::max({relDiff(a.x(), b.x()), relDiff(a.y(), b.y()), relDiff(a.z(), b.z())});
    }
};

struct PredictedWorld {
    PredictedSI* solver;
    std::unique_ptr<World> world;
    PredictedWorld() {
        auto s = std::make_unique<PredictedSI>();
        solver = s.get();
        world = std::make_unique<World>(std::move(s));
    }
};

}  // namespace

TEST_CASE("the host reference solve of joints gives SI's velocities, impulses and feedback", "[joints][solve]") {
    auto scene = GENERATE(0, 1, 2, 3, 4);
    auto simd = GENERATE(true, false);
    CAPTURE(scene, simd);
    PredictedWorld pw;
    World& w = *pw.world;
    if (!simd) w.info().m_solverMode &= ~SOLVER_SIMD;  // impulses scaled by the body factors twice, as SI's scalar path
    int steps = 60;
    switch (scene) {
        case 0: testworld::addPendulum(w, btVector3(0, 5, 0), 2, btScalar(0.5)); break;
        case 1: testworld::addChain(w, btVector3(0, 12, 0), 10, 2); break;
        case 2:  // a chain whose top joint breaks under a heavy load, and a hinge limit and motor
        {
            const std::vector<btRigidBody*> chain = testworld::addChain(w, btVector3(0, 12, 0), 5);
            chain.back()->setMassProps(40, btVector3(4, 4, 4));
            chain.back()->updateInertiaTensor();
            w.constraints()[0]->setBreakingImpulseThreshold(5);
            testworld::addPendulum(w, btVector3(5, 5, 0), 1, 0);
            break;
        }
        case 3:  // every joint type; more iterations for two joints, fewer for one
            testworld::addJointZoo(w);
            steps = 30;
            break;
        case 4:  // a box sliding on the ground (one manifold: SI's contact order is ours) beside a
                 // pendulum that asks for more iterations than the contacts get
        {
            w.addGround();
            testworld::BodyOptions sliding;
            sliding.linearVelocity = btVector3(3, 0, 0);
            w.addUnitBox(btVector3(3, btScalar(0.5), 0), sliding);
            testworld::addPendulum(w, btVector3(0, 5, 0), 2, 1);
            w.constraints()[0]->setOverrideNumSolverIterations(25);
            break;
        }
    }
    for (int i = 0; i < steps; ++i) w.step();
    const PredictedSI::Worst& worst = pw.solver->worst;
    INFO("worst relative difference over " << steps << " steps: velocity " << worst.velocity << ", joint impulse "
                                           << worst.impulse << ", feedback " << worst.feedback << "; joints broken "
                                           << worst.breaks);
    REQUIRE(worst.calls >= steps);
    CHECK(worst.joints > 0);
    // The same rows solved in SI's order (joints, then the one manifold's normal rows, then its
    // friction rows); the sums differ by rounding only. 1e-5 relative (absolute below 1).
    CHECK(worst.velocity < 1e-5f);
    CHECK(worst.impulse < 1e-5f);
    CHECK(worst.feedback < 1e-5f);
    CHECK(worst.breakMismatches == 0);
    if (scene == 2) CHECK(worst.breaks == 1);
}

namespace {

// A world's step as the gather leaves it, solved on the host in gather order; each body's
// velocities after it (what the write-back gives Bullet).
std::vector<btVector3> solvedVelocities(StepProblem& p, const btContactSolverInfo& info) {
    solveOnHost(p, buildSerialLayout(int(p.constraints.size())), solveSettingsOf(info, false));
    std::vector<btVector3> v;
    for (size_t i = 1; i < p.bodies.size(); ++i) {
        const btoclBody& b = p.bodies[i];
        v.push_back(toVector3(b.linearVelocity) + toVector3(p.deltas[i].deltaLinearVelocity));
        v.push_back(toVector3(b.angularVelocity) + toVector3(btoclAngularChange(&b, p.deltas[i].deltaAngularVelocity)));
    }
    return v;
}

// The largest relative gap between the velocities after a solve of `p` and of the same step with
// every body's angular change kept as SI's (BTOCL_BODY_SCALED 0), gathered again from `w`.
float gapToRowsAsSI(StepProblem& p, World& w, const btContactSolverInfo& info) {
    StepProblem asSI = gatherStep(w, info, RowSetup::Host).problem;
    for (size_t i = 1; i < asSI.bodies.size(); ++i) BTOCL_BODY_SCALED(asSI.bodies[i]) = 0.0f;
    const std::vector<btVector3> a = solvedVelocities(p, info), b = solvedVelocities(asSI, info);
    float worst = 0;
    for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, vectorGap(a[i], toFloat4(b[i])));
    return worst;
}

}  // namespace

TEST_CASE("bodies whose angular changes the passes keep scaled end with the velocities of SI's rows",
          "[joints][solve]") {
    World w(SolverKind::Reference);
    groundAndPile(w, 27);
    testworld::addChain(w, btVector3(6, 8, 0), 6, 2);
    addJointZoo(w);
    for (int i = 0; i < 40; ++i) w.step();
    const btContactSolverInfo info = w.stepInfo();
    StepProblem scaled = gatherStep(w, info, RowSetup::Host).problem;
    REQUIRE(scaled.numContactPoints() > 0);
    REQUIRE(scaled.numJointRows() > 0);
    // Each body whose angular factor is 1 (the zoo has one turning about one axis alone, which
    // keeps SI's rows) has S, its inverse inertia's square root: S S = I to float rounding.
    float worstRoot = 0;
    int unscaled = 0;
    for (size_t i = 1; i < scaled.bodies.size(); ++i) {
        const btoclBody& b = scaled.bodies[i];
        const bool unit = b.angularFactor.x == 1 && b.angularFactor.y == 1 && b.angularFactor.z == 1;
        CHECK(BTOCL_BODY_SCALED(b) == (unit ? 1.0f : 0.0f));
        if (!unit) {
            ++unscaled;
            continue;
        }
        const btoclFloat4 S[3] = {b.angularScaleRow0, b.angularScaleRow1, b.angularScaleRow2};
        const btoclFloat4 I[3] = {b.invInertiaRow0, b.invInertiaRow1, b.invInertiaRow2};
        float largest = 0;
        for (int r = 0; r < 3; ++r)
            largest = std::max({largest, std::fabs(I[r].x), std::fabs(I[r].y), std::fabs(I[r].z)});
        for (int r = 0; r < 3; ++r) {
            const btoclFloat4 column[3] = {
                {S[0].x, S[1].x, S[2].x, 0}, {S[0].y, S[1].y, S[2].y, 0}, {S[0].z, S[1].z, S[2].z, 0}};
            const float product[3] = {btoclDot3(S[r], column[0]), btoclDot3(S[r], column[1]),
                                      btoclDot3(S[r], column[2])};
            const float wanted[3] = {I[r].x, I[r].y, I[r].z};
            for (int c = 0; c < 3; ++c) worstRoot = std::max(worstRoot, std::fabs(product[c] - wanted[c]) / largest);
        }
    }
    CHECK(scaled.unscaledBodies == unscaled);
    CHECK(unscaled < scaled.numBodies() / 10);
    INFO("worst |S S - I| over the largest entry " << worstRoot);
    CHECK(worstRoot < 1e-6f);

    const float worst = gapToRowsAsSI(scaled, w, info);
    INFO("worst relative velocity difference " << worst);
    // The same rows and order; the effective masses differ by rounding (S S for I), which ten
    // iterations carry on: 1.2e-6 measured. A's Jacobian left unscaled (its component scaled) gives 1.4.
    CHECK(worst < 1e-5f);
}

TEST_CASE("a body with an angular factor of its own, or moved without its inertia, keeps SI's rows and no lanes",
          "[joints][solve]") {
    auto odd = GENERATE(0, 1, 2);
    CAPTURE(odd);
    World w(SolverKind::Reference);
    groundAndPile(w, 8);
    w.body(3)->setMassProps(1, btVector3(btScalar(0.2), btScalar(0.4), btScalar(0.6)));  // not a cube's inertia
    w.body(3)->updateInertiaTensor();
    for (int i = 0; i < 20; ++i) w.step();
    if (odd == 1) w.body(3)->setAngularFactor(btVector3(0, 0, 1));  // a body turning in a plane
    if (odd == 2) {  // moved by the user: Bullet's tensor is the old basis's until its next step
        btTransform moved = w.body(3)->getWorldTransform();
        moved.setRotation(moved.getRotation() * btQuaternion(btVector3(1, 0, 0), 0.7f));
        w.body(3)->setWorldTransform(moved);
    }
    const btContactSolverInfo info = w.stepInfo();
    StepProblem p = gatherStep(w, info, RowSetup::Device).problem;
    CHECK(p.unscaledBodies == (odd ? 1 : 0));
    const SolveSettings settings = solveSettingsOf(info, false);
    CHECK(stepFitsHostLanes(p, settings, passScheduleOf(settings, p)) == (odd == 0));
    // The unscaled body's rows are SI's (test_row_setup.cpp holds SI's rows to the solve rows
    // where scaled): its velocities after a solve are those of a world whose bodies all keep SI's.
    StepProblem mixed = gatherStep(w, info, RowSetup::Host).problem;
    const float worst = gapToRowsAsSI(mixed, w, info);
    INFO("worst relative velocity difference " << worst);
    CHECK(worst < 1e-5f);
}
