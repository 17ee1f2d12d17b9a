// The host's loops over bodies, manifolds and points (HostParallel.h) give the step they give on
// one thread, bitwise: every loop writes only its own item's records. Each scene runs twice in
// this process, once with every loop on the calling thread and once with every loop in
// parallel (the threshold lowered to one item), and the two worlds are compared field by field.
#include "HostParallel.h"
#include "ParallelFrom.h"
#include "Scenes.h"
#include "WorldSnapshot.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <limits>
#include <string>
#include <vector>

using namespace testworld;
using btocl::test::ParallelFrom;

namespace {

// A pile of 300 boxes (about 1,000 manifolds at rest) for 90 steps, with two friction
// directions, rolling friction, and split impulse, which each take a branch of the gather.
std::vector<unsigned char> pileAfter90Steps(size_t minItems) {
    ParallelFrom threshold(minItems);
    World w(SolverKind::OpenCL);
    groundAndPile(w, 300);
    for (btRigidBody* b : w.bodies()) b->setRollingFriction(btScalar(0.05));
    w.dyn().getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    w.dyn().getSolverInfo().m_splitImpulse = true;
    for (int s = 0; s < 90; ++s) w.step();
    REQUIRE(w.manifolds().size() > 300);
    return solveOutputsOf(w.bodies(), w.manifolds());
}

// Chains of 12 links swinging down onto the ground, their joints of three kinds (point-to-point,
// hinge with a limit, 6-DoF spring), 60 steps; what the step writes plus each joint's impulse.
std::vector<unsigned char> chainsAfter60Steps(size_t minItems) {
    ParallelFrom threshold(minItems);
    World w(SolverKind::OpenCL);
    w.addGround();
    std::vector<btTypedConstraint*> joints;
    for (int chain = 0; chain < 6; ++chain) {
        btRigidBody* previous = nullptr;
        for (int k = 0; k < 12; ++k) {
            btRigidBody* link = w.addUnitBox(btVector3(btScalar(1.1 * k), 14, btScalar(3 * chain)));
            if (!previous) {
                joints.push_back(w.addConstraint(std::make_unique<btPoint2PointConstraint>(*link, btVector3(-0.55f, 0, 0))));
            } else if (k % 3 == 0) {
                joints.push_back(w.addConstraint(std::make_unique<btPoint2PointConstraint>(
                    *previous, *link, btVector3(0.55f, 0, 0), btVector3(-0.55f, 0, 0))));
            } else if (k % 3 == 1) {
                auto hinge = std::make_unique<btHingeConstraint>(*previous, *link, btVector3(0.55f, 0, 0),
                                                                 btVector3(-0.55f, 0, 0), btVector3(0, 0, 1), btVector3(0, 0, 1));
                hinge->setLimit(-1, 1);
                joints.push_back(w.addConstraint(std::move(hinge)));
            } else {
                auto spring = std::make_unique<btGeneric6DofSpring2Constraint>(
                    *previous, *link, btTransform(btQuaternion::getIdentity(), btVector3(0.55f, 0, 0)),
                    btTransform(btQuaternion::getIdentity(), btVector3(-0.55f, 0, 0)));
                spring->setLinearLowerLimit(btVector3(0, 0, 0));
                spring->setLinearUpperLimit(btVector3(0, 0, 0));
                spring->setAngularLowerLimit(btVector3(-0.5f, -0.5f, -0.5f));
                spring->setAngularUpperLimit(btVector3(0.5f, 0.5f, 0.5f));
                spring->enableSpring(5, true);
                spring->setStiffness(5, 20);
                joints.push_back(w.addConstraint(std::move(spring)));
            }
            previous = link;
        }
    }
    for (int s = 0; s < 60; ++s) w.step();
    std::vector<unsigned char> out = solveOutputsOf(w.bodies(), w.manifolds());
    for (const btTypedConstraint* j : joints) {
        const btScalar impulse = j->getAppliedImpulse();
        out.insert(out.end(), reinterpret_cast<const unsigned char*>(&impulse),
                   reinterpret_cast<const unsigned char*>(&impulse) + sizeof(btScalar));
    }
    return out;
}

}  // namespace

TEST_CASE("the joints' rows set up in parallel give the same steps as on one thread, bitwise", "[host][parallel][joints]") {
    const std::vector<unsigned char> serial = chainsAfter60Steps(std::numeric_limits<size_t>::max());
    const std::vector<unsigned char> parallel = chainsAfter60Steps(1);
    REQUIRE(serial.size() == parallel.size());
    CHECK(std::memcmp(serial.data(), parallel.data(), serial.size()) == 0);
}

