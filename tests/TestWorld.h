// The tests' Bullet world: the scenes' world (scenes/World.h, which owns every body it makes)
// with a solver of its own, stepped at a fixed 60 Hz under g = 9.81 m/s^2. Its solver is
// btSequentialImpulseConstraintSolver (SI), ours (validate = true: every step checks the split
// and batch invariants), or any solver the test passes in. Scenes to build in it: Scenes.h,
// JointScenes.h.
//
// Parity tests build one scene twice (Pair): a reference world stepped by SI and a candidate
// world stepped by ours, in lock step. BTOCL_PARITY_REFERENCE_ONLY switches the candidate's
// solver so the tests' logic and tolerances can be checked without our solver:
//   unset or "0" - btOpenCLConstraintSolver (the real test);
//   "1"          - SI on both sides (every comparison must hold exactly);
//   "shuffle"    - SI with SOLVER_RANDMIZE_ORDER on the candidate side: a different Gauss-Seidel
//                  order each iteration, as our batching gives; tolerances must hold for it too.
#pragma once

#include "btOpenCLConstraintSolver.h"
#include "scenes/World.h"

#include <btBulletDynamicsCommon.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace testworld {

using btscenes::at;
using btscenes::BodyOptions;

enum class SolverKind { Reference, OpenCL, ReferenceShuffled };

constexpr btScalar kDt = btScalar(1) / btScalar(60);  // the fixed 60 Hz step of every test
constexpr btScalar kG = btScalar(9.81);               // gravity, along -y

inline SolverKind candidateKind() {
    const char* env = std::getenv("BTOCL_PARITY_REFERENCE_ONLY");
    if (!env || std::string(env).empty() || std::string(env) == "0") return SolverKind::OpenCL;
    if (std::string(env) == "shuffle") return SolverKind::ReferenceShuffled;
    return SolverKind::Reference;
}

inline btOpenCLSolverConfig validatingConfig() {
    btOpenCLSolverConfig c;
    c.validate = true;  // every step checks the split and batch invariants
    // Steps past 4,096 rows (about 1,000 constraints) go through the global split on either
    // path, so that the parity scenes exercise the split and the sets as well as the whole-step
    // kernel; the serial path's own choice (whole up to about 128K rows on 2 cores) would solve
    // nearly every test scene whole. test_solver_api.cpp tests the automatic choice.
    c.wholeStepMaxRows = 4096;
    return c;
}

inline std::unique_ptr<btConstraintSolver> makeSolver(SolverKind kind, const btOpenCLSolverConfig& config) {
    if (kind == SolverKind::OpenCL) return std::make_unique<btOpenCLConstraintSolver>(config);
    return std::make_unique<btSequentialImpulseConstraintSolver>();  // shuffled or not: see World::step
}

namespace detail {
// The solver a World owns, made before the world around it and gone after it (a base class
// initialised ahead of btscenes::World).
struct OwnedSolver {
    std::unique_ptr<btConstraintSolver> solver;
};
}  // namespace detail

// One dynamics world with its own collision set-up and solver; owns every body it makes.
class World : private detail::OwnedSolver, public btscenes::World {
public:
    explicit World(SolverKind kind, const btOpenCLSolverConfig& config = validatingConfig())
        : World(makeSolver(kind, config)) {
        m_shuffleOrder = kind == SolverKind::ReferenceShuffled;
    }
    // With the solver the test passes in.
    explicit World(std::unique_ptr<btConstraintSolver> s)
        : detail::OwnedSolver{std::move(s)},
          btscenes::World(solver.get(), kG),
          m_openCL(dynamic_cast<btOpenCLConstraintSolver*>(solver.get())) {}

    // The solver settings with the fixed step, as the world hands them to its solver.
    btContactSolverInfo stepInfo() const {
        btContactSolverInfo i = dyn().getSolverInfo();
        i.m_timeStep = kDt;
        return i;
    }
    btOpenCLConstraintSolver* openCL() { return m_openCL; }  // null unless our solver runs here

