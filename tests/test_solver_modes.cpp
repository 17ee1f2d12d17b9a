// The solver-mode flags that change the order of the solve (btContactSolverInfo::m_solverMode):
// SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS, which solves each point's friction rows
// right after its normal row as Bullet's solver does, and SOLVER_RANDMIZE_ORDER, which walks each
// velocity pass in shuffled orders that are the same from run to run. The flags that Bullet's
// solver reads nowhere change nothing here either.
#include "GatherAndSolve.h"
#include "HostSolve.h"
#include "Scenes.h"
#include "SerialLayout.h"
#include "WorldSnapshot.h"
#include "row_solve.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

using namespace btocl;
using namespace btocl::test;
using testworld::SolverKind;
using testworld::World;

namespace {

// A settled pile whose boxes then slide sideways: every point's friction rows act.
void slidingPile(World& w) {
    testworld::groundAndPile(w, 48);
    for (int s = 0; s < 30; ++s) w.step();
    for (size_t i = 1; i < w.bodies().size(); ++i)
        w.body(i)->setLinearVelocity(btVector3(btScalar(0.4) + btScalar(0.01) * btScalar(i), 0, btScalar(-0.3)));
}

// Every body's velocity after one step solved by our host reference in SI's order (a serial
// layout: the manifolds in order, one batch each) under `info`, as the write-back would set it.
std::vector<btVector3> ourVelocities(World& w, const btContactSolverInfo& info) {
    StepProblem p = gatherProblem(w, info, RowSetup::Host);
    solveOnHost(p, buildSerialLayout(int(p.constraints.size())), solveSettingsOf(info, false));
    std::vector<btVector3> v;
    for (size_t i = 1; i < p.bodies.size(); ++i)
        v.push_back(toVector3(p.bodies[i].linearVelocity) + toVector3(p.deltas[i].deltaLinearVelocity) +
                    toVector3(p.bodies[i].externalForceImpulse));
    return v;
}

// The same step by SI (which writes it to the world): the bodies' velocities, in the gather's order.
std::vector<btVector3> siVelocities(World& w, const btContactSolverInfo& info) {
    GatheredStep g = gatherStep(w, info, RowSetup::Host);  // for the bodies' order only
    btSequentialImpulseConstraintSolver si;
    btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
    std::vector<btPersistentManifold*> manifolds = w.manifolds();
    si.solveGroup(&objects[0], objects.size(), manifolds.data(), int(manifolds.size()), nullptr, 0, info, nullptr,
                  &w.dispatcher());
    std::vector<btVector3> v;
    for (size_t i = 1; i < g.bullet.original.size(); ++i) v.push_back(g.bullet.original[i]->getLinearVelocity());
    return v;
}

// What a device solve leaves, as bytes: every body's changes and every row's impulse.
std::vector<unsigned char> solveOutputs(const StepProblem& p) {
    std::vector<unsigned char> out(p.deltas.size() * sizeof(btoclBodyDelta) + p.appliedImpulses.size() * sizeof(float));
    std::memcpy(out.data(), p.deltas.data(), p.deltas.size() * sizeof(btoclBodyDelta));
    std::memcpy(out.data() + p.deltas.size() * sizeof(btoclBodyDelta), p.appliedImpulses.data(),
                p.appliedImpulses.size() * sizeof(float));
    return out;
}

double worstGap(const std::vector<btVector3>& a, const std::vector<btVector3>& b) {
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double((a[i] - b[i]).length()));
    return worst;
}

}  // namespace

