// Contact rows as btSequentialImpulseConstraintSolver sets them up: our host setup
// (HostRowSetup) and the device's (kernels/setup.cl after the arrange kernel, then the warm-start
// pass) against the rows and warm-started solver bodies of Bullet's own solver, stopped after its
// setup, on contacts gathered from a real world.
#include "GatherAndSolve.h"
#include "HostSolve.h"
#include "ParallelFrom.h"
#include "Scenes.h"
#include "SerialLayout.h"
#include "StepProblem.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>

using namespace btocl;
using namespace btocl::test;
using testworld::SolverKind;
using testworld::World;
using testworld::groundAndPile;

namespace {

// Bullet's solver, stopped after its setup: its rows and solver bodies as it made them.
class SetupOnlySI : public btSequentialImpulseConstraintSolver {
public:
    void setUp(World& w, const btContactSolverInfo& info) {
        btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
        std::vector<btPersistentManifold*> manifolds = w.manifolds();
        solveGroupCacheFriendlySetup(&objects[0], objects.size(), manifolds.data(), int(manifolds.size()), nullptr, 0,
                                     info, nullptr);
    }
    const btConstraintArray& normalRows() const { return m_tmpSolverContactConstraintPool; }
    const btConstraintArray& frictionRows() const { return m_tmpSolverContactFrictionConstraintPool; }
    const btConstraintArray& rollingRows() const { return m_tmpSolverContactRollingFrictionConstraintPool; }
    const btSolverBody& body(int id) const { return m_tmpSolverBodyPool[id]; }
    int numBodies() const { return m_tmpSolverBodyPool.size(); }
};

// SI's row with each side's angular Jacobian and component as the passes hold them where the
// body's angular change is kept scaled (btoclSolveRowOf): both S J.
btSolverConstraint inSolveTerms(const btSolverConstraint& si, const btoclBody& A, const btoclBody& B) {
    btSolverConstraint s = si;
    const auto scaled = [](const btoclBody& b, const btVector3& v) {
        return toVector3(btoclAngularScaled(&b, toFloat4(v)));
    };
    if (BTOCL_BODY_SCALED(A) != 0) s.m_relpos1CrossNormal = s.m_angularComponentA = scaled(A, si.m_relpos1CrossNormal);
    if (BTOCL_BODY_SCALED(B) != 0) s.m_relpos2CrossNormal = s.m_angularComponentB = scaled(B, si.m_relpos2CrossNormal);
    return s;
}

// The largest relative gap between one of SI's rows and ours, over every field the solve reads
// (with solveTerms, ours as the passes hold it: inSolveTerms); `sameBodies` is cleared when they
// act on other bodies or refer to another normal row.
float rowGap(const btSolverConstraint& si, const btoclRow& r, const StepProblem& p, const SetupOnlySI& bullet,
             const BulletStep& from, bool compareNormalIndex, bool solveTerms, bool& sameBodies) {
    if (bullet.body(si.m_solverBodyIdA).m_originalBody != from.original[size_t(r.bodyA)] ||
        bullet.body(si.m_solverBodyIdB).m_originalBody != from.original[size_t(r.bodyB)] ||
        (compareNormalIndex && si.m_frictionIndex != r.frictionIndex))
        sameBodies = false;
    if (!solveTerms) return fieldGap(si, r);
    return fieldGap(inSolveTerms(si, p.bodies[size_t(r.bodyA)], p.bodies[size_t(r.bodyB)]), r);
}

// Holds one problem's rows (gather order), friction directions and warm-started bodies to SI's.
// solveTerms: p.rows as the passes hold them (read back from the device's solve rows).
void requireAsSI(const char* path, const StepProblem& p, const BulletStep& from, const SetupOnlySI& bullet,
                 const std::vector<btVector3>& siDir1, const std::vector<btVector3>& siDir2, bool solveTerms) {
    INFO(path << " setup");
    REQUIRE(p.numRowsOf(BTOCL_ROWS_NORMAL) == bullet.normalRows().size());
    REQUIRE(p.numRowsOf(BTOCL_ROWS_FRICTION) == bullet.frictionRows().size());
    REQUIRE(p.numRowsOf(BTOCL_ROWS_ROLLING) == bullet.rollingRows().size());
    // The same formulas in the same order; Bullet's vector code may associate a dot product
    // differently and the OpenCL compiler may fuse multiply-adds: the last bits only, so 1e-5
    // relative (absolute below 1).
    float worst = 0;
    int worstRow = -1;
    bool sameBodies = true;
    auto check = [&](const btConstraintArray& pool, int base, bool compareNormalIndex) {
        for (int k = 0; k < pool.size(); ++k) {
            const float gap =
                rowGap(pool[k], p.rows[size_t(base + k)], p, bullet, from, compareNormalIndex, solveTerms, sameBodies);
            if (gap > worst) {
                worst = gap;
                worstRow = base + k;
            }
        }
    };
    check(bullet.normalRows(), 0, false);
    check(bullet.frictionRows(), p.numContactPoints(), true);
    check(bullet.rollingRows(), p.rowStart(BTOCL_ROWS_ROLLING), true);
    for (int i = 0; i < p.numContactPoints(); ++i)
        if (btoclFirstFrictionRow(&p.setupParams, i) - p.numContactPoints() != bullet.normalRows()[i].m_frictionIndex)
            sameBodies = false;
    CHECK(sameBodies);
    INFO("worst relative row difference " << worst << " at row " << worstRow << " of " << p.numRows());
    CHECK(worst < 1e-5f);

    float worstDir = 0;
    for (int i = 0; i < p.numContactPoints(); ++i)
        worstDir = std::max({worstDir, vectorGap(siDir1[size_t(i)], p.lateralDirs[2 * size_t(i)]),
                             vectorGap(siDir2[size_t(i)], p.lateralDirs[2 * size_t(i) + 1])});
    INFO("worst relative friction direction difference " << worstDir);
    CHECK(worstDir < 1e-5f);

    // Warm start: the same impulses summed into the bodies, in another order on the device.
    float worstDelta = 0;
    for (int id = 0; id < bullet.numBodies(); ++id) {
        btSolverBody& sb = const_cast<btSolverBody&>(bullet.body(id));
        const auto ours = std::find(from.original.begin(), from.original.end(), sb.m_originalBody);
        if (!sb.m_originalBody || ours == from.original.end()) continue;
        const size_t index = size_t(ours - from.original.begin());
        const btoclBodyDelta& d = p.deltas[index];
        worstDelta = std::max({worstDelta, vectorGap(sb.internalGetDeltaLinearVelocity(), d.deltaLinearVelocity),
                               vectorGap(sb.internalGetDeltaAngularVelocity(),
                                         btoclAngularChange(&p.bodies[index], d.deltaAngularVelocity))});
    }
    INFO("worst relative warm-start velocity difference " << worstDelta);
    CHECK(worstDelta < 1e-5f);
}

}  // namespace