TEST_CASE("the host's loops give the same steps in parallel as on one thread, bitwise", "[host][parallel]") {
    INFO("host threads: " << btocl::hostThreads());
    const std::vector<unsigned char> serial = pileAfter90Steps(std::numeric_limits<size_t>::max());
    const std::vector<unsigned char> parallel = pileAfter90Steps(1);
    REQUIRE(serial.size() == parallel.size());
    CHECK(std::memcmp(serial.data(), parallel.data(), serial.size()) == 0);
}

TEST_CASE("a bad body found by a parallel loop is reported as the serial loop reports it", "[host][parallel][errors]") {
    // Two bodies with a NaN velocity: both loops name the first of them in the world's order.
    auto messageOf = [](size_t minItems) {
        ParallelFrom threshold(minItems);
        World w(SolverKind::OpenCL);
        groundAndPile(w, 64);
        for (int s = 0; s < 20; ++s) w.step();
        const btScalar nan = std::numeric_limits<btScalar>::quiet_NaN();
        w.body(50)->setLinearVelocity(btVector3(nan, 0, 0));
        w.body(12)->setLinearVelocity(btVector3(0, nan, 0));
        std::string message;
        try {
            w.step();
        } catch (const btOpenCLSolverError& e) {
            message = e.what();
        }
        return message;
    };
    const std::string serial = messageOf(std::numeric_limits<size_t>::max()), parallel = messageOf(1);
    INFO("serial: " << serial);
    REQUIRE_FALSE(serial.empty());
    CHECK(parallel == serial);
}

TEST_CASE("parallelFor runs every item once, nested and from two threads at a time", "[host][parallel]") {
    ParallelFrom threshold(1);
    const size_t n = 100000;
    auto countEach = [n] {
        std::vector<int> hits(n, 0);
        btocl::parallelFor(n, [&](size_t i) { hits[i] += 1; });
        return std::count(hits.begin(), hits.end(), 1) == long(n);
    };
    CHECK(countEach());
    // A loop inside a loop's item runs on that item's thread.
    std::vector<int> inner(64 * 64, 0);
    btocl::parallelFor(64, [&](size_t i) { btocl::parallelFor(64, [&](size_t j) { inner[i * 64 + j] += 1; }); });
    CHECK(std::count(inner.begin(), inner.end(), 1) == long(inner.size()));
    // Two threads' loops at once: one gets the pool, the other runs on its own thread.
    bool a = false, b = false;
    std::thread other([&] { a = countEach(); });
    b = countEach();
    other.join();
    CHECK(a);
    CHECK(b);
}

TEST_CASE("parallelFor rethrows the exception of the lowest index", "[host][parallel][errors]") {
    ParallelFrom threshold(1);
    std::vector<size_t> throwing{99000, 70000, 30001, 30000};
    std::string message;
    try {
        btocl::parallelFor(100000, [&](size_t i) {
            if (std::find(throwing.begin(), throwing.end(), i) != throwing.end()) throw std::runtime_error(std::to_string(i));
        });
    } catch (const std::runtime_error& e) {
        message = e.what();
    }
    CHECK(message == "30000");
}

TEST_CASE("parallelFor's loops back to back each run their own items", "[host][parallel]") {
    // Short loops one after another: a worker that wakes late must join the loop that is running
    // then, or none, never run one loop's items with another's function.
    ParallelFrom threshold(1);
    bool allRight = true;
    for (int loop = 0; loop < 3000; ++loop) {
        std::vector<int> hits(size_t(1 + loop % 37), 0);
        btocl::parallelFor(hits.size(), [&](size_t i) { hits[i] += loop + 1; });
        for (int h : hits) allRight = allRight && h == loop + 1;
    }
    CHECK(allRight);
}

