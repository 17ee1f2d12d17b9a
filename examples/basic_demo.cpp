// Bullet's BasicDemo (examples/BasicDemo/BasicExample.cpp), headless, with its constraint solver
// swapped for btOpenCLConstraintSolver: a ground box and a 5 x 5 x 5 array of small boxes
// dropped onto it, stepped for 5 seconds at 60 Hz.
//
// Build it against an installed package (examples/CMakeLists.txt):
//     cmake -S examples -B build-examples -DCMAKE_PREFIX_PATH=<install prefix>
//     cmake --build build-examples && build-examples/basic_demo
#include <btBulletDynamicsCommon.h>
#include <btOpenCLConstraintSolver.h>

#include <cstdio>
#include <memory>
#include <vector>

int main() {
    btDefaultCollisionConfiguration collisionConfiguration;
    btCollisionDispatcher dispatcher(&collisionConfiguration);
    btDbvtBroadphase broadphase;

    // The one change to BasicDemo: this solver in place of btSequentialImpulseConstraintSolver.
    // The constructor throws btOpenCLSolverError when no OpenCL device fits (no driver, or none
    // named by BT_OPENCL_DEVICE); then the demo runs on Bullet's own solver.
    std::unique_ptr<btConstraintSolver> solver;
    btOpenCLConstraintSolver* openclSolver = nullptr;
    try {
        btOpenCLSolverConfig config;     // the device: env BT_OPENCL_DEVICE, else a GPU, else a CPU
        config.fallbackToBullet = true;  // a step that fails on the device is solved by Bullet's solver
        auto ours = std::make_unique<btOpenCLConstraintSolver>(config);
        openclSolver = ours.get();
        std::printf("solver: btOpenCLConstraintSolver %s on %s\n", BTOCL_VERSION_STRING,
                    ours->getDeviceName().c_str());
        solver = std::move(ours);
    } catch (const btOpenCLSolverError& e) {
        std::printf("solver: btSequentialImpulseConstraintSolver (no OpenCL solver: %s)\n", e.what());
        solver = std::make_unique<btSequentialImpulseConstraintSolver>();
    }

    // Declared before the world, so that they outlive it.
    btBoxShape groundShape(btVector3(50, 50, 50));
    btBoxShape boxShape(btVector3(0.1f, 0.1f, 0.1f));
    std::vector<std::unique_ptr<btRigidBody>> bodies;

    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, solver.get(), &collisionConfiguration);
    world.setGravity(btVector3(0, -10, 0));

    // The ground: static (mass 0), its top face at y = 0.
    btRigidBody::btRigidBodyConstructionInfo groundInfo(0, nullptr, &groundShape);
    groundInfo.m_startWorldTransform.setOrigin(btVector3(0, -50, 0));
    bodies.push_back(std::make_unique<btRigidBody>(groundInfo));
    world.addRigidBody(bodies.back().get());

    // The boxes: 1 kg, 0.2 m on a side, in a 5 x 5 x 5 array from 2 m up.
    const btScalar mass = 1;
    btVector3 inertia(0, 0, 0);
    boxShape.calculateLocalInertia(mass, inertia);
    std::vector<btRigidBody*> boxes;
    for (int k = 0; k < 5; ++k) {
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j < 5; ++j) {
                btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, &boxShape, inertia);
                info.m_startWorldTransform.setOrigin(btVector3(0.2f * i, 2 + 0.2f * k, 0.2f * j));
                bodies.push_back(std::make_unique<btRigidBody>(info));
                boxes.push_back(bodies.back().get());
                world.addRigidBody(boxes.back());
            }
        }
    }

    for (int step = 0; step < 300; ++step) {
        world.stepSimulation(1.0f / 60.0f);
    }

    // Where the boxes are after 5 s: a heap settles chaotically, and a box may still be sliding
    // off it, with Bullet's solver as with this one.
    btScalar top = -BT_LARGE_FLOAT, bottom = BT_LARGE_FLOAT, fastest = 0;
    for (const btRigidBody* box : boxes) {
        const btScalar y = box->getCenterOfMassPosition().y();
        top = btMax(top, y);
        bottom = btMin(bottom, y);
        fastest = btMax(fastest, box->getLinearVelocity().length());
    }
    std::printf("after 300 steps: top box at y = %.3f m, lowest box at y = %.3f m, fastest box %.3f m/s\n",
                top, bottom, fastest);

    if (openclSolver) {
        const btOpenCLSolverStats& stats = openclSolver->getLastStats();
        std::printf("last step: %d bodies, %d contact points, %d rows, %.3f ms, solved %s\n",
                    stats.numBodies, stats.numContactPoints, stats.numConstraintRows, stats.msTotal,
                    stats.solvedByBullet ? "by Bullet's solver (fallback)"
                    : stats.solvedOnHost ? "on the host" : "on the device");
    }

    for (auto& body : bodies) {  // as BasicDemo's exitPhysics
        world.removeRigidBody(body.get());
    }
    return 0;
}
