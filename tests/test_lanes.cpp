// A split step solved in SIMD lanes (btOpenCLSolverConfig::simdLanes; kernels/lane_solve.h,
// step/LaneLayout.h): the constraints on each body go through the lanes in their group's order,
// as one work-item walks the group, so a step in lanes must end to the bit where the one-lane
// walk ends; steps the lanes do not take walk one group a work-item; the lane layout keeps its
// invariants, and its validator finds a broken one.
#include "BulletConversions.h"
#include "GatherAndSolve.h"
#include "HostLaneSolve.h"
#include "HostRowSetup.h"
#include "HostSolve.h"
#include "LaneVectors.h"
#include "HostSplit.h"
#include "LaneLayout.h"
#include "ParallelFrom.h"
#include "Scenes.h"
#include "ScopedEnv.h"
#include "TestWorld.h"
#include "WorldSnapshot.h"
#include "btOpenCLConstraintSolver.h"
#include "lane_setup.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

using namespace testworld;
using btocl::test::ScopedEnv;

namespace {

btOpenCLSolverConfig lanesConfig(int simdLanes) {
    btOpenCLSolverConfig c = validatingConfig();  // the lane layout checked every step too
    c.solvePath = btOpenCLSolvePath::Serial;      // the path a CPU runs, whatever the environment says
    c.hostStepMaxRows = 0;                        // every step on the device ...
    c.wholeStepMaxRows = 0;                       // ... and split: the steps the lanes take
    c.simdLanes = simdLanes;
    // Only what a step launches is compiled: a lanes program is no kernel binary of the build's,
    // and warming every kernel of it up would double the test's time with an empty PoCL cache.
    c.warmUpAtConstruction = false;
    return c;
}

// The same scene stepped by a solver in `lanes` lanes and by one group a work-item: what they
// write to Bullet must agree to the bit at every step. Returns the lanes' last stats.
template <class Build>
btOpenCLSolverStats requireSameAsOneLane(int lanes, Build build, int steps = 30) {
    World inLanes(SolverKind::OpenCL, lanesConfig(lanes));
    World oneLane(SolverKind::OpenCL, lanesConfig(1));
    for (World* w : {&inLanes, &oneLane}) build(*w);
    for (int s = 0; s < steps; ++s) {
        inLanes.step();
        oneLane.step();
        INFO("step " << s);
        REQUIRE(inLanes.openCL()->getLastStats().validationFailures == 0);
        REQUIRE(solveOutputsOf(inLanes.bodies(), inLanes.manifolds()) ==
                solveOutputsOf(oneLane.bodies(), oneLane.manifolds()));
    }
    CHECK(oneLane.openCL()->getLastStats().simdLanes == 0);
    return inLanes.openCL()->getLastStats();
}

}  // namespace

TEST_CASE("a step in lanes ends to the bit where one group a work-item ends", "[lanes]") {
    // 4: 128-bit vectors; 8: AVX2's, its rows set up by the host where the CPU has AVX2 (the
    // device in the host's memory); 16: four vectors, and the lane names past 9 (a to f).
    const int lanes = GENERATE(4, 8, 16);
    const bool pyramid = GENERATE(false, true);  // a pyramid's neighbouring manifolds share boxes
    const bool twoFriction = GENERATE(false, true);
    CAPTURE(lanes, pyramid, twoFriction);
    const btOpenCLSolverStats stats = requireSameAsOneLane(lanes, [&](World& w) {
        if (pyramid)
            groundAndPyramid(w, 12);
        else
            groundAndPile(w, 200);
        w.info().m_splitImpulse = 1;  // the push passes too
        if (twoFriction) w.info().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    });
    CHECK(stats.numContactPoints > 100);
    CHECK(stats.simdLanes == lanes);
    CHECK(stats.laneFill > 0.0);
    CHECK(stats.laneFill <= 1.0);
    CHECK(stats.laneRowFill > 0.0);
}

