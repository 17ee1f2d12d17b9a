#include "SceneWorld.h"

namespace btbench {

SceneWorld::SceneWorld(btConstraintSolver* solver)
    : m_config(std::make_unique<btDefaultCollisionConfiguration>()),
      m_dispatcher(std::make_unique<btCollisionDispatcher>(m_config.get())),
      m_broadphase(std::make_unique<btDbvtBroadphase>()),
      m_world(std::make_unique<btDiscreteDynamicsWorld>(m_dispatcher.get(), m_broadphase.get(), solver,
                                                        m_config.get())) {
    m_world->setGravity(btVector3(0, -10, 0));
}

SceneWorld::~SceneWorld() {
    // The world touches its bodies' broadphase proxies when it goes, so take them out first
    // (and the joints before the bodies they refer to).
    for (auto& j : m_ownedJoints) m_world->removeConstraint(j.get());
    for (auto& b : m_ownedBodies) m_world->removeRigidBody(b.get());
    m_world.reset();
}

int SceneWorld::numDynamicBodies() const {
    int n = 0;
    for (auto& b : m_bodies) n += b.dynamic ? 1 : 0;
    return n;
}

btBoxShape* SceneWorld::boxShape(const btVector3& halfExtents) {
    for (auto& s : m_shapes)
        if (s->getHalfExtentsWithMargin() == halfExtents) return s.get();
    m_shapes.push_back(std::make_unique<btBoxShape>(halfExtents));
    return m_shapes.back().get();
}

btRigidBody* SceneWorld::addStaticBox(const btVector3& halfExtents, const btTransform& transform) {
    btBoxShape* shape = boxShape(halfExtents);
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape);
    info.m_startWorldTransform = transform;
    info.m_friction = 0.8f;
    m_ownedBodies.push_back(std::make_unique<btRigidBody>(info));
    btRigidBody* body = m_ownedBodies.back().get();
    m_world->addRigidBody(body);
    m_bodies.push_back({body, halfExtents, false});
    return body;
}

btRigidBody* SceneWorld::addBox(const btVector3& halfExtents, const btTransform& transform, btScalar density,
                                const btVector3& linearVelocity) {
    btBoxShape* shape = boxShape(halfExtents);
    const btScalar mass = density * 8 * halfExtents.x() * halfExtents.y() * halfExtents.z();
    btVector3 inertia;
    shape->calculateLocalInertia(mass, inertia);
    m_motionStates.push_back(std::make_unique<btDefaultMotionState>(transform));
    btRigidBody::btRigidBodyConstructionInfo info(mass, m_motionStates.back().get(), shape, inertia);
    info.m_friction = 0.8f;
    m_ownedBodies.push_back(std::make_unique<btRigidBody>(info));
    btRigidBody* body = m_ownedBodies.back().get();
    body->setActivationState(DISABLE_DEACTIVATION);
    body->setLinearVelocity(linearVelocity);
    m_world->addRigidBody(body);
    m_bodies.push_back({body, halfExtents, true});
    return body;
}

btTypedConstraint* SceneWorld::addJoint(std::unique_ptr<btTypedConstraint> joint) {
    m_world->addConstraint(joint.get(), true);
    m_joints.push_back(joint.get());
    m_ownedJoints.push_back(std::move(joint));
    return m_joints.back();
}

}  // namespace btbench