// Gathers the world's contacts for both setups, sets the rows up (and warm-starts) on the host and
// on the device, then lets SI set up the same contacts and compares.
void requireRowsAsSI(World& w, const btContactSolverInfo& info, bool deviceToo = true) {
    GatheredStep gatheredHost = gatherStep(w, info, RowSetup::Host), gatheredDev = gatherStep(w, info, RowSetup::Device);
    StepProblem& host = gatheredHost.problem;
    StepProblem& dev = gatheredDev.problem;
    REQUIRE_FALSE(host.rowsOnDevice);
    REQUIRE(dev.rowsOnDevice == deviceToo);
    SolveSettings settings = solveSettingsOf(info, false);
    settings.numIterations = 0;  // the warm start only
    solveOnHost(host, buildSerialLayout(int(host.constraints.size())), settings);
    solveOnDevice(dev, buildSerialLayout(int(dev.constraints.size())), settings, &dev.rows);

    SetupOnlySI bullet;  // last: it writes friction directions and flags to the points
    bullet.setUp(w, info);
    std::vector<btVector3> dir1, dir2;
    for (btManifoldPoint* cp : gatheredHost.bullet.manifoldPoints) {
        dir1.push_back(cp->m_lateralFrictionDir1);
        dir2.push_back(cp->m_lateralFrictionDir2);
    }
    requireAsSI("host", host, gatheredHost.bullet, bullet, dir1, dir2, false);
    if (deviceToo) requireAsSI("device", dev, gatheredDev.bullet, bullet, dir1, dir2, true);
}