TEST_CASE("lanes chosen automatically take the steps whose layout they fill, to the bit of one lane", "[lanes]") {
    // Where the host sets the lanes' rows up (AVX2, PoCL), the solver takes eight lanes by itself,
    // for a step whose layout fills its rows' places well (a field of columns: manifolds of four
    // points side by side), and walks one group a work-item where it does not (a lone column: a
    // chain of manifolds, each on the box of the one before, one lane a slot). Either way the
    // bits of one lane.
    ScopedEnv env("BT_OPENCL_SIMD_LANES", "auto");
    const bool hostSetsRowsUp = btocl::HostLaneSolve::available() && btocl::test::testDeviceIsCpu();
    const btOpenCLSolverStats field = requireSameAsOneLane(-1, [](World& w) {
        groundAndColumn(w, 3);
        for (int x = 0; x < 12; ++x)
            for (int z = 0; z < 12; ++z)
                if (x + z > 0) addColumn(w, 3, btScalar(3 * x), btScalar(3 * z));
    });
    CHECK(field.numContactPoints > 1000);
    CHECK(field.simdLanes == (hostSetsRowsUp ? 8 : 0));
    if (hostSetsRowsUp) CHECK(field.laneRowFill >= 0.6);
    const btOpenCLSolverStats column = requireSameAsOneLane(-1, [](World& w) { groundAndColumn(w, 10); });
    CHECK(column.numContactPoints >= 30);
    CHECK(column.simdLanes == 0);
}

TEST_CASE("steps whose rows the lanes do not solve walk one group a work-item", "[lanes]") {
    SECTION("SOLVER_RANDMIZE_ORDER") {
        const btOpenCLSolverStats stats = requireSameAsOneLane(4, [](World& w) {
            groundAndPile(w, 200);
            w.info().m_solverMode |= SOLVER_RANDMIZE_ORDER;
        });
        CHECK(stats.numContactPoints > 100);
        CHECK(stats.simdLanes == 0);
    }
    SECTION("interleaved friction") {
        const btOpenCLSolverStats stats = requireSameAsOneLane(4, [](World& w) {
            groundAndPile(w, 200);
            w.info().m_solverMode |= SOLVER_INTERLEAVE_CONTACT_AND_FRICTION_CONSTRAINTS;
        });
        CHECK(stats.simdLanes == 0);
    }
}

