// The README's example, compiled and run: swap the solver into a btDiscreteDynamicsWorld and
// step a falling sphere once. Keep readmeExample() the same as the README's code block.
#include "btOpenCLConstraintSolver.h"

#include <btBulletDynamicsCommon.h>

#include <catch2/catch.hpp>

#include <string>

namespace {

// Returns the sphere's vertical velocity after one step.
btScalar readmeExample() {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;

    btOpenCLSolverConfig solverConfig;
    solverConfig.device = "cpu";  // or "" (env BT_OPENCL_DEVICE, else GPU, else CPU), "gpu", "0", "pthread"
    btOpenCLConstraintSolver solver(solverConfig);
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    world.setGravity(btVector3(0, -10, 0));

    btSphereShape shape(0.5f);
    btVector3 inertia(0, 0, 0);
    shape.calculateLocalInertia(1.0f, inertia);
    btDefaultMotionState motion(btTransform(btQuaternion::getIdentity(), btVector3(0, 10, 0)));
    btRigidBody sphere(btRigidBody::btRigidBodyConstructionInfo(1.0f, &motion, &shape, inertia));
    world.addRigidBody(&sphere);

    world.stepSimulation(1.0f / 60.0f);

    world.removeRigidBody(&sphere);
    return sphere.getLinearVelocity().y();
}

}  // namespace

TEST_CASE("the README's example steps a falling sphere", "[readme]") {
    btScalar vy = 0;
    try {
        vy = readmeExample();
    } catch (const btOpenCLSolverError& e) {
        // While the device solve is being written the solver throws "not implemented"; that case
        // alone is let through (the lead removes this once the solver works). Any other error fails.
        if (std::string(e.what()).find("not implemented") == std::string::npos) throw;
        WARN("solver not implemented yet: " << e.what());
        return;
    }
    // One step of 1/60 s from rest under g = -10: v = -1/6, whichever solver applies gravity.
    // float arithmetic on a handful of operations: 1e-5 relative is far above its rounding.
    CHECK(vy == Approx(-10.0 / 60.0).epsilon(1e-5));
}
