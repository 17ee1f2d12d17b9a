// A Bullet world that owns everything a scene puts in it (shapes, bodies, motion states, joints),
// built around a constraint solver it does not own. Two SceneWorlds built by the same scene
// function with the same options hold the same bodies in the same order, so body i of one
// corresponds to body i of the other.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <vector>

namespace btbench {

struct BodyRecord {
    btRigidBody* body;
    btVector3 halfExtents;  // the box's half extents (every shape here is a box)
    bool dynamic;
};

class SceneWorld {
public:
    explicit SceneWorld(btConstraintSolver* solver);
    ~SceneWorld();
    SceneWorld(const SceneWorld&) = delete;
    SceneWorld& operator=(const SceneWorld&) = delete;

    btDiscreteDynamicsWorld& world() { return *m_world; }
    btCollisionDispatcher& dispatcher() { return *m_dispatcher; }
    const std::vector<BodyRecord>& bodies() const { return m_bodies; }
    int numDynamicBodies() const;

    // A static box (inverse mass 0).
    btRigidBody* addStaticBox(const btVector3& halfExtents, const btTransform& transform);
    // A dynamic box of mass density x volume; never deactivates, so every step the solver
    // sees the whole scene (a benchmark must not measure sleeping bodies).
    btRigidBody* addBox(const btVector3& halfExtents, const btTransform& transform, btScalar density,
                        const btVector3& linearVelocity = btVector3(0, 0, 0));
    // A joint between bodies of this world; its two bodies no longer collide with each other
    // (btDiscreteDynamicsWorld's disableCollisionsBetweenLinkedBodies, as linked bodies usually are).
    btTypedConstraint* addJoint(std::unique_ptr<btTypedConstraint> joint);
    const std::vector<btTypedConstraint*>& joints() const { return m_joints; }

private:
    btBoxShape* boxShape(const btVector3& halfExtents);  // shared per size

    std::unique_ptr<btDefaultCollisionConfiguration> m_config;
    std::unique_ptr<btCollisionDispatcher> m_dispatcher;
    std::unique_ptr<btBroadphaseInterface> m_broadphase;
    std::unique_ptr<btDiscreteDynamicsWorld> m_world;
    std::vector<std::unique_ptr<btBoxShape>> m_shapes;
    std::vector<std::unique_ptr<btMotionState>> m_motionStates;
    std::vector<std::unique_ptr<btRigidBody>> m_ownedBodies;
    std::vector<BodyRecord> m_bodies;
    std::vector<std::unique_ptr<btTypedConstraint>> m_ownedJoints;
    std::vector<btTypedConstraint*> m_joints;
};

}  // namespace btbench