TEST_CASE("the lane layout keeps its invariants, and its validator finds a broken one", "[lanes]") {
    using namespace btocl;
    World w(SolverKind::OpenCL);
    groundAndColumn(w, 3);  // a field of 12 x 12 columns of 3 boxes: many groups of like sizes
    for (int x = 0; x < 12; ++x)
        for (int z = 0; z < 12; ++z)
            if (x + z > 0) addColumn(w, 3, btScalar(3 * x), btScalar(3 * z));
    for (int s = 0; s < 30; ++s) w.step();
    btContactSolverInfo info = w.stepInfo();
    const StepProblem p = btocl::test::gatherProblem(w, info, RowSetup::Device);
    REQUIRE(p.numContactPoints() > 100);
    SplitParams params;
    BatchLayout split;
    splitHostInto(p.constraints.data(), p.constraints.size(), p.splitBodies, params, true, split);
    INFO("groups " << split.setGroupStart[BTOCL_NUM_SETS]);
    REQUIRE(split.setGroupStart[BTOCL_NUM_SETS] > 8);
    const int lanes = GENERATE(4, 8);
    const int minBundles = GENERATE(1, 2);
    LaneLayout layout;
    layOutLanes(split, p.constraints.data(), p.regions, lanes, 1, minBundles, layout);
    REQUIRE(validateLaneLayout(layout, split, p.constraints) == "");
    CHECK(layout.usedLanes == long(p.constraints.size()));
    CHECK(layout.usedRowPlaces == p.numRows());
    CHECK(layout.laneFill() > 0.5);  // several groups a lane even the lanes out

    // The bundles are scheduled and written on the host's threads: the layout is the one a single
    // thread makes, into fresh arrays or into arrays that held another layout.
    {
        LaneLayout serial, reused;
        {
            test::ParallelFrom never(size_t(1) << 40);
            layOutLanes(split, p.constraints.data(), p.regions, lanes, 1, minBundles, serial);
        }
        test::ParallelFrom always(1);
        layOutLanes(split, p.constraints.data(), p.regions, lanes == 4 ? 8 : 4, 1, 1, reused);
        layOutLanes(split, p.constraints.data(), p.regions, lanes, 1, minBundles, reused);
        for (const LaneLayout* l : {&layout, &reused}) {
            CHECK(l->bundles.size() == serial.bundles.size());
            for (size_t b = 0; b < std::min(l->bundles.size(), serial.bundles.size()); ++b) {
                CHECK(l->bundles[b].offset == serial.bundles[b].offset);
                CHECK(l->bundles[b].count == serial.bundles[b].count);
            }
            CHECK(l->setBundleStart == serial.setBundleStart);
            CHECK(std::memcmp(l->slots.data(), serial.slots.data(),
                              std::min(l->slots.size(), serial.slots.size()) * sizeof(btoclLaneSlot)) == 0);
            CHECK(l->slots.size() == serial.slots.size());
            CHECK(l->laneInts == serial.laneInts);
            CHECK(l->laneConstraint == serial.laneConstraint);
            CHECK(l->rowMap == serial.rowMap);
            CHECK(l->numBlocks == serial.numBlocks);
            CHECK(l->usedRowPlaces == serial.usedRowPlaces);
        }
        REQUIRE(serial.bundles.size() > 2);  // bundles enough to be shared out
    }

    // Mutations of the layout, and of a slot whose first two lanes hold constraints.
    size_t slot = 0;
    while (slot + 1 < layout.slots.size() &&
           (layout.laneConstraint[slot * size_t(lanes)] < 0 || layout.laneConstraint[slot * size_t(lanes) + 1] < 0 ||
            layout.laneConstraint[(slot + 1) * size_t(lanes)] < 0))
        ++slot;
    REQUIRE(slot + 1 < layout.slots.size());
    // Two constraints of a group on one dynamic body swapped across slots (their ints with them):
    // the group's order on that body is broken.
    std::vector<int> groupOf(p.constraints.size(), -1);
    for (size_t g = 0; g < split.groups.size(); ++g)
        for (int k = 0; k < split.groups[g].count; ++k)
            groupOf[size_t(split.solveOrder[size_t(split.groups[g].offset + k)])] = int(g);
    const auto shareBody = [&](int a, int b) {
        for (int sa = 0; sa < 2; ++sa)
            for (int sb = 0; sb < 2; ++sb)
                if (dynamicBodyOf(p.constraints[size_t(a)], sa) >= 0 &&
                    dynamicBodyOf(p.constraints[size_t(a)], sa) == dynamicBodyOf(p.constraints[size_t(b)], sb))
                    return true;
        return false;
    };
    size_t here = 0, later = 0;
    for (size_t a = 0; a < layout.laneConstraint.size() && later == 0; ++a)
        for (size_t b = a + 1; b < layout.laneConstraint.size() && later == 0; ++b) {
            const int ca = layout.laneConstraint[a], cb = layout.laneConstraint[b];
            if (ca >= 0 && cb >= 0 && b / size_t(lanes) > a / size_t(lanes) &&
                groupOf[size_t(ca)] == groupOf[size_t(cb)] && shareBody(ca, cb)) {
                here = a;
                later = b;
            }
        }
    REQUIRE(later > 0);
    LaneLayout moved = layout;
    std::swap(moved.laneConstraint[here], moved.laneConstraint[later]);
    for (int f = 0; f < BTOCL_LANE_INTS; ++f) {
        const auto place = [&](size_t at) { return at / size_t(lanes) * BTOCL_LANE_INTS * size_t(lanes) + size_t(f * lanes) + at % size_t(lanes); };
        std::swap(moved.laneInts[place(here)], moved.laneInts[place(later)]);
    }
    CHECK(validateLaneLayout(moved, split, p.constraints) == "a body's constraints out of their group's order");
    // A row's place taken by another row.
    LaneLayout shared = layout;
    shared.rowMap[1] = shared.rowMap[0];
    CHECK(validateLaneLayout(shared, split, p.constraints) != "");
    // A lane's bodies not its constraint's.
    LaneLayout wrongBody = layout;
    wrongBody.laneInts[slot * BTOCL_LANE_INTS * size_t(lanes) + BTOCL_LANE_BODY_A * size_t(lanes)] += 1;
    CHECK(validateLaneLayout(wrongBody, split, p.constraints) != "");
    // Rows the lanes do not solve: a layout is refused.
    CHECK_THROWS_AS(layOutLanes(split, p.constraints.data(), p.regions, lanes, 2, minBundles, layout),
                    btOpenCLSolverError);
}

