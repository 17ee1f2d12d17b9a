// Determinism: the same world stepped twice by our solver ends bitwise equal, however the
// device schedules its work.
#include "Scenes.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

using namespace testworld;

namespace {

std::vector<btTransform> runPile(int boxes, int steps) {
    World w(SolverKind::OpenCL);
    groundAndPile(w, boxes);
    for (int s = 0; s < steps; ++s) w.step();
    std::vector<btTransform> out;
    for (const btRigidBody* b : w.bodies()) out.push_back(b->getWorldTransform());
    return out;
}

}  // namespace

TEST_CASE("two runs of a 1,000-box pile end bitwise equal", "[determinism]") {
    // Groups of a set run on both cores in any order, but share no dynamic body, and batches
    // inside a group are solved in a fixed order: nothing the scheduler does reaches the result.
    const std::vector<btTransform> a = runPile(1000, 40);
    const std::vector<btTransform> b = runPile(1000, 40);
    REQUIRE(a.size() == b.size());
    size_t differing = 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::memcmp(&a[i], &b[i], sizeof(btTransform)) != 0) ++differing;
    CHECK(differing == 0);
}