TEST_CASE("contact rows are set up on the host and on the device as SI sets them up", "[setup]") {
    auto mode = GENERATE(0, 1, 2, 3, 4, 5, 6);
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
    if (mode == 6) {
        // Anisotropic friction (sliding and rolling) on some bodies: the step sets its rows up on
        // the host, with the directions scaled in each body's frame.
        for (size_t i = 2; i < w.bodies().size(); i += 4) {
            w.body(i)->setAnisotropicFriction(btVector3(1, 0.3f, 0.6f), btCollisionObject::CF_ANISOTROPIC_FRICTION);
            w.body(i)->setRollingFriction(0.1f);
        }
        w.body(6)->setAnisotropicFriction(btVector3(0.5f, 0, 0), btCollisionObject::CF_ANISOTROPIC_ROLLING_FRICTION);
        info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    }
    requireRowsAsSI(w, info, mode != 6);
}

TEST_CASE("a large world's contacts are set up on the host and on the device as SI sets them up", "[setup]") {
    // Over 4,000 manifolds and 50,000 rows, with rolling friction on some: every row, body index
    // and starting impulse as SI's.
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
    requireRowsAsSI(w, info);
}

TEST_CASE("point records stored past the caches are the records stored plainly", "[setup][parallel]") {
    // A step whose records outgrow the caches stores them past them (kStreamedArrayBytes): the
    // same bytes, read after the pack's loop, on one thread or the pool's.
    World w(SolverKind::Reference);
    groundAndPile(w, 48);
    for (int i = 0; i < 30; ++i) w.step();
    const btContactSolverInfo info = w.stepInfo();
    auto gather = [&](bool streamed) {
        const StepProblem p = gatherProblem(w, info, RowSetup::Device, streamed);
        std::vector<unsigned char> bytes(p.points.size() * sizeof(btoclContactPoint));
        std::memcpy(bytes.data(), p.points.data(), bytes.size());
        return bytes;
    };
    const std::vector<unsigned char> plain = gather(false);
    REQUIRE(plain.size() >= 40 * sizeof(btoclContactPoint));
    CHECK(gather(true) == plain);
    btocl::test::ParallelFrom parallel(1);  // the pack's loop on the pool's threads too
    CHECK(gather(true) == plain);
    CHECK(gather(false) == plain);
}

TEST_CASE("the gather counts a manifold's points unread, read, or again, and places the rows as SI does",
          "[setup]") {
    // Objects' processing threshold left as Bullet sets it: the count takes every point as in
    // reach without reading it (StepGatherer::countsUnread).
    World w(SolverKind::Reference);
    groundAndPile(w, 48);
    for (int i = 0; i < 30; ++i) w.step();
    const btContactSolverInfo info = w.stepInfo();
    std::vector<btPersistentManifold*> withPoints;
    for (btPersistentManifold* m : w.manifolds())
        if (m->getNumContacts() >= 2) withPoints.push_back(m);
    REQUIRE(withPoints.size() >= 4);
    SECTION("every point in reach") { requireRowsAsSI(w, info); }
    SECTION("a point beyond Bullet's largest threshold, which SI leaves out: counted again") {
        REQUIRE(withPoints[0]->getContactProcessingThreshold() >= BT_LARGE_FLOAT);
        withPoints[0]->getContactPoint(1).m_distance1 = 10 * BT_LARGE_FLOAT;
        requireRowsAsSI(w, info);
    }
    SECTION("thresholds of their own, some points beyond them: counted as read") {
        for (size_t k = 0; k < withPoints.size(); k += 2) {
            btPersistentManifold* m = withPoints[k];
            btScalar lo = m->getContactPoint(0).getDistance(), hi = lo;
            for (int j = 1; j < m->getNumContacts(); ++j) {
                lo = std::min(lo, m->getContactPoint(j).getDistance());
                hi = std::max(hi, m->getContactPoint(j).getDistance());
            }
            m->setContactProcessingThreshold((lo + hi) / 2);
        }
        requireRowsAsSI(w, info);
    }
}
