// The tests' Bullet world: a btDiscreteDynamicsWorld with its own collision set-up and solver,
// owning every body it makes, stepped at a fixed 60 Hz under g = 9.81 m/s^2. Its solver is
// btSequentialImpulseConstraintSolver (SI), ours (validate = true: every step checks the split
// and batch invariants), or any solver the test passes in. Scenes to build in it: Scenes.h.
//
// Parity tests build one scene twice (Pair): a reference world stepped by SI and a candidate
// world stepped by ours, in lock step. BTOCL_PARITY_REFERENCE_ONLY switches the candidate's
// solver so the tests' logic and tolerances can be checked without our solver:
//   unset or "0" - btOpenCLConstraintSolver (the real test);
//   "1"          - SI on both sides (every comparison must hold exactly);
//   "shuffle"    - SI with SOLVER_RANDMIZE_ORDER on the candidate side: a different Gauss-Seidel
//                  order each iteration, as our batching gives; tolerances must hold for it too.
#pragma once

#include "btOpenCLConstraintSolver.h"

#include <btBulletDynamicsCommon.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace testworld {

enum class SolverKind { Reference, OpenCL, ReferenceShuffled };

constexpr btScalar kDt = btScalar(1) / btScalar(60);  // the fixed 60 Hz step of every test
constexpr btScalar kG = btScalar(9.81);               // gravity, along -y

inline SolverKind candidateKind() {
    const char* env = std::getenv("BTOCL_PARITY_REFERENCE_ONLY");
    if (!env || std::string(env).empty() || std::string(env) == "0") return SolverKind::OpenCL;
    if (std::string(env) == "shuffle") return SolverKind::ReferenceShuffled;
    return SolverKind::Reference;
}

inline btOpenCLSolverConfig validatingConfig() {
    btOpenCLSolverConfig c;
    c.validate = true;  // every step checks the split and batch invariants
    // Steps past 4,096 rows (about 1,000 constraints) go through the global split on either
    // path, so that the parity scenes exercise the split and the sets as well as the whole-step
    // kernel; the serial path's own choice (whole up to about 128K rows on 2 cores) would solve
    // nearly every test scene whole. test_solver_api.cpp tests the automatic choice.
    c.wholeStepMaxRows = 4096;
    return c;
}

inline std::unique_ptr<btConstraintSolver> makeSolver(SolverKind kind, const btOpenCLSolverConfig& config) {
    if (kind == SolverKind::OpenCL) return std::make_unique<btOpenCLConstraintSolver>(config);
    return std::make_unique<btSequentialImpulseConstraintSolver>();  // shuffled or not: see World::step
}

// A kinematic body's motion state: the body moves along a straight line at constant velocity;
// the world reads the pose at the end of the step it is about to take.
class LinearPathMotionState : public btMotionState {
public:
    LinearPathMotionState(const btTransform& start, const btVector3& velocity, const btScalar* time)
        : m_start(start), m_velocity(velocity), m_time(time) {}
    void getWorldTransform(btTransform& t) const override {
        t = m_start;
        t.setOrigin(m_start.getOrigin() + m_velocity * *m_time);
    }
    void setWorldTransform(const btTransform&) override {}

private:
    btTransform m_start;
    btVector3 m_velocity;
    const btScalar* m_time;
};

struct BodyOptions {
    btScalar friction = btScalar(0.5);
    btScalar restitution = 0;
    btScalar rollingFriction = 0;
    btVector3 linearVelocity{0, 0, 0};
    btVector3 angularVelocity{0, 0, 0};
};

// One dynamics world with its own collision set-up and solver; owns every body it makes.
class World {
public:
    explicit World(SolverKind kind, const btOpenCLSolverConfig& config = validatingConfig())
        : World(makeSolver(kind, config)) {
        m_shuffleOrder = kind == SolverKind::ReferenceShuffled;
    }
    // With the solver the test passes in.
    explicit World(std::unique_ptr<btConstraintSolver> solver)
        : m_dispatcher(&m_collisionConfig),
          m_solver(std::move(solver)),
          m_openCL(dynamic_cast<btOpenCLConstraintSolver*>(m_solver.get())) {
        m_world = std::make_unique<btDiscreteDynamicsWorld>(&m_dispatcher, &m_broadphase, m_solver.get(),
                                                             &m_collisionConfig);
        m_world->setGravity(btVector3(0, -kG, 0));
    }

