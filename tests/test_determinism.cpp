// Determinism: the same world stepped twice by our solver ends bitwise equal, however the
// device schedules its work.
#include "Scenes.h"
#include "ScopedEnv.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

using namespace testworld;
using btocl::test::ScopedEnv;

namespace {

std::vector<btTransform> runPile(int boxes, int steps, const btOpenCLSolverConfig& config = {}) {
    World w(SolverKind::OpenCL, config);
    groundAndPile(w, boxes);
    for (int s = 0; s < steps; ++s) w.step();
    std::vector<btTransform> out;
    for (const btRigidBody* b : w.bodies()) out.push_back(b->getWorldTransform());
    return out;
}

// A config with the default whole-step threshold, and one that splits every step.
std::vector<btOpenCLSolverConfig> wholeAndSplit() {
    btOpenCLSolverConfig split;
    split.wholeStepMaxRows = 0;
    return {btOpenCLSolverConfig{}, split};
}

size_t differingBodies(const std::vector<btTransform>& a, const std::vector<btTransform>& b) {
    size_t differing = 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::memcmp(&a[i], &b[i], sizeof(btTransform)) != 0) ++differing;
    return differing;
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

TEST_CASE("a split step ends the same whether the host reads the split back early or with the last wait",
          "[determinism]") {
    // Serial path: the claimed solve reads the set starts on the device, and the host takes the
    // split's summary only with the step's last wait. Validation reads the whole layout back
    // before the solve; neither may change a bit of the result or the counts.
    auto run = [](bool validate, btOpenCLSolverStats& stats) {
        btOpenCLSolverConfig config;
        config.wholeStepMaxRows = 0;  // every step split, on the device (a GPU would take it on the host)
        config.hostStepMaxRows = 0;
        config.validate = validate;
        World w(SolverKind::OpenCL, config);
        groundAndPile(w, 400);
        for (int s = 0; s < 40; ++s) w.step();
        stats = w.openCL()->getLastStats();
        std::vector<btTransform> out;
        for (const btRigidBody* b : w.bodies()) out.push_back(b->getWorldTransform());
        return out;
    };
    btOpenCLSolverStats late, early;
    const std::vector<btTransform> a = run(false, late), b = run(true, early);
    CAPTURE(late.numGroups, late.numCellGroups, early.numGroups, early.numCellGroups);
    REQUIRE_FALSE(late.solvedWholeStep);
    REQUIRE(late.numCellGroups > 4);
    CHECK(late.numGroups == early.numGroups);
    CHECK(late.numCellGroups == early.numCellGroups);
    CHECK(late.numOverflowConstraints == early.numOverflowConstraints);
    CHECK(early.validationFailures == 0);
    REQUIRE(a.size() == b.size());
    size_t differing = 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::memcmp(&a[i], &b[i], sizeof(btTransform)) != 0) ++differing;
    CHECK(differing == 0);
}

TEST_CASE("a pile ends bitwise the same when the step's arrays are copied from pinned memory, as on a GPU",
          "[determinism]") {
    // BT_OPENCL_TRANSFERS=copy: PoCL copies to and from the device as a GPU does, and the solver
    // puts the step's host arrays in pinned memory (PinnedHostMemory). Whole and split steps.
    for (const btOpenCLSolverConfig& config : wholeAndSplit()) {
        INFO("wholeStepMaxRows " << config.wholeStepMaxRows);
        const std::vector<btTransform> inPlace = runPile(300, 30, config);
        std::vector<btTransform> copied;
        {
            const ScopedEnv copy("BT_OPENCL_TRANSFERS", "copy");
            copied = runPile(300, 30, config);
        }
        REQUIRE(inPlace.size() == copied.size());
        CHECK(differingBodies(inPlace, copied) == 0);
    }
    const ScopedEnv bad("BT_OPENCL_TRANSFERS", "dma");
    CHECK_THROWS_WITH(btOpenCLConstraintSolver(), Catch::Contains("BT_OPENCL_TRANSFERS is 'dma'"));
}

TEST_CASE("with SOLVER_RANDMIZE_ORDER two runs end bitwise equal, and reset() starts the orders again",
          "[determinism][modes]") {
    // The shuffled orders come from the steps run since the solver was made or reset (as SI's
    // random sequence restarts at its reset()), never from the device's scheduling. Whole and
    // split steps.
    for (const btOpenCLSolverConfig& config : wholeAndSplit()) {
        INFO("wholeStepMaxRows " << config.wholeStepMaxRows);
        auto run = [&config](bool randomized, int resetBefore) {
            World w(SolverKind::OpenCL, config);
            groundAndPile(w, 300);
            if (randomized) w.info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
            for (int s = 0; s < 30; ++s) {
                if (s == resetBefore) w.openCL()->reset();
                w.step();
            }
            std::vector<btTransform> out;
            for (const btRigidBody* b : w.bodies()) out.push_back(b->getWorldTransform());
            return out;
        };
        const std::vector<btTransform> randomized = run(true, -1);
        CHECK(differingBodies(randomized, run(true, -1)) == 0);
        CHECK(differingBodies(randomized, run(false, -1)) > 0);
        CHECK(differingBodies(randomized, run(true, 15)) > 0);  // steps 15 on take steps 0 on's orders
        CHECK(differingBodies(run(false, -1), run(false, 15)) == 0);  // the fixed order has none to restart
    }
}