TEST_CASE("a lane layout's slots take constraints of like point counts", "[lanes]") {
    // Sixteen groups of eight constraints on bodies of their own, in one set: eight groups of
    // four-point constraints and eight of one-point ones, interleaved in the split's order. Eight
    // lanes of one bundle can take the one-point constraints in eight slots of one block and the
    // four-point ones in eight of four: every row place filled, in the fewest slots. A slot of
    // mixed counts would leave places empty.
    using namespace btocl;
    constexpr int kGroups = 16, kPerGroup = 8, W = 8;
    std::vector<btoclConstraint> constraints;
    BatchLayout split;
    split.serialRuns = true;
    int normalRows = 0;
    for (int g = 0; g < kGroups; ++g) {
        split.groups.push_back(btoclGroup{g * kPerGroup, kPerGroup, 1, g});
        for (int k = 0; k < kPerGroup; ++k) {
            btoclConstraint c{};
            c.bodyA = 1 + g * (kPerGroup + 1) + k;  // a chain of bodies a group: 0 is fixed
            c.bodyB = c.bodyA + 1;
            c.dynamicA = c.dynamicB = 1;
            c.numRows[BTOCL_ROWS_NORMAL] = g % 2 ? 1 : 4;
            c.numRows[BTOCL_ROWS_FRICTION] = c.numRows[BTOCL_ROWS_NORMAL];
            c.firstRow[BTOCL_ROWS_NORMAL] = normalRows;
            normalRows += c.numRows[BTOCL_ROWS_NORMAL];
            split.solveOrder.push_back(int(constraints.size()));
            constraints.push_back(c);
        }
    }
    for (btoclConstraint& c : constraints) c.firstRow[BTOCL_ROWS_FRICTION] = normalRows + c.firstRow[BTOCL_ROWS_NORMAL];
    for (int s = 1; s < BTOCL_NUM_SETS + 2; ++s) split.setGroupStart[size_t(s)] = kGroups;
    const btoclRowRegions regions = btoclRowRegionsOf(normalRows, normalRows, 0, 0);
    LaneLayout layout;
    layOutLanes(split, constraints.data(), regions, W, 1, 1, layout);
    REQUIRE(validateLaneLayout(layout, split, constraints) == "");
    CHECK(layout.slots.size() == size_t(kGroups * kPerGroup / W));
    CHECK(layout.rowFill() == 1.0);
    CHECK(layout.laneFill() == 1.0);
}