    ~World() {
        for (auto& c : m_constraints) m_world->removeConstraint(c.get());
        for (auto& b : m_bodies) m_world->removeRigidBody(b.get());
        m_world.reset();  // before the bodies, shapes and solver it points to
    }

    World(const World&) = delete;
    World& operator=(const World&) = delete;

    btDiscreteDynamicsWorld& dyn() { return *m_world; }
    btCollisionDispatcher& dispatcher() { return m_dispatcher; }
    btContactSolverInfo& info() { return m_world->getSolverInfo(); }
    // The solver settings with the fixed step, as the world hands them to its solver.
    btContactSolverInfo stepInfo() const {
        btContactSolverInfo i = m_world->getSolverInfo();
        i.m_timeStep = kDt;
        return i;
    }
    btOpenCLConstraintSolver* openCL() { return m_openCL; }  // null unless our solver runs here
    const std::vector<btRigidBody*>& bodies() const { return m_bodyList; }
    btRigidBody* body(size_t i) const { return m_bodyList.at(i); }
    btScalar time() const { return m_time; }
    int stepsTaken() const { return m_steps; }

    // Bodies made after this may fall asleep (Bullet's default); before it, they never do, so a
    // test of resting contact keeps the solver busy for its whole run.
    void allowSleeping() { m_allowSleeping = true; }

    btRigidBody* addBox(const btVector3& halfExtents, btScalar mass, const btTransform& pose,
                        const BodyOptions& o = {}) {
        return addBody(std::make_unique<btBoxShape>(halfExtents), mass, pose, o);
    }
    // A 1 m cube of 1 kg.
    btRigidBody* addUnitBox(const btVector3& center, const BodyOptions& o = {}) {
        const btVector3 half(btScalar(0.5), btScalar(0.5), btScalar(0.5));
        return addBox(half, 1, btTransform(btQuaternion::getIdentity(), center), o);
    }
    btRigidBody* addSphere(btScalar radius, btScalar mass, const btTransform& pose, const BodyOptions& o = {}) {
        return addBody(std::make_unique<btSphereShape>(radius), mass, pose, o);
    }
    // A static slab whose top face is the plane y = 0 (before `tilt`, a rotation about the origin).
    btRigidBody* addGround(const BodyOptions& o = groundOptions(), const btQuaternion& tilt = btQuaternion::getIdentity()) {
        btTransform pose(tilt, btVector3(0, 0, 0));
        pose = pose * btTransform(btQuaternion::getIdentity(), btVector3(0, -kGroundHalf, 0));
        return addBox(btVector3(kGroundHalfWidth, kGroundHalf, kGroundHalfWidth), 0, pose, o);
    }
    static BodyOptions groundOptions() {
        BodyOptions o;
        o.friction = 1;      // combined friction is the product: the other body's value rules
        o.restitution = 1;   // combined restitution is the product too
        return o;
    }
    // A kinematic box moving at `velocity` from `start`.
    btRigidBody* addKinematicBox(const btVector3& halfExtents, const btTransform& start, const btVector3& velocity,
                                 const BodyOptions& o = {}) {
        auto state = std::make_unique<LinearPathMotionState>(start, velocity, &m_time);
        btRigidBody::btRigidBodyConstructionInfo ci(0, state.get(), keepShape(std::make_unique<btBoxShape>(halfExtents)));
        ci.m_friction = o.friction;
        ci.m_restitution = o.restitution;
        auto body = std::make_unique<btRigidBody>(ci);
        body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
        body->setActivationState(DISABLE_DEACTIVATION);
        m_motionStates.push_back(std::move(state));
        return keepBody(std::move(body));
    }

    template <class C>
    C* addConstraint(std::unique_ptr<C> c) {
        C* raw = c.get();
        m_world->addConstraint(raw, true);
        m_constraints.push_back(std::move(c));
        return raw;
    }
    // A btJointFeedback that the world owns, attached to c.
    btJointFeedback* addFeedback(btTypedConstraint* c) {
        m_feedbacks.push_back(std::make_unique<btJointFeedback>());
        c->setJointFeedback(m_feedbacks.back().get());
        return m_feedbacks.back().get();
    }
    std::vector<btTypedConstraint*> constraints() {
        std::vector<btTypedConstraint*> out;
        for (int i = 0; i < m_world->getNumConstraints(); ++i) out.push_back(m_world->getConstraint(i));
        return out;
    }