    // One fixed 60 Hz step. With our solver, the invariants it validated must all hold.
    void step() {
        if (m_shuffleOrder) info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
        btscenes::World::step(kDt);
        if (m_openCL) {
            const btOpenCLSolverStats& s = m_openCL->getLastStats();
            if (s.validationFailures != 0)
                FAIL("step " << stepsTaken() << ": " << s.validationFailures
                             << " invariant failures: " << s.lastValidationMessage);
        }
    }

private:
    btOpenCLConstraintSolver* m_openCL = nullptr;
    bool m_shuffleOrder = false;  // SI in a new order every iteration (SolverKind::ReferenceShuffled)
};

// The same scene twice: `ref` with SI, `ours` with the candidate solver. Body i of one world is
// body i of the other.
struct Pair {
    World ref;
    World ours;

    explicit Pair(SolverKind candidate = candidateKind(), const btOpenCLSolverConfig& config = validatingConfig())
        : ref(SolverKind::Reference), ours(candidate, config) {}

    void build(const std::function<void(World&)>& scene) {
        scene(ref);
        scene(ours);
    }
    void configure(const std::function<void(btContactSolverInfo&)>& set) {
        set(ref.info());
        set(ours.info());
    }
    void step(int n = 1) {
        for (int i = 0; i < n; ++i) {
            ref.step();
            ours.step();
        }
    }
    // Steps n times, calling watch(ref, ours) after each step.
    void run(int n, const std::function<void(World&, World&)>& watch) {
        for (int i = 0; i < n; ++i) {
            step();
            watch(ref, ours);
        }
    }
};

// Every body's transform and velocities, as bytes: what two runs that must agree to the bit compare.
inline std::vector<unsigned char> bodyBytes(const World& w) {
    std::vector<unsigned char> out;
    auto append = [&](const void* p, size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        out.insert(out.end(), c, c + n);
    };
    for (const btRigidBody* b : w.bodies()) {
        append(&b->getWorldTransform(), sizeof(btTransform));
        append(&b->getLinearVelocity(), sizeof(btVector3));
        append(&b->getAngularVelocity(), sizeof(btVector3));
    }
    return out;
}

inline btScalar distance(const btVector3& a, const btVector3& b) { return (a - b).length(); }
inline btVector3 pos(const btRigidBody* b) { return b->getCenterOfMassPosition(); }

// Largest distance between body i of one world and body i of the other, over dynamic bodies.
inline btScalar maxPositionGap(const World& a, const World& b) {
    btScalar gap = 0;
    for (size_t i = 0; i < a.bodies().size(); ++i)
        if (!a.body(i)->isStaticOrKinematicObject()) gap = std::max(gap, distance(pos(a.body(i)), pos(b.body(i))));
    return gap;
}

// Largest distance of a dynamic body from where it started (`start` as recorded at build time).
inline btScalar maxDisplacement(const World& w, const std::vector<btVector3>& start) {
    btScalar d = 0;
    for (size_t i = 0; i < w.bodies().size(); ++i)
        if (!w.body(i)->isStaticOrKinematicObject()) d = std::max(d, distance(pos(w.body(i)), start[i]));
    return d;
}
inline std::vector<btVector3> positionsOf(const World& w) {
    std::vector<btVector3> p;
    for (const btRigidBody* b : w.bodies()) p.push_back(pos(b));
    return p;
}

// Body by body, b moved as a did: within 2 mm plus 5% of the way a's body went since `start`.
// 2 mm: the boxes of a column jitter by about 1 mm around rest (SI's do), so two runs that
// order the work differently can sit 2 mm apart; 5%: the friction bound of the sliding tests.
inline double worstExcessGap(const World& a, const World& b, const std::vector<btVector3>& start) {
    double worst = -1;  // largest gap - tolerance; <= 0 when all bodies agree
    for (size_t i = 0; i < a.bodies().size(); ++i) {
        if (a.body(i)->isStaticOrKinematicObject()) continue;
        const double tol = 2e-3 + 0.05 * distance(pos(a.body(i)), start[i]);
        worst = std::max(worst, double(distance(pos(a.body(i)), pos(b.body(i)))) - tol);
    }
    return worst;
}

// |a - b| <= rel * max(|a|, |b|, floor): a relative bound that does not vanish near zero.
inline bool closeRel(double a, double b, double rel, double floor) {
    return std::fabs(a - b) <= rel * std::max({std::fabs(a), std::fabs(b), floor});
}

}  // namespace testworld
