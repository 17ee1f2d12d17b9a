// Solvers in threads: several, each made, stepped and destroyed in a thread of its own while the
// others are, on either solve path and through the fallback to Bullet's solver. Each ends bitwise
// where the same run ends alone on the test's thread (one device gives the same outputs for the
// same inputs). CI runs these under ThreadSanitizer too (scripts/test-threads-tsan.sh), where a
// race on the library's process-wide state fails the run even when the results come out right.
#include "ParallelFrom.h"
#include "Scenes.h"
#include "WorldSnapshot.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <exception>
#include <string>
#include <thread>
#include <vector>

using namespace testworld;

namespace {

// One row whose linear Jacobians on its two bodies are not opposite (the second is not the
// first's negative): the solve record cannot hold it, a failure on our side that the fallback
// hands to Bullet's solver.
class SkewedJoint : public btTypedConstraint {
public:
    SkewedJoint(btRigidBody& a, btRigidBody& b) : btTypedConstraint(POINT2POINT_CONSTRAINT_TYPE, a, b) {}
    void getInfo1(btConstraintInfo1* info) override {
        info->m_numConstraintRows = 1;
        info->nub = 5;
    }
    void getInfo2(btConstraintInfo2* info) override {
        info->m_J1linearAxis[0] = 1;
        info->m_J2linearAxis[1] = -1;
    }
    void setParam(int, btScalar, int) override {}
    btScalar getParam(int, int) const override { return 0; }
};

struct Run {
    btOpenCLSolverConfig config;
    bool skewedJoint = false;  // with fallbackToBullet: every step solved by Bullet's solver
};

// A pile of 64 boxes, 30 steps; what the solver wrote to the bodies, as bytes. Uses no Catch
// macro: it runs in threads, which Catch's assertions do not support.
std::vector<unsigned char> runPile(const Run& run, int* fallbackSteps = nullptr) {
    btOpenCLConstraintSolver solver(run.config);
    btscenes::World w(&solver);
    btscenes::groundAndPile(w, 64);
    if (run.skewedJoint) w.addConstraint(std::make_unique<SkewedJoint>(*w.body(1), *w.body(2)));
    for (int s = 0; s < 30; ++s) w.step(kDt);
    if (fallbackSteps) *fallbackSteps = solver.getLastStats().numFallbackSteps;
    return solveOutputsOf(w.bodies(), std::vector<const btPersistentManifold*>{});
}

// Runs `run` on `threads` threads at once, each with its own solver and world.
std::vector<std::vector<unsigned char>> runInThreads(const Run& run, int threads, std::vector<std::string>& errors) {
    std::vector<std::vector<unsigned char>> results(static_cast<size_t>(threads));
    errors.assign(size_t(threads), "");
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            try {
                results[size_t(t)] = runPile(run);
            } catch (const std::exception& e) {
                errors[size_t(t)] = e.what();
            }
        });
    for (std::thread& thread : pool) thread.join();
    return results;
}

Run onPath(btOpenCLSolvePath path) {
    Run run;
    run.config.solvePath = path;
    run.config.wholeStepMaxRows = 0;  // every step split: the wide path sorts through its library each step
    return run;
}

// Three threads at once, twice: once with the host's loops on each solver's own thread, once
// with every loop on the host's pool of threads, which all solvers share (parallel loops give
// the serial loops' results, bitwise).
void requireSameInThreads(const Run& run) {
    const std::vector<unsigned char> alone = runPile(run);
    for (const bool pool : {false, true}) {
        const btocl::test::ParallelFrom threshold(pool ? 1 : btocl::kMinParallelItems);
        std::vector<std::string> errors;
        const std::vector<std::vector<unsigned char>> results = runInThreads(run, 3, errors);
        for (size_t t = 0; t < results.size(); ++t) {
            INFO((pool ? "loops on the pool" : "loops on the solvers' threads") << ", thread " << t);
            REQUIRE(errors[t] == "");
            CHECK(results[t] == alone);
        }
    }
}

}  // namespace

TEST_CASE("solvers made and stepped in threads at once end as each ends alone: serial path", "[threads]") {
    requireSameInThreads(onPath(btOpenCLSolvePath::Serial));
}

TEST_CASE("solvers made and stepped in threads at once end as each ends alone: wide path", "[threads]") {
    requireSameInThreads(onPath(btOpenCLSolvePath::Wide));
}

TEST_CASE("solvers made and stepped in threads at once end as each ends alone: split steps on the host",
          "[threads][host]") {
    // Split on the calling thread, solved in the vector unit's lanes where the CPU has AVX2, a
    // share of each set on each of the pool's threads (HostLaneSolve), which the solvers share:
    // a solver whose loop finds the pool taken runs every share on its own thread.
    Run run = onPath(btOpenCLSolvePath::Serial);
    run.config.hostStepMaxRows = 0;   // no step whole on the host ...
    run.config.splitStepsOnHost = 1;  // ... every split step there
    requireSameInThreads(run);
}

TEST_CASE("solvers in threads that fall back to Bullet's solver end as each ends alone", "[threads][fallback]") {
    for (const btOpenCLSolvePath path : {btOpenCLSolvePath::Serial, btOpenCLSolvePath::Wide}) {
        Run run = onPath(path);
        run.config.fallbackToBullet = true;
        run.skewedJoint = true;
        int fallbackSteps = 0;
        runPile(run, &fallbackSteps);
        REQUIRE(fallbackSteps == 30);  // the joint sent every step to Bullet's solver
        requireSameInThreads(run);
    }
}