TEST_CASE("a group's constraints on bodies of their own pass each other in the lanes", "[lanes]") {
    // One group: 32 pairs of boxes on top of each other, one-point and four-point manifolds by
    // turns, then a one-point constraint on the first pair's upper box, which must wait for the
    // first. No body joins two pairs, so only that one waits: eight lanes take the 17 one-point
    // constraints in three slots of one block and the 16 four-point ones in two of four, the
    // fewest slots and blocks there are, though the group's order mixes them (taken in that
    // order, one a slot, they would need 33). The first pair's body keeps its order: the last
    // constraint comes in a later slot than the first.
    using namespace btocl;
    constexpr int kPairs = 32, W = 8;
    std::vector<btoclConstraint> constraints;
    BatchLayout split;
    split.serialRuns = true;
    int normalRows = 0;
    const auto add = [&](int bodyA, int bodyB, int points) {
        btoclConstraint c{};
        c.bodyA = bodyA;
        c.bodyB = bodyB;
        c.dynamicA = c.dynamicB = 1;
        c.numRows[BTOCL_ROWS_NORMAL] = points;
        c.numRows[BTOCL_ROWS_FRICTION] = points;
        c.firstRow[BTOCL_ROWS_NORMAL] = normalRows;
        normalRows += points;
        split.solveOrder.push_back(int(constraints.size()));
        constraints.push_back(c);
    };
    for (int k = 0; k < kPairs; ++k) add(1 + 2 * k, 2 + 2 * k, k % 2 ? 4 : 1);
    add(2, 2 * kPairs + 1, 1);
    split.groups.push_back(btoclGroup{0, int(constraints.size()), 1, 0});
    for (btoclConstraint& c : constraints) c.firstRow[BTOCL_ROWS_FRICTION] = normalRows + c.firstRow[BTOCL_ROWS_NORMAL];
    for (int s = 1; s < BTOCL_NUM_SETS + 2; ++s) split.setGroupStart[size_t(s)] = 1;
    const btoclRowRegions regions = btoclRowRegionsOf(normalRows, normalRows, 0, 0);
    LaneLayout layout;
    layOutLanes(split, constraints.data(), regions, W, 1, 1, layout);
    REQUIRE(validateLaneLayout(layout, split, constraints) == "");
    std::vector<int> slotOf(constraints.size(), -1);
    for (size_t at = 0; at < layout.laneConstraint.size(); ++at)
        if (layout.laneConstraint[at] >= 0) slotOf[size_t(layout.laneConstraint[at])] = int(at / W);
    CHECK(slotOf[size_t(kPairs)] > slotOf[0]);
    CHECK(layout.slots.size() == 5);
    long long blocks = 0;
    for (const btoclLaneSlot& slot : layout.slots) blocks += slot.normalBlocks;
    CHECK(blocks == 3 * 1 + 2 * 4);
}

TEST_CASE("the host's lanes set rows up eight points at a time to the one-lane setup's bits", "[lanes][host]") {
    // HostLaneSolve sets a slot's rows up in vectors where every point is a plain contact, and one
    // lane at a time (lane_setup.h, the device's code) where one is not: either way the bits of
    // lane_setup.h's setup of every slot. Boxes tumbling onto the ground and bouncing (restitution
    // above its threshold, points on the fixed body and between boxes, friction along the sliding
    // velocity and across a resting normal), under the options the row setup reads.
    using namespace btocl;
    if (!HostLaneSolve::available()) {
        WARN("no AVX2 on this CPU: the host's lanes are not used");
        return;
    }
    struct Options {
        int solverMode;
        bool splitImpulse;
        int flags;
        bool ownCfm;  // some points with their own cfm, some with cached directions: one lane at a time
    };
    const Options o = GENERATE(Options{SOLVER_USE_WARMSTARTING, false, 0, false},
                               Options{SOLVER_USE_WARMSTARTING | SOLVER_USE_2_FRICTION_DIRECTIONS, true,
                                       BTOCL_FLAG_APPLY_FACTORS, false},
                               Options{SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION, true, 0, false},
                               Options{SOLVER_USE_WARMSTARTING | SOLVER_ENABLE_FRICTION_DIRECTION_CACHING |
                                           SOLVER_USE_2_FRICTION_DIRECTIONS,
                                       false, 0, true});
    CAPTURE(o.solverMode, o.splitImpulse, o.flags, o.ownCfm);
    World w(SolverKind::Reference);
    groundAndTumblingPile(w, 125);
    btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) objects[i]->setRestitution(btScalar(0.5));
    size_t inVectors = 0, oneLane = 0;
    HostLaneSolve lanes;
    for (int s = 0; s < 60; ++s) {
        w.step();
        if (s % 6 != 5) continue;
        btContactSolverInfo info = w.stepInfo();
        info.m_solverMode = o.solverMode;
        info.m_splitImpulse = o.splitImpulse;
        StepProblem p = test::gatherProblem(w, info, RowSetup::Device);
        if (p.constraints.empty()) continue;
        if (o.ownCfm)
            for (size_t i = 0; i < p.points.size(); i += 13) {
                p.points[i].flags |= i % 2 ? BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM : BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
                BTOCL_POINT_CONTACT_CFM(p.points[i]) = 0.01f;
            }
        BatchLayout split;
        splitHostInto(p.constraints.data(), p.constraints.size(), p.splitBodies, SplitParams{}, true, split);
        const std::vector<btoclFloat4> dirsBefore(p.lateralDirs.begin(), p.lateralDirs.end());
        lanes.setUp(p, split, o.flags);
        const LaneLayout& l = lanes.layout();
        const int W = l.lanes;
        const LaneRows& set = lanes.rows();
        std::vector<float> rows(set.rows.size()), applied(set.applied.size()), pushApplied(set.pushApplied.size());
        std::vector<btoclFloat4> dirs = dirsBefore;
        dirs.resize(p.lateralDirs.size());
        for (size_t slot = 0; slot < l.slots.size(); ++slot)
            btoclSetupLaneSlot(p.points.data(), p.bodies.data(), l.slots[slot],
                               l.laneInts.data() + slot * BTOCL_LANE_INTS * size_t(W), rows.data(), applied.data(),
                               pushApplied.data(), dirs.data(), &p.setupParams, W);
        INFO("step " << s << ", " << p.points.size() << " points");
        auto sameBits = [](const auto& a, const auto& b) {
            return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
        };
        CHECK(sameBits(set.rows, rows));
        CHECK(sameBits(set.applied, applied));
        CHECK(sameBits(set.pushApplied, pushApplied));
        CHECK(sameBits(std::vector<btoclFloat4>(p.lateralDirs.begin(), p.lateralDirs.end()), dirs));
        // Streamed past the caches (as a large step's are), the same bits.
        LaneRows streamed;
        setUpLaneRows(p, l, streamed, LaneRowStores::Streamed);
        CHECK(sameBits(streamed.rows, rows));
        CHECK(sameBits(streamed.applied, applied));
        CHECK(sameBits(streamed.pushApplied, pushApplied));
        inVectors += lanes.slotsInVectors();
        oneLane += l.slots.size() - lanes.slotsInVectors();
    }
    CHECK(inVectors > 20);
    if (o.ownCfm) CHECK(oneLane > 0);
}