    // One fixed 60 Hz step. With our solver, the invariants it validated must all hold.
    void step() {
        if (m_shuffleOrder) info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
        m_time += kDt;  // kinematic bodies read the pose at the end of this step
        m_world->stepSimulation(kDt, 0);
        ++m_steps;
        if (m_openCL) {
            const btOpenCLSolverStats& s = m_openCL->getLastStats();
            if (s.validationFailures != 0)
                FAIL("step " << m_steps << ": " << s.validationFailures
                             << " invariant failures: " << s.lastValidationMessage);
        }
    }

    // Contact queries over the dispatcher's manifolds as they are after the last step.
    std::vector<btPersistentManifold*> manifolds() {
        std::vector<btPersistentManifold*> out;
        for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) out.push_back(m_dispatcher.getManifoldByIndexInternal(i));
        return out;
    }
    int numContactPoints() const {
        int n = 0;
        for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i)
            n += m_dispatcher.getManifoldByIndexInternal(i)->getNumContacts();
        return n;
    }
    // Deepest penetration (a positive depth) of any contact point; 0 when nothing overlaps.
    btScalar maxPenetration() const {
        btScalar deepest = 0;
        for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) {
            const btPersistentManifold* m = m_dispatcher.getManifoldByIndexInternal(i);
            for (int j = 0; j < m->getNumContacts(); ++j)
                deepest = std::max(deepest, -m->getContactPoint(j).getDistance());
        }
        return deepest;
    }
    // Sum of m_appliedImpulse over the points of every manifold between a and b.
    btScalar normalImpulseBetween(const btCollisionObject* a, const btCollisionObject* b) const {
        btScalar sum = 0;
        for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) {
            const btPersistentManifold* m = m_dispatcher.getManifoldByIndexInternal(i);
            const bool match = (m->getBody0() == a && m->getBody1() == b) || (m->getBody0() == b && m->getBody1() == a);
            if (!match) continue;
            for (int j = 0; j < m->getNumContacts(); ++j) sum += m->getContactPoint(j).m_appliedImpulse;
        }
        return sum;
    }
    int numContactPointsBetween(const btCollisionObject* a, const btCollisionObject* b) const {
        int n = 0;
        for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) {
            const btPersistentManifold* m = m_dispatcher.getManifoldByIndexInternal(i);
            if ((m->getBody0() == a && m->getBody1() == b) || (m->getBody0() == b && m->getBody1() == a))
                n += m->getNumContacts();
        }
        return n;
    }

    static constexpr btScalar kGroundHalf = btScalar(0.5);
    static constexpr btScalar kGroundHalfWidth = btScalar(50);

private:
    btCollisionShape* keepShape(std::unique_ptr<btCollisionShape> s) {
        m_shapes.push_back(std::move(s));
        return m_shapes.back().get();
    }
    btRigidBody* keepBody(std::unique_ptr<btRigidBody> b) {
        m_world->addRigidBody(b.get());
        m_bodyList.push_back(b.get());
        m_bodies.push_back(std::move(b));
        return m_bodyList.back();
    }
    btRigidBody* addBody(std::unique_ptr<btCollisionShape> shapeOwned, btScalar mass, const btTransform& pose,
                         const BodyOptions& o) {
        btCollisionShape* shape = keepShape(std::move(shapeOwned));
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shape->calculateLocalInertia(mass, inertia);
        auto state = std::make_unique<btDefaultMotionState>(pose);
        btRigidBody::btRigidBodyConstructionInfo ci(mass, state.get(), shape, inertia);
        ci.m_friction = o.friction;
        ci.m_restitution = o.restitution;
        ci.m_rollingFriction = o.rollingFriction;
        auto body = std::make_unique<btRigidBody>(ci);
        body->setLinearVelocity(o.linearVelocity);
        body->setAngularVelocity(o.angularVelocity);
        if (mass > 0 && !m_allowSleeping) body->setActivationState(DISABLE_DEACTIVATION);
        m_motionStates.push_back(std::move(state));
        return keepBody(std::move(body));
    }

    btDefaultCollisionConfiguration m_collisionConfig;
    btCollisionDispatcher m_dispatcher;
    btDbvtBroadphase m_broadphase;
    std::unique_ptr<btConstraintSolver> m_solver;
    btOpenCLConstraintSolver* m_openCL = nullptr;
    std::unique_ptr<btDiscreteDynamicsWorld> m_world;
    std::vector<std::unique_ptr<btCollisionShape>> m_shapes;
    std::vector<std::unique_ptr<btMotionState>> m_motionStates;
    std::vector<std::unique_ptr<btRigidBody>> m_bodies;
    std::vector<btRigidBody*> m_bodyList;
    std::vector<std::unique_ptr<btTypedConstraint>> m_constraints;
    std::vector<std::unique_ptr<btJointFeedback>> m_feedbacks;
    bool m_shuffleOrder = false;  // SI in a new order every iteration (SolverKind::ReferenceShuffled)
    btScalar m_time = 0;
    int m_steps = 0;
    bool m_allowSleeping = false;
};

