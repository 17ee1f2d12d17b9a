// The row setup on the device (kernels/setup.cl, after the arrange kernel, with the warm start)
// against the host's setup of SI's rows, on contacts gathered from a real world.
#include "GatherAndSolve.h"
#include "Scenes.h"
#include "HostSolver.h"
#include "SerialLayout.h"
#include "StepProblem.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace btocl;
using namespace btocl::test;
using testworld::SolverKind;
using testworld::World;
using testworld::groundAndPile;

namespace {

float rowFieldGap(const btoclFloat4& a, const btoclFloat4& b) {
    return std::max({relDiff(a.x, b.x), relDiff(a.y, b.y), relDiff(a.z, b.z), relDiff(a.w, b.w)});
}

}  // namespace

// Gathers the world's contacts both ways (device records, host rows), sets the device rows up and
// applies the warm start, and compares rows and starting velocity changes with the host's.
void requireDeviceSetupAsHost(World& w, const btContactSolverInfo& info) {
    StepProblem dev = gatherProblem(w, info, RowSetup::Device);
    StepProblem host = gatherProblem(w, info, RowSetup::Host);
    REQUIRE(dev.rowsOnDevice);
    REQUIRE_FALSE(host.rowsOnDevice);
    REQUIRE(dev.numRows() == host.numRows());
    REQUIRE(dev.constraints.size() == host.constraints.size());

    SolveSettings settings = SolveSettings::from(info);
    settings.numIterations = 0;  // warm start only: compare the starting deltas
    const BatchLayout serial = buildSerialLayout(int(dev.constraints.size()));
    solveOnDevice(dev, serial, settings, &dev.rows);
    solveOnHost(host, serial, settings);

    // The kernel evaluates SI's formulas in the same order; fused multiply-adds and OpenCL's own
    // normalize() change the last bits only: 1e-5 relative (absolute below 1).
    float worst = 0;
    int worstRow = -1, wrongBodies = 0;
    for (int i = 0; i < host.numRows(); ++i) {
        const btoclRow& a = host.rows[size_t(i)];
        const btoclRow& b = dev.rows[size_t(i)];
        if (a.bodyA != b.bodyA || a.bodyB != b.bodyB || a.frictionIndex != b.frictionIndex) ++wrongBodies;
        const float gap = std::max({rowFieldGap(a.contactNormal1, b.contactNormal1),
                                    rowFieldGap(a.relpos1CrossNormal, b.relpos1CrossNormal),
                                    rowFieldGap(a.contactNormal2, b.contactNormal2),
                                    rowFieldGap(a.relpos2CrossNormal, b.relpos2CrossNormal),
                                    rowFieldGap(a.angularComponentA, b.angularComponentA),
                                    rowFieldGap(a.angularComponentB, b.angularComponentB),
                                    rowFieldGap(a.impulses, b.impulses)});
        if (gap > worst) {
            worst = gap;
            worstRow = i;
        }
    }
    CHECK(wrongBodies == 0);
    INFO("worst relative row difference " << worst << " at row " << worstRow << " of " << host.numRows());
    CHECK(worst < 1e-5f);
    // Warm start: the same impulses summed into the bodies in another order.
    float worstDelta = 0;
    for (size_t i = 0; i < host.deltas.size(); ++i)
        worstDelta = std::max({worstDelta, rowFieldGap(host.deltas[i].deltaLinearVelocity, dev.deltas[i].deltaLinearVelocity),
                               rowFieldGap(host.deltas[i].deltaAngularVelocity, dev.deltas[i].deltaAngularVelocity)});
    INFO("worst relative warm-start delta difference " << worstDelta);
    CHECK(worstDelta < 1e-5f);
}

TEST_CASE("device row setup matches the host setup of SI's rows", "[setup]") {
    auto mode = GENERATE(0, 1, 2, 3, 4, 5);
    CAPTURE(mode);
    World w(SolverKind::Reference);
    groundAndPile(w, 48);
    for (size_t i = 1; i < w.bodies().size(); i += 3) {
        w.body(i)->setRollingFriction(0.1f);  // rolling and spinning rows on some points
        w.body(i)->setSpinningFriction(0.05f);
        w.body(i)->setRestitution(0.4f);
    }
    w.body(0)->setRollingFriction(0.2f);
    btContactSolverInfo info = w.stepInfo();
    if (mode == 1) info.m_splitImpulse = 1;
    if (mode == 2) info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    if (mode == 3) info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS | SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION;
    if (mode == 4) {  // relaxation and global CFM
        info.m_sor = 0.9f;
        info.m_globalCfm = 0.001f;
    }
    for (int i = 0; i < 30; ++i) w.step();
    if (mode == 5) {
        // Per-point options: contact CFM/ERP, stiffness and damping, friction anchors, and cached
        // friction directions with a conveyor-belt motion.
        info.m_solverMode |= SOLVER_ENABLE_FRICTION_DIRECTION_CACHING | SOLVER_USE_2_FRICTION_DIRECTIONS;
        int k = 0;
        for (btPersistentManifold* m : w.manifolds()) {
            for (int j = 0; j < m->getNumContacts(); ++j, ++k) {
                btManifoldPoint& cp = m->getContactPoint(j);
                switch (k % 5) {
                    case 0: cp.m_contactPointFlags |= BT_CONTACT_FLAG_HAS_CONTACT_CFM; cp.m_contactCFM = 0.01f; break;
                    case 1: cp.m_contactPointFlags |= BT_CONTACT_FLAG_HAS_CONTACT_ERP; cp.m_contactERP = 0.4f; break;
                    case 2:
                        cp.m_contactPointFlags |= BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING;
                        cp.m_combinedContactStiffness1 = 1e4f;
                        cp.m_combinedContactDamping1 = 50;
                        break;
                    case 3: cp.m_contactPointFlags |= BT_CONTACT_FLAG_FRICTION_ANCHOR; break;
                    default:
                        cp.m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
                        cp.m_lateralFrictionDir1 = btVector3(1, 0, 0);
                        cp.m_lateralFrictionDir2 = btVector3(0, 0, 1);
                        cp.m_contactMotion1 = 0.3f;
                        cp.m_frictionCFM = 0.02f;
                        break;
                }
            }
        }
    }
    requireDeviceSetupAsHost(w, info);
}

TEST_CASE("a large world's contacts set up on the device as on the host", "[setup]") {
    // Over 4,000 manifolds and 50,000 rows, with rolling friction on some: every row, body index
    // and starting impulse as the host setup's.
    World w(SolverKind::Reference);
    w.addGround();
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 20; ++x)
            for (int z = 0; z < 20; ++z) w.addUnitBox(btVector3(btScalar(x) * 1.02f, 0.5f + btScalar(y), btScalar(z) * 1.02f));
    for (size_t i = 1; i < w.bodies().size(); i += 7) w.body(i)->setRollingFriction(0.1f);
    for (int i = 0; i < 3; ++i) w.step();
    REQUIRE(w.manifolds().size() > 4000);
    btContactSolverInfo info = w.stepInfo();
    // Friction along the plane space: a direction taken from a nearly-zero sliding velocity is
    // ill-conditioned (cancellation), in SI too, and would test rounding, not the packing.
    info.m_solverMode |= SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION;
    requireDeviceSetupAsHost(w, info);
}