namespace {

// A split step of a landed pile of 343 tumbling boxes, every tenth step from step 49 to `lastStep`
// (split impulse on; two friction directions where asked): f(gathered, split, settings, step).
template <class F>
int forLandedPileSteps(int lastStep, bool twoFriction, F&& f) {
    using namespace btocl;
    World w(SolverKind::Reference);
    groundAndTumblingPile(w, 343);
    int steps = 0;
    for (int s = 0; s < lastStep; ++s) {
        w.step();
        if (s < 40 || s % 10 != 9) continue;  // once the pile has landed
        btContactSolverInfo info = w.stepInfo();
        if (twoFriction) info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
        info.m_splitImpulse = 1;
        const StepProblem gathered = test::gatherProblem(w, info, RowSetup::Device);
        REQUIRE(gathered.constraints.size() > 150);
        BatchLayout split;
        splitHostInto(gathered.constraints.data(), gathered.constraints.size(), gathered.splitBodies, SplitParams{},
                      true, split);
        f(gathered, split, solveSettingsOf(info, false), s);
        ++steps;
    }
    return steps;
}

}  // namespace

TEST_CASE("the host's lanes give the same bits with AVX-512's registers as with AVX2's", "[lanes][host]") {
    // The solve's AVX-512VL build (lanesUseWideRegisters) runs the AVX2 build's operations with
    // twice the registers: every body and impulse must be the AVX2 build's to the bit.
    using namespace btocl;
    if (!HostLaneSolve::available() || !lanesUseWideRegisters()) {
        WARN("no AVX-512VL on this CPU: the lanes' solve has its AVX2 build alone");
        return;
    }
    const int compared = forLandedPileSteps(60, false, [](const StepProblem& gathered, const BatchLayout& split,
                                                           const SolveSettings& settings, int s) {
        auto solve = [&](bool wideRegisters) {
            lanesUseWideRegisters() = wideRegisters;
            StepProblem p = gathered;
            HostLaneSolve lanes;
            lanes.setUp(p, split, settings.flags, 2);
            lanes.solve(p, passScheduleOf(settings, p), false);
            lanesUseWideRegisters() = true;
            return std::make_pair(std::vector<btoclBodyDelta>(p.deltas.begin(), p.deltas.end()),
                                  std::vector<float>(p.appliedImpulses.begin(), p.appliedImpulses.end()));
        };
        const auto avx2 = solve(false), wide = solve(true);
        INFO("step " << s);
        REQUIRE(avx2.first.size() == wide.first.size());
        REQUIRE(avx2.second.size() == wide.second.size());
        CHECK(std::memcmp(avx2.first.data(), wide.first.data(), avx2.first.size() * sizeof(btoclBodyDelta)) == 0);
        CHECK(std::memcmp(avx2.second.data(), wide.second.data(), avx2.second.size() * sizeof(float)) == 0);
        // The solve moved the bodies: equal deltas of an idle solve would prove nothing.
        bool moved = false;
        for (const btoclBodyDelta& d : avx2.first) moved = moved || toVector3(d.deltaLinearVelocity).length2() > 0;
        CHECK(moved);
    });
    CHECK(compared == 2);
}

