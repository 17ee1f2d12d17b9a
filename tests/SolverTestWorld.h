// A small Bullet world for the solver's core tests: ground plus boxes, owned in one place.
#pragma once

#include "btOpenCLConstraintSolver.h"

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <vector>

// Our solver as the tests use it: the split and batch invariants checked every step.
inline std::unique_ptr<btConstraintSolver> makeValidatingSolver() {
    btOpenCLSolverConfig config;
    config.validate = true;
    return std::make_unique<btOpenCLConstraintSolver>(config);
}

struct SolverTestWorld {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    std::unique_ptr<btConstraintSolver> solver;
    std::unique_ptr<btDiscreteDynamicsWorld> world;
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btMotionState>> motions;
    std::vector<std::unique_ptr<btRigidBody>> bodies;

    explicit SolverTestWorld(std::unique_ptr<btConstraintSolver> s) : solver(std::move(s)) {
        world = std::make_unique<btDiscreteDynamicsWorld>(&dispatcher, &broadphase, solver.get(), &config);
        world->setGravity(btVector3(0, -10, 0));
    }
    ~SolverTestWorld() {
        for (auto& b : bodies) world->removeRigidBody(b.get());
    }

    btRigidBody* add(btCollisionShape* shape, btScalar mass, const btVector3& at) {
        shapes.emplace_back(shape);
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shape->calculateLocalInertia(mass, inertia);
        motions.emplace_back(new btDefaultMotionState(btTransform(btQuaternion::getIdentity(), at)));
        btRigidBody::btRigidBodyConstructionInfo ci(mass, motions.back().get(), shape, inertia);
        bodies.emplace_back(new btRigidBody(ci));
        world->addRigidBody(bodies.back().get());
        return bodies.back().get();
    }
    // The world's contact manifolds, as the dispatcher holds them now.
    std::vector<btPersistentManifold*> manifolds() {
        std::vector<btPersistentManifold*> out;
        for (int i = 0; i < dispatcher.getNumManifolds(); ++i) out.push_back(dispatcher.getManifoldByIndexInternal(i));
        return out;
    }
    // The world's solver settings with the fixed step the tests use.
    btContactSolverInfo stepInfo() {
        btContactSolverInfo info = world->getSolverInfo();
        info.m_timeStep = 1.f / 60;
        return info;
    }

    btRigidBody* addGround() { return add(new btBoxShape(btVector3(50, 1, 50)), 0, btVector3(0, -1, 0)); }
    btRigidBody* addBox(const btVector3& at, btScalar half = 0.5f, btScalar mass = 1) {
        return add(new btBoxShape(btVector3(half, half, half)), mass, at);
    }
    // A loose pile: rows of boxes dropped in layers with small offsets (deterministic).
    void addPile(int count) {
        for (int i = 0; i < count; ++i) {
            const int layer = i / 16, k = i % 16;
            addBox(btVector3(btScalar(k % 4) * 1.1f + 0.05f * btScalar(layer % 3), 0.5f + btScalar(layer) * 1.05f,
                             btScalar(k / 4) * 1.1f - 0.04f * btScalar(layer % 2)));
        }
    }
};
