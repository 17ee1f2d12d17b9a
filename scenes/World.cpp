#include "scenes/World.h"

#include <algorithm>

namespace btscenes {

World::World(btConstraintSolver* solver, btScalar gravity) : m_dispatcher(&m_collisionConfig) {
    m_world = std::make_unique<btDiscreteDynamicsWorld>(&m_dispatcher, &m_broadphase, solver, &m_collisionConfig);
    m_world->setGravity(btVector3(0, -gravity, 0));
}

World::~World() {
    // The world touches its bodies' broadphase proxies when it goes, so take them out first
    // (and the joints before the bodies they refer to).
    for (auto& c : m_constraints) m_world->removeConstraint(c.get());
    for (auto& b : m_bodies) m_world->removeRigidBody(b.get());
    m_world.reset();
}

int World::numDynamicBodies() const {
    return int(std::count_if(m_bodyList.begin(), m_bodyList.end(),
                             [](const btRigidBody* b) { return !b->isStaticOrKinematicObject(); }));
}

void World::step(btScalar dt) {
    m_time += dt;  // kinematic bodies read the pose at the end of this step
    m_world->stepSimulation(dt, 0);
    ++m_steps;
}

btRigidBody* World::addBox(const btVector3& halfExtents, btScalar mass, const btTransform& pose, const BodyOptions& o) {
    return addBody(std::make_unique<btBoxShape>(halfExtents), halfExtents, mass, pose, o);
}

btRigidBody* World::addUnitBox(const btVector3& center, const BodyOptions& o) {
    const btVector3 half(btScalar(0.5), btScalar(0.5), btScalar(0.5));
    return addBox(half, 1, btTransform(btQuaternion::getIdentity(), center), o);
}

btRigidBody* World::addSphere(btScalar radius, btScalar mass, const btTransform& pose, const BodyOptions& o) {
    return addBody(std::make_unique<btSphereShape>(radius), btVector3(radius, radius, radius), mass, pose, o);
}

btRigidBody* World::addGround(const BodyOptions& o, const btQuaternion& tilt, btScalar halfWidth) {
    btTransform pose(tilt, btVector3(0, 0, 0));
    pose = pose * btTransform(btQuaternion::getIdentity(), btVector3(0, -kGroundHalf, 0));
    return addBox(btVector3(halfWidth, kGroundHalf, halfWidth), 0, pose, o);
}

btRigidBody* World::addKinematicBox(const btVector3& halfExtents, const btTransform& start, const btVector3& velocity,
                                    const BodyOptions& o) {
    auto state = std::make_unique<LinearPathMotionState>(start, velocity, &m_time);
    btRigidBody::btRigidBodyConstructionInfo ci(0, state.get(), keepShape(std::make_unique<btBoxShape>(halfExtents)));
    ci.m_friction = o.friction;
    ci.m_restitution = o.restitution;
    auto body = std::make_unique<btRigidBody>(ci);
    body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    body->setActivationState(DISABLE_DEACTIVATION);
    m_motionStates.push_back(std::move(state));
    return keepBody(std::move(body), halfExtents);
}

btJointFeedback* World::addFeedback(btTypedConstraint* c) {
    m_feedbacks.push_back(std::make_unique<btJointFeedback>());
    c->setJointFeedback(m_feedbacks.back().get());
    return m_feedbacks.back().get();
}

std::vector<btTypedConstraint*> World::constraints() const {
    std::vector<btTypedConstraint*> out;
    for (int i = 0; i < m_world->getNumConstraints(); ++i) out.push_back(m_world->getConstraint(i));
    return out;
}

std::vector<btPersistentManifold*> World::manifolds() {
    std::vector<btPersistentManifold*> out;
    for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) out.push_back(m_dispatcher.getManifoldByIndexInternal(i));
    return out;
}

int World::numContactPoints() const {
    int n = 0;
    for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i)
        n += m_dispatcher.getManifoldByIndexInternal(i)->getNumContacts();
    return n;
}

btScalar World::maxPenetration() const {
    btScalar deepest = 0;
    for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) {
        const btPersistentManifold* m = m_dispatcher.getManifoldByIndexInternal(i);
        for (int j = 0; j < m->getNumContacts(); ++j) deepest = std::max(deepest, -m->getContactPoint(j).getDistance());
    }
    return deepest;
}

namespace {

bool joins(const btPersistentManifold* m, const btCollisionObject* a, const btCollisionObject* b) {
    return (m->getBody0() == a && m->getBody1() == b) || (m->getBody0() == b && m->getBody1() == a);
}

}  // namespace

btScalar World::normalImpulseBetween(const btCollisionObject* a, const btCollisionObject* b) const {
    btScalar sum = 0;
    for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) {
        const btPersistentManifold* m = m_dispatcher.getManifoldByIndexInternal(i);
        if (!joins(m, a, b)) continue;
        for (int j = 0; j < m->getNumContacts(); ++j) sum += m->getContactPoint(j).m_appliedImpulse;
    }
    return sum;
}

int World::numContactPointsBetween(const btCollisionObject* a, const btCollisionObject* b) const {
    int n = 0;
    for (int i = 0; i < m_dispatcher.getNumManifolds(); ++i) {
        const btPersistentManifold* m = m_dispatcher.getManifoldByIndexInternal(i);
        if (joins(m, a, b)) n += m->getNumContacts();
    }
    return n;
}

btCollisionShape* World::keepShape(std::unique_ptr<btCollisionShape> s) {
    m_shapes.push_back(std::move(s));
    return m_shapes.back().get();
}

btRigidBody* World::keepBody(std::unique_ptr<btRigidBody> b, const btVector3& halfExtents) {
    m_world->addRigidBody(b.get());
    m_bodyList.push_back(b.get());
    m_halfExtents.push_back(halfExtents);
    m_bodies.push_back(std::move(b));
    return m_bodyList.back();
}

btRigidBody* World::addBody(std::unique_ptr<btCollisionShape> shapeOwned, const btVector3& halfExtents, btScalar mass,
                            const btTransform& pose, const BodyOptions& o) {
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
    return keepBody(std::move(body), halfExtents);
}

}  // namespace btscenes