TEST_CASE("the host's lanes on the host's threads give one thread's bits, however the shares fall", "[lanes][host]") {
    // HostLaneSolve lays each set out in a bundle a thread (by place) and runs a share of every
    // set on each thread; a share its thread has not taken is run by another. A set's bundles
    // share no dynamic body, so the bodies and impulses must be one thread's to the bit: the
    // shares on the pool, and all of them on the calling thread (as when the worker never comes).
    using namespace btocl;
    if (!HostLaneSolve::available()) {
        WARN("no AVX2 on this CPU: the host's lanes are not used");
        return;
    }
    const bool twoFriction = GENERATE(false, true);
    CAPTURE(twoFriction);
    test::ParallelFrom everyLoop(1);  // the pool takes the scene's loops, and the lanes' shares
    const int compared = forLandedPileSteps(80, twoFriction, [](const StepProblem& gathered, const BatchLayout& split,
                                                                 const SolveSettings& settings, int s) {
        auto solve = [&](int shares, bool onPool, HostLaneSolve& lanes) {
            StepProblem p = gathered;
            lanes.setUp(p, split, settings.flags, shares);
            INFO(shares << " shares");
            REQUIRE(validateLaneLayout(lanes.layout(), split, p.constraints) == "");
            lanes.solve(p, passScheduleOf(settings, p), onPool);
            return std::make_pair(std::vector<btoclBodyDelta>(p.deltas.begin(), p.deltas.end()),
                                  std::vector<float>(p.appliedImpulses.begin(), p.appliedImpulses.end()));
        };
        HostLaneSolve one, pool, calling;
        const auto byOne = solve(1, true, one);
        const int threads = std::min(hostThreads(), HostLaneSolve::kMaxShares);
        const auto onPool = solve(threads, true, pool);
        const auto onCalling = solve(std::max(2, threads), false, calling);
        INFO("step " << s << ", " << gathered.constraints.size() << " constraints");
        CHECK(one.shares() == 1);
        CHECK(pool.shares() == threads);
        CHECK(calling.shares() > 1);
        auto sameBits = [](const auto& a, const auto& b) {
            return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
        };
        CHECK(sameBits(byOne.first, onPool.first));
        CHECK(sameBits(byOne.second, onPool.second));
        CHECK(sameBits(byOne.first, onCalling.first));
        CHECK(sameBits(byOne.second, onCalling.second));
        // More than one bundle a set, where there are threads for them.
        if (hostThreads() > 1)
            CHECK(pool.layout().bundles.size() > one.layout().bundles.size());
    });
    CHECK(compared == 4);
}

