// The device solve (kernels/solve.cl) against its serial host reference, on rows gathered from
// a real world, and the whole solver against btSequentialImpulseConstraintSolver.
#include "DeviceSolver.h"
#include "HostSolver.h"
#include "SerialLayout.h"
#include "SolverTestWorld.h"
#include "StepProblem.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace btocl;

namespace {

// Settles a pile with SI so that it has contacts, then gathers one step's problem from it.
StepProblem gatherPileProblem(SolverTestWorld& w, StepProblemBuilder& builder, const btContactSolverInfo& info) {
    for (int i = 0; i < 30; ++i) w.world->stepSimulation(1.f / 60, 0);
    builder.begin(info);
    btCollisionObjectArray& objects = w.world->getCollisionObjectArray();
    builder.addBodies(&objects[0], objects.size());
    btDispatcher* d = w.world->getDispatcher();
    std::vector<btPersistentManifold*> manifolds;
    for (int i = 0; i < d->getNumManifolds(); ++i) manifolds.push_back(d->getManifoldByIndexInternal(i));
    builder.addManifolds(manifolds.data(), int(manifolds.size()));
    StepProblem p = builder.finish();
    builder.releaseBodies();
    return p;
}

float relDiff(float a, float b) { return std::fabs(a - b) / std::max(1.0f, std::max(std::fabs(a), std::fabs(b))); }

}  // namespace

TEST_CASE("device solve matches the serial host reference on a gathered pile", "[solve]") {
    SolverTestWorld w(std::make_unique<btSequentialImpulseConstraintSolver>());
    w.addGround();
    w.addPile(64);
    btContactSolverInfo info = w.world->getSolverInfo();
    info.m_timeStep = 1.f / 60;
    auto mode = GENERATE(0, 1, 2);
    if (mode == 1) info.m_splitImpulse = 1;
    if (mode == 2) info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    StepProblemBuilder builder;
    StepProblem host = gatherPileProblem(w, builder, info);
    REQUIRE(host.numContactPoints() > 100);
    StepProblem dev = host;
    const BatchLayout layout = buildSerialLayout(int(host.constraints.size()));
    const SolveSettings settings = SolveSettings::from(info);

    solveOnHost(host, layout, settings);
    OclRuntime rt("");
    DeviceSolver solver(rt, 64);
    solver.upload(dev);
    solver.iterate(dev, solver.uploadLayout(layout), settings);
    solver.download(dev, settings);

    // Same operations in the same order; the OpenCL compiler may fuse multiply-adds, which
    // changes the last bits of each row update: 1e-4 relative over 10 iterations bounds that.
    float worst = 0;
    for (size_t i = 0; i < host.deltas.size(); ++i) {
        worst = std::max(worst, relDiff(host.deltas[i].deltaLinearVelocity.y, dev.deltas[i].deltaLinearVelocity.y));
        worst = std::max(worst, relDiff(host.deltas[i].deltaAngularVelocity.x, dev.deltas[i].deltaAngularVelocity.x));
        worst = std::max(worst, relDiff(host.deltas[i].pushVelocity.y, dev.deltas[i].pushVelocity.y));
    }
    for (int i = 0; i < host.numNormalRows + host.numFrictionRows; ++i)
        worst = std::max(worst, relDiff(host.rows[size_t(i)].impulses.x, dev.rows[size_t(i)].impulses.x));
    INFO("worst relative difference " << worst);
    CHECK(worst < 1e-4f);
}
