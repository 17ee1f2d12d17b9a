// The scenes' Bullet world, shared by the tests and the benchmark: a btDiscreteDynamicsWorld with
// its own collision set-up, built around a constraint solver it does not own, owning every shape,
// body, motion state and joint that a scene puts in it. Two worlds built by the same scene
// function with the same arguments hold the same bodies and joints in the same order, so body i
// of one is body i of the other. Scenes to build in it: Stacks.h, Joints.h.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <vector>

namespace btscenes {

constexpr btScalar kGravity = btScalar(9.81);  // m/s^2 along -y, unless a world is given another

inline btTransform at(const btVector3& p, const btQuaternion& q = btQuaternion::getIdentity()) {
    return btTransform(q, p);
}

// The mass of a box of `density` (kg/m^3) with those half extents.
inline btScalar boxMass(btScalar density, const btVector3& half) {
    return density * 8 * half.x() * half.y() * half.z();
}

// A body's surface and starting velocities.
struct BodyOptions {
    btScalar friction = btScalar(0.5);
    btScalar restitution = 0;
    btScalar rollingFriction = 0;
    btVector3 linearVelocity{0, 0, 0};
    btVector3 angularVelocity{0, 0, 0};
};

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

class World {
public:
    explicit World(btConstraintSolver* solver, btScalar gravity = kGravity);
    virtual ~World();
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    btDiscreteDynamicsWorld& dyn() { return *m_world; }
    const btDiscreteDynamicsWorld& dyn() const { return *m_world; }
    btCollisionDispatcher& dispatcher() { return m_dispatcher; }
    btContactSolverInfo& info() { return m_world->getSolverInfo(); }
    const std::vector<btRigidBody*>& bodies() const { return m_bodyList; }
    btRigidBody* body(size_t i) const { return m_bodyList.at(i); }
    // Half extents of body i's box (a sphere's radius on each axis), for drawing it.
    const btVector3& halfExtents(size_t i) const { return m_halfExtents.at(i); }
    int numDynamicBodies() const;
    btScalar time() const { return m_time; }
    int stepsTaken() const { return m_steps; }

    // One world step of dt, with no substeps and no interpolation.
    void step(btScalar dt);

    // Bodies made after this may fall asleep (Bullet's default); before it, they never do, so a
    // scene keeps the solver busy for its whole run.
    void allowSleeping() { m_allowSleeping = true; }

    btRigidBody* addBox(const btVector3& halfExtents, btScalar mass, const btTransform& pose,
                        const BodyOptions& o = {});
    // A 1 m cube of 1 kg.
    btRigidBody* addUnitBox(const btVector3& center, const BodyOptions& o = {});
    btRigidBody* addSphere(btScalar radius, btScalar mass, const btTransform& pose, const BodyOptions& o = {});
    // A static slab whose top face is the plane y = 0 (before `tilt`, a rotation about the origin),
    // reaching halfWidth from the origin along x and z.
    btRigidBody* addGround(const BodyOptions& o = groundOptions(), const btQuaternion& tilt = btQuaternion::getIdentity(),
                           btScalar halfWidth = kGroundHalfWidth);
    static BodyOptions groundOptions() {
        BodyOptions o;
        o.friction = 1;      // combined friction is the product: the other body's value rules
        o.restitution = 1;   // combined restitution is the product too
        return o;
    }
    // A kinematic box moving at `velocity` from `start`.
    btRigidBody* addKinematicBox(const btVector3& halfExtents, const btTransform& start, const btVector3& velocity,
                                 const BodyOptions& o = {});

    // A joint between bodies of this world; its two bodies no longer collide with each other.
    template <class C>
    C* addConstraint(std::unique_ptr<C> c) {
        C* raw = c.get();
        m_world->addConstraint(raw, true);
        m_constraints.push_back(std::move(c));
        return raw;
    }
    // A btJointFeedback that the world owns, attached to c.
    btJointFeedback* addFeedback(btTypedConstraint* c);
    // The world's joints, in its order.
    std::vector<btTypedConstraint*> constraints() const;

    // Contact queries over the dispatcher's manifolds as they are after the last step.
    std::vector<btPersistentManifold*> manifolds();
    int numContactPoints() const;
    // Deepest penetration (a positive depth) of any contact point; 0 when nothing overlaps.
    btScalar maxPenetration() const;
    // Sum of m_appliedImpulse over the points of every manifold between a and b.
    btScalar normalImpulseBetween(const btCollisionObject* a, const btCollisionObject* b) const;
    int numContactPointsBetween(const btCollisionObject* a, const btCollisionObject* b) const;

    static constexpr btScalar kGroundHalf = btScalar(0.5);
    static constexpr btScalar kGroundHalfWidth = btScalar(50);

private:
    btCollisionShape* keepShape(std::unique_ptr<btCollisionShape> s);
    btRigidBody* keepBody(std::unique_ptr<btRigidBody> b, const btVector3& halfExtents);
    btRigidBody* addBody(std::unique_ptr<btCollisionShape> shapeOwned, const btVector3& halfExtents, btScalar mass,
                         const btTransform& pose, const BodyOptions& o);

    btDefaultCollisionConfiguration m_collisionConfig;
    btCollisionDispatcher m_dispatcher;
    btDbvtBroadphase m_broadphase;
    std::unique_ptr<btDiscreteDynamicsWorld> m_world;
    std::vector<std::unique_ptr<btCollisionShape>> m_shapes;
    std::vector<std::unique_ptr<btMotionState>> m_motionStates;
    std::vector<std::unique_ptr<btRigidBody>> m_bodies;
    std::vector<btRigidBody*> m_bodyList;
    std::vector<btVector3> m_halfExtents;
    std::vector<std::unique_ptr<btTypedConstraint>> m_constraints;
    std::vector<std::unique_ptr<btJointFeedback>> m_feedbacks;
    btScalar m_time = 0;
    int m_steps = 0;
    bool m_allowSleeping = false;
};

// The ground of a scene: its surface and how far it reaches from the origin along x and z.
struct Ground {
    BodyOptions surface = World::groundOptions();
    btScalar halfWidth = World::kGroundHalfWidth;
};

}  // namespace btscenes