TEST_CASE("a host step's rows set up eight points at a time are the one-by-one setup's bits", "[host][setup]") {
    // setupRowsOnHost into a host solve sets eight consecutive points up in vectors where all
    // eight are plain contacts (LaneRowSetup.h), and one by one where one is not; into p.rows it
    // sets every point up one by one. The two must give the same records to the bit, on a
    // bouncing, tumbling pile, under the options the row setup reads.
    using namespace btocl;
    if (!lanesAvailable()) {
        WARN("no AVX2 on this CPU: the host's lanes are not used");
        return;
    }
    const int solverMode = GENERATE(SOLVER_USE_WARMSTARTING,
                                    SOLVER_USE_WARMSTARTING | SOLVER_USE_2_FRICTION_DIRECTIONS,
                                    SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION,
                                    SOLVER_USE_WARMSTARTING | SOLVER_ENABLE_FRICTION_DIRECTION_CACHING);
    const bool splitImpulse = GENERATE(false, true);
    CAPTURE(solverMode, splitImpulse);
    World w(SolverKind::Reference);
    groundAndTumblingPile(w, 125);
    btCollisionObjectArray& objects = w.dyn().getCollisionObjectArray();
    for (int i = 0; i < objects.size(); ++i) objects[i]->setRestitution(btScalar(0.5));
    int stepsCompared = 0;
    for (int s = 0; s < 60; ++s) {
        w.step();
        if (s % 6 != 5) continue;
        btContactSolverInfo info = w.stepInfo();
        info.m_solverMode = solverMode;
        info.m_splitImpulse = splitImpulse;
        test::GatheredStep oneByOne = test::gatherStep(w, info, RowSetup::Device);
        test::GatheredStep inLanes = test::gatherStep(w, info, RowSetup::Device);
        StepProblem& p = oneByOne.problem;
        if (p.points.empty()) continue;
        // Some points with a cfm of their own or cached directions: their runs one by one.
        for (StepProblem* q : {&oneByOne.problem, &inLanes.problem})
            for (size_t i = 0; i < q->points.size(); i += 29) {
                q->points[i].flags |= i % 2 ? BTOCL_CONTACT_FLAG_HAS_CONTACT_CFM : BTOCL_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
                BTOCL_POINT_CONTACT_CFM(q->points[i]) = 0.01f;
            }
        setupRowsOnHost(p, oneByOne.bullet);
        HostSolve solve;
        setupRowsOnHost(inLanes.problem, inLanes.bullet, &solve);
        const HostSolve::RowRecords records = solve.rowRecords();
        INFO("step " << s << ", " << p.points.size() << " points");
        REQUIRE(p.rows.size() == size_t(p.numRows()));
        bool same = true;
        for (int r = 0; r < p.numRows(); ++r) {
            const btoclRow& row = p.rows[size_t(r)];
            const btoclSolveRow expected =
                btoclSolveRowOf(row, r < p.numContactPoints() ? BTOCL_ROWS_NORMAL : BTOCL_ROWS_FRICTION,
                                &p.bodies[size_t(row.bodyA)], &p.bodies[size_t(row.bodyB)]);
            same = same && std::memcmp(&expected, &records.rows[r], sizeof expected) == 0 &&
                   records.normalOfRow[r] == row.frictionIndex &&
                   std::memcmp(&BTOCL_ROW_APPLIED(row), &records.applied[r], sizeof(float)) == 0 &&
                   std::memcmp(&BTOCL_ROW_APPLIED_PUSH(row), &records.pushApplied[r], sizeof(float)) == 0;
        }
        CHECK(same);
        CHECK(std::memcmp(p.lateralDirs.data(), inLanes.problem.lateralDirs.data(),
                          p.lateralDirs.size() * sizeof(btoclFloat4)) == 0);
        ++stepsCompared;
    }
    CHECK(stepsCompared >= 5);
}

TEST_CASE("a lane count other than 1, 4, 8 or 16 is refused with a clear error", "[lanes]") {
    btOpenCLSolverConfig c;
    c.simdLanes = 3;
    CHECK_THROWS_AS(btOpenCLConstraintSolver(c), btOpenCLSolverError);
    ScopedEnv env("BT_OPENCL_SIMD_LANES", "wide");
    CHECK_THROWS_AS(btOpenCLConstraintSolver(), btOpenCLSolverError);
}
