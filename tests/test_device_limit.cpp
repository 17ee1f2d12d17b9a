// A step past the device's largest allocation, for real. PoCL reads POCL_MEMORY_LIMIT (GB) only
// at start-up, so this runs as a ctest of its own (device_memory_limit, POCL_MEMORY_LIMIT=1:
// allocations of at most 256 MB) and is hidden ([.]) from the other runs of the test program.
#include "DeviceFit.h"
#include "FaultInjection.h"
#include "TestWorld.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <limits>
#include <memory>
#include <string>
#include <vector>

using namespace testworld;

namespace {

// Boxes falling at 1 m/s onto a static slab, each with several made-up manifolds of 4 points
// (rolling friction, two friction directions). No world: only what the solver reads.
struct HandMadeContacts {
    btBoxShape shape{btVector3(btScalar(0.5), btScalar(0.5), btScalar(0.5))};
    btBoxShape slabShape{btVector3(1000, 1, 1000)};
    std::unique_ptr<btRigidBody> slab;
    std::vector<std::unique_ptr<btRigidBody>> boxes;
    std::vector<std::unique_ptr<btPersistentManifold>> manifolds;
    std::vector<btCollisionObject*> objects;
    std::vector<btPersistentManifold*> manifoldList;

    explicit HandMadeContacts(size_t points) {
        btRigidBody::btRigidBodyConstructionInfo slabInfo(0, nullptr, &slabShape);
        slabInfo.m_startWorldTransform.setOrigin(btVector3(0, -1, 0));
        slab = std::make_unique<btRigidBody>(slabInfo);
        const int numBoxes = 20000;
        for (int i = 0; i < numBoxes; ++i) {
            const btScalar third = btScalar(1) / 6;
            btRigidBody::btRigidBodyConstructionInfo ci(1, nullptr, &shape, btVector3(third, third, third));
            ci.m_startWorldTransform.setOrigin(btVector3(btScalar(2 * (i % 200)), btScalar(0.5), btScalar(2 * (i / 200))));
            boxes.push_back(std::make_unique<btRigidBody>(ci));
            boxes.back()->setLinearVelocity(btVector3(0, -1, 0));
            objects.push_back(boxes.back().get());
        }
        for (size_t m = 0; m < (points + 3) / 4; ++m) {
            btRigidBody* box = boxes[m % boxes.size()].get();
            manifolds.push_back(std::make_unique<btPersistentManifold>(box, slab.get(), 0, btScalar(0.02), btScalar(0.02)));
            const btVector3 c = box->getWorldTransform().getOrigin();
            for (int k = 0; k < 4; ++k) {
                const btVector3 corner(btScalar(k & 1 ? 0.5 : -0.5), btScalar(-0.5), btScalar(k & 2 ? 0.5 : -0.5));
                btManifoldPoint pt(corner, btVector3(c.x() + corner.x(), 0, c.z() + corner.z()), btVector3(0, 1, 0),
                                   btScalar(-0.001));
                pt.m_positionWorldOnA = c + corner;
                pt.m_positionWorldOnB = pt.m_localPointB;
                pt.m_combinedFriction = btScalar(0.5);
                pt.m_combinedRollingFriction = btScalar(0.01);  // 3 rolling rows a point: fewer points needed
                manifolds.back()->addManifoldPoint(pt);
            }
            manifoldList.push_back(manifolds.back().get());
        }
    }
    void solve(btConstraintSolver& solver) {
        btContactSolverInfo info;
        info.m_timeStep = kDt;
        info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
        info.m_numIterations = 2;  // enough to stop the boxes; Bullet's solver takes its time over 2M rows
        solver.solveGroup(objects.data(), int(objects.size()), manifoldList.data(), int(manifoldList.size()), nullptr,
                          0, info, nullptr, nullptr);
    }
};

}  // namespace

TEST_CASE("a step past the device's largest allocation is refused before its first enqueue, or solved by Bullet's solver",
          "[.][device-limit]") {
    const btocl::DeviceLimits limits = btocl::deviceLimitsOf(btocl::OclRuntime(""));
    INFO("CL_DEVICE_MAX_MEM_ALLOC_SIZE = " << limits.maxAlloc << " (this test runs under POCL_MEMORY_LIMIT=1)");
    REQUIRE(limits.maxAlloc <= (size_t(256) << 20));
    // A normal, two friction and three rolling rows a point: a few more points than the rows
    // buffer fits.
    size_t rowSize = 0;
    for (const btocl::StepBuffer& b : btocl::stepBuffers(btocl::StepCounts{}))
        if (std::string(b.name) == "rows") rowSize = b.elementSize;
    REQUIRE(rowSize > 0);
    HandMadeContacts scene(limits.maxAlloc / (6 * rowSize) + 4000);

    auto ours = std::make_unique<btOpenCLConstraintSolver>();
    btocl::injectDeviceFault(std::numeric_limits<long>::max());  // counts OpenCL checks, fails none
    std::string message;
    try {
        scene.solve(*ours);
    } catch (const btOpenCLSolverError& e) {
        message = e.what();
    }
    const long checks = btocl::deviceResultsChecked();
    btocl::injectDeviceFault(0);
    INFO("message: " << message);
    CHECK(message.find("the rows buffer needs") != std::string::npos);
    CHECK(message.find("CL_DEVICE_MAX_MEM_ALLOC_SIZE = " + std::to_string(limits.maxAlloc)) != std::string::npos);
    CHECK(checks == 0);  // refused before any OpenCL call of the step
    CHECK(scene.boxes[7]->getLinearVelocity() == btVector3(0, -1, 0));
    CHECK(scene.manifolds[7]->getContactPoint(0).m_appliedImpulse == 0);
    ours.reset();  // as the user did, right after the error

    btOpenCLSolverConfig config;
    config.fallbackToBullet = true;
    btOpenCLConstraintSolver fallingBack(config);
    REQUIRE_NOTHROW(scene.solve(fallingBack));
    const btOpenCLSolverStats& stats = fallingBack.getLastStats();
    CHECK(stats.solvedByBullet);
    CHECK(stats.numFallbackSteps == 1);
    CHECK(stats.lastFallbackReason.find("CL_DEVICE_MAX_MEM_ALLOC_SIZE") != std::string::npos);
    CHECK(scene.boxes[7]->getLinearVelocity().y() > btScalar(-0.1));  // Bullet's solver stopped the boxes
    CHECK(scene.manifolds[7]->getContactPoint(0).m_appliedImpulse > 0);
}