TEST_CASE("shared steps run every part once, each step after every part of the steps before", "[host][parallel]") {
    // runSharedSteps: thread i takes part i of each step, and a part left untaken is run by
    // another thread. Whoever runs it, each part runs once, and never before every part of the
    // steps before it has finished; on the pool (awake or asleep, so that the worker comes late
    // or at once), on the calling thread alone, and from two threads at once (one of which finds
    // the pool taken).
    const int shares = std::max(2, btocl::hostThreads());
    auto runRight = [&](int numSteps, bool onPool) {
        std::vector<std::atomic<int>> runs(size_t(numSteps) * size_t(shares));
        std::atomic<int> finished{0};
        std::atomic<bool> early{false};
        btocl::shareSteps(numSteps, shares, onPool, [&](int step, int share) {
            if (finished.load() < step * shares) early = true;
            for (volatile int spin = 0; spin < (step * 7 + share * 13) % 200; ++spin) {
            }
            runs[size_t(step) * size_t(shares) + size_t(share)].fetch_add(1);
            finished.fetch_add(1);
        });
        return !early && std::all_of(runs.begin(), runs.end(), [](const std::atomic<int>& r) { return r == 1; });
    };
    bool allRight = true;
    for (int round = 0; round < 200; ++round) {
        if (round % 2 == 0) btocl::prewakeHostThreads(std::chrono::microseconds(2000));
        allRight = allRight && runRight(1 + round % 40, true);
    }
    btocl::restHostThreads();
    for (int round = 0; round < 20; ++round) allRight = allRight && runRight(1 + round, false);
    CHECK(allRight);
    bool otherRight = true;
    std::thread other([&] {
        for (int round = 0; round < 100; ++round) otherRight = otherRight && runRight(5 + round % 20, true);
    });
    for (int round = 0; round < 100; ++round) allRight = allRight && runRight(5 + round % 20, true);
    other.join();
    CHECK(allRight);
    CHECK(otherRight);
}

TEST_CASE("parallelFor's loops run right around pre-wakes of the pool", "[host][parallel]") {
    // A pre-wake leaves the workers waiting awake for a loop, up to a deadline: loops that start
    // within it, after it, or while another thread pre-wakes the pool each run their own items
    // once, and the pool still stops (the test's end) with workers awake or asleep.
    ParallelFrom threshold(1);
    auto loopRight = [](int loop) {
        std::vector<int> hits(size_t(1 + loop % 53) * 97, 0);
        btocl::parallelFor(hits.size(), [&](size_t i) { hits[i] += loop + 1; });
        return std::all_of(hits.begin(), hits.end(), [&](int h) { return h == loop + 1; });
    };
    bool allRight = true;
    for (int loop = 0; loop < 600; ++loop) {
        if (loop % 3 == 0) btocl::prewakeHostThreads(std::chrono::microseconds(loop % 2 ? 2000 : 0));
        if (loop % 50 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(3));  // past the deadline
        allRight = allRight && loopRight(loop);
    }
    std::atomic<bool> stop{false};
    std::thread waker([&] {
        while (!stop) btocl::prewakeHostThreads(std::chrono::microseconds(500));
    });
    for (int loop = 0; loop < 600; ++loop) allRight = allRight && loopRight(loop);
    stop = true;
    waker.join();
    CHECK(allRight);
}

TEST_CASE("a loop below the threshold takes the pool while it waits awake, and not once it rests",
          "[host][parallel]") {
    if (btocl::hostThreads() < 2) {
        WARN("one hardware thread: no pool to wait awake");
        return;
    }
    // Loops of 2,000 items, under the threshold of 8,000 but above its share for an awake pool.
    ParallelFrom threshold(8000);
    const size_t n = 2000;
    static_assert(8000 / btocl::kAwakeThresholdDivisor <= 2000, "the loop is big enough for an awake pool");
    // Whether another thread ran one of the loop's items: the first item waits (up to 2 s) for
    // one to, so a loop on the calling thread alone says no rather than hang.
    auto ranOnTwoThreads = [n] {
        const std::thread::id caller = std::this_thread::get_id();
        std::atomic<bool> other{false};
        std::vector<int> hits(n, 0);
        btocl::parallelFor(n, [&](size_t i) {
            hits[i] += 1;
            if (std::this_thread::get_id() != caller) other = true;
            if (i == 0) {
                const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);
                while (!other && std::chrono::steady_clock::now() < until) std::this_thread::yield();
            }
        });
        REQUIRE(std::count(hits.begin(), hits.end(), 1) == long(n));
        return other.load();
    };
    btocl::prewakeHostThreads(std::chrono::seconds(30));
    CHECK(btocl::hostThreadsAwake());
    CHECK(ranOnTwoThreads());
    CHECK(ranOnTwoThreads());  // and the next loop within the deadline
    btocl::restHostThreads();
    CHECK_FALSE(btocl::hostThreadsAwake());
    CHECK_FALSE(ranOnTwoThreads());
}