TEST_CASE("interleaved friction: one step in SI's order gives SI's velocities, with the flag and only with it",
          "[modes][si]") {
    const bool twoDirections = GENERATE(false, true);
    CAPTURE(twoDirections);
    World w(SolverKind::Reference);
    slidingPile(w);
    btContactSolverInfo info = w.stepInfo();
    if (twoDirections) info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    btContactSolverInfo interleaved = info;
    interleaved.m_solverMode |= SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS;
    const std::vector<btVector3> oursInterleaved = ourVelocities(w, interleaved);
    const std::vector<btVector3> oursApart = ourVelocities(w, info);
    const std::vector<btVector3> si = siVelocities(w, interleaved);
    const double same = worstGap(oursInterleaved, si), apart = worstGap(oursApart, si);
    CAPTURE(same, apart);
    // The same row updates in the same order, in float: SI's SIMD rounding and our reordered sums
    // part them by about 1e-7 m/s; the other order of kinds by about 2 cm/s.
    CHECK(same < 1e-5);
    CHECK(apart > 1e-3);
}

TEST_CASE("the randomized order's shuffles take every position once", "[modes]") {
    int shuffled = 0;
    for (int n = 0; n <= 300; ++n)
        for (unsigned seed = 0; seed < 16; ++seed) {
            const btoclShuffle s = btoclShuffleOf(n, seed);
            std::vector<int> seen(size_t(n), 0);
            bool inOrder = true;
            for (int k = 0; k < n; ++k) {
                const int at = btoclShuffleAt(s, k);
                REQUIRE(at >= 0);
                REQUIRE(at < n);
                ++seen[size_t(at)];
                inOrder = inOrder && at == k;
            }
            for (int k = 0; k < n; ++k) REQUIRE(seen[size_t(k)] == 1);
            shuffled += inOrder ? 0 : 1;
        }
    CHECK(shuffled > 16 * 290);  // nearly every shuffle of two or more positions moves something
}

TEST_CASE("the randomized order: one seed gives one result, another seed another, and only with the flag",
          "[modes][solve]") {
    World w(SolverKind::Reference);
    slidingPile(w);
    btContactSolverInfo info = w.stepInfo();
    info.m_solverMode |= SOLVER_RANDMIZE_ORDER;
    const StepProblem gathered = gatherProblem(w, info, RowSetup::Host);
    const BatchLayout layout = buildSerialLayout(int(gathered.constraints.size()));
    auto solved = [&](const btContactSolverInfo& with, unsigned seed) {
        StepProblem p = gathered;
        solveOnDevice(p, layout, solveSettingsOf(with, false, seed), nullptr, StepMode::WholeStep);
        return solveOutputs(p);
    };
    CHECK(solved(info, 5) == solved(info, 5));
    CHECK(solved(info, 5) != solved(info, 6));
    btContactSolverInfo fixed = info;
    fixed.m_solverMode &= ~SOLVER_RANDMIZE_ORDER;
    CHECK(solved(fixed, 5) == solved(fixed, 6));
    CHECK(solved(fixed, 5) != solved(info, 5));
}

TEST_CASE("solver-mode flags that Bullet's solver reads nowhere change nothing", "[modes]") {
    // SOLVER_FRICTION_SEPARATE, SOLVER_CACHE_FRIENDLY, SOLVER_ALLOW_ZERO_LENGTH_FRICTION_DIRECTIONS,
    // SOLVER_DISABLE_IMPLICIT_CONE_FRICTION and SOLVER_USE_ARTICULATED_WARMSTARTING: no line of
    // btSequentialImpulseConstraintSolver reads them (multibody solvers read the last two).
    auto run = [](int extraFlags) {
        World w(SolverKind::OpenCL);
        testworld::groundAndPile(w, 32);
        w.info().m_solverMode |= extraFlags;
        for (int s = 0; s < 20; ++s) w.step();
        return testworld::solveOutputsOf(w.bodies(), w.manifolds());
    };
    CHECK(run(0) == run(SOLVER_FRICTION_SEPARATE | SOLVER_CACHE_FRIENDLY | SOLVER_ALLOW_ZERO_LENGTH_FRICTION_DIRECTIONS |
                        SOLVER_DISABLE_IMPLICIT_CONE_FRICTION | SOLVER_USE_ARTICULATED_WARMSTARTING));
}
