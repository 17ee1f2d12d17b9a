// The README's example, compiled and run: swap the solver into a btDiscreteDynamicsWorld and
// step a falling sphere once. Keep readmeExample() the same as the README's code block (its
// "... add bodies ..." is the sphere; the block's last lines hand back what the test checks).
#include "btOpenCLConstraintSolver.h"

#include <btBulletDynamicsCommon.h>

#include <catch2/catch.hpp>

#include <string>

namespace {

struct ReadmeResult {
    btScalar sphereVelocityY;  // after the step
    std::string deviceName;
    btOpenCLSolverStats stats;  // of the step
};

ReadmeResult readmeExample() {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;

    btOpenCLSolverConfig solverConfig;
    solverConfig.device = "cpu";  // or "" (env BT_OPENCL_DEVICE, else GPU, else CPU), "gpu", "0", "pthread"
    btOpenCLConstraintSolver solver(solverConfig);   // throws btOpenCLSolverError if no device fits
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
    return ReadmeResult{sphere.getLinearVelocity().y(), solver.getDeviceName(), solver.getLastStats()};
}

}  // namespace

TEST_CASE("the README's example steps a falling sphere", "[readme]") {
    // Any btOpenCLSolverError (no "cpu" device, a kernel that does not build, a failed step)
    // fails the test: the README promises none on a machine with an OpenCL CPU device.
    const ReadmeResult r = readmeExample();
    // One step of 1/60 s from rest under g = -10: v = -1/6, whichever solver applies gravity.
    // float arithmetic on a handful of operations: 1e-5 relative is far above its rounding.
    CHECK(r.sphereVelocityY == Approx(-10.0 / 60.0).epsilon(1e-5));
    CHECK_FALSE(r.deviceName.empty());
    // Our solver ran the step: the one sphere, in the air, with nothing to solve.
    CHECK(r.stats.numBodies == 1);
    CHECK(r.stats.numContactPoints == 0);
    CHECK(r.stats.numConstraintRows == 0);
    CHECK(r.stats.numJointRows == 0);
    CHECK(r.stats.msTotal > 0);
}