// The same scene twice: `ref` with SI, `ours` with the candidate solver. Body i of one world is
// body i of the other.
struct Pair {
    World ref;
    World ours;

    explicit Pair(SolverKind candidate = candidateKind(), const btOpenCLSolverConfig& config = validatingConfig())
        : ref(SolverKind::Reference), ours(candidate, config) {}

    void build(const std::function<void(World&)>& scene) {
        scene(ref);
        scene(ours);
    }
    void configure(const std::function<void(btContactSolverInfo&)>& set) {
        set(ref.info());
        set(ours.info());
    }
    void step(int n = 1) {
        for (int i = 0; i < n; ++i) {
            ref.step();
            ours.step();
        }
    }
    // Steps n times, calling watch(ref, ours) after each step.
    void run(int n, const std::function<void(World&, World&)>& watch) {
        for (int i = 0; i < n; ++i) {
            step();
            watch(ref, ours);
        }
    }
};

inline btTransform at(const btVector3& p, const btQuaternion& q = btQuaternion::getIdentity()) {
    return btTransform(q, p);
}
inline btScalar distance(const btVector3& a, const btVector3& b) { return (a - b).length(); }
inline btVector3 pos(const btRigidBody* b) { return b->getCenterOfMassPosition(); }

// Largest distance between body i of one world and body i of the other, over dynamic bodies.
inline btScalar maxPositionGap(const World& a, const World& b) {
    btScalar gap = 0;
    for (size_t i = 0; i < a.bodies().size(); ++i)
        if (!a.body(i)->isStaticOrKinematicObject()) gap = std::max(gap, distance(pos(a.body(i)), pos(b.body(i))));
    return gap;
}

// Largest distance of a dynamic body from where it started (`start` as recorded at build time).
inline btScalar maxDisplacement(const World& w, const std::vector<btVector3>& start) {
    btScalar d = 0;
    for (size_t i = 0; i < w.bodies().size(); ++i)
        if (!w.body(i)->isStaticOrKinematicObject()) d = std::max(d, distance(pos(w.body(i)), start[i]));
    return d;
}
inline std::vector<btVector3> positionsOf(const World& w) {
    std::vector<btVector3> p;
    for (const btRigidBody* b : w.bodies()) p.push_back(pos(b));
    return p;
}

// Body by body, b moved as a did: within 2 mm plus 5% of the way a's body went since `start`.
// 2 mm: the boxes of a column jitter by about 1 mm around rest (SI's do), so two runs that
// order the work differently can sit 2 mm apart; 5%: the friction bound of the sliding tests.
inline double worstExcessGap(const World& a, const World& b, const std::vector<btVector3>& start) {
    double worst = -1;  // largest gap - tolerance; <= 0 when all bodies agree
    for (size_t i = 0; i < a.bodies().size(); ++i) {
        if (a.body(i)->isStaticOrKinematicObject()) continue;
        const double tol = 2e-3 + 0.05 * distance(pos(a.body(i)), start[i]);
        worst = std::max(worst, double(distance(pos(a.body(i)), pos(b.body(i)))) - tol);
    }
    return worst;
}

// |a - b| <= rel * max(|a|, |b|, floor): a relative bound that does not vanish near zero.
inline bool closeRel(double a, double b, double rel, double floor) {
    return std::fabs(a - b) <= rel * std::max({std::fabs(a), std::fabs(b), floor});
}

}  // namespace testworld
