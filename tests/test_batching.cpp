// Global split and local batching: the device against its serial host twin (bitwise), the
// invariants of docs/architecture.md on every layout, batch quality against greedy colouring,
// determinism; layouts of worlds with joints, gathered from Bullet.
#include "BatchingScenes.h"
#include "GatherAndSolve.h"
#include "JointScenes.h"
#include "HostBatching.h"
#include "LayoutValidator.h"
#include "HostSplit.h"
#include "ParallelFrom.h"
#include "DeviceLayout.h"
#include "TestDevice.h"
#include "btOpenCLConstraintSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>

using namespace btocl;
using namespace btocl_test;
using btocl::test::testBackend;

namespace {

// One runtime and batcher for the whole file: program builds take seconds.
struct Fixture {
    OclRuntime rt{""};
    DevicePrimitives primitives{rt, testBackend()};
    DeviceLayout batcher{rt, primitives};
    DeviceBuffer<btoclConstraint> constraints;
};
Fixture& fixture() {
    static Fixture f;
    return f;
}

// The layout reads no pass of a plan.
constexpr btoclPassSchedule kNoPasses{0, 0, 0, 0, 0};

// The wide path's layout: the global split, each group in local batches.
StepPlan splitInBatches(const SplitParams& params) { return StepPlan::perSet(GroupLanes::wide(params.workGroupSize), kNoPasses); }

BatchLayout runDevice(const BatchScene& scene, const SplitParams& params = SplitParams{}) {
    Fixture& f = fixture();
    f.constraints.write(f.rt, scene.constraints);
    f.batcher.build(f.constraints, int(scene.constraints.size()), scene.bodies, params, splitInBatches(params));
    return f.batcher.download();
}

bool sameGroups(const std::vector<btoclGroup>& a, const std::vector<btoclGroup>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(btoclGroup)) == 0);
}

// Equal up to the batch ends past each group's last batch (never written, never read).
void requireSameLayout(const BatchLayout& device, const BatchLayout& host) {
    REQUIRE(device.setGroupStart == host.setGroupStart);
    REQUIRE(sameGroups(device.groups, host.groups));
    REQUIRE(device.solveOrder == host.solveOrder);
    for (const btoclGroup& g : host.groups)
        for (int k = 0; k < g.numBatches; ++k)
            REQUIRE(device.batchEnd[size_t(g.offset + k)] == host.batchEnd[size_t(g.offset + k)]);
    REQUIRE(device.numOverflowConstraints == host.numOverflowConstraints);
    REQUIRE(device.cellSize == host.cellSize);
}

// The split alone must match the greedy reference: same groups with the same constraints.
void requireSameSplit(const BatchLayout& a, const BatchLayout& b) {
    REQUIRE(a.setGroupStart == b.setGroupStart);
    REQUIRE(a.groups.size() == b.groups.size());
    for (size_t g = 0; g < a.groups.size(); ++g) {
        REQUIRE(a.groups[g].offset == b.groups[g].offset);
        REQUIRE(a.groups[g].count == b.groups[g].count);
        REQUIRE(a.groups[g].cell == b.groups[g].cell);
        const auto first = [&](const BatchLayout& l) {
            std::vector<int> v(l.solveOrder.begin() + l.groups[g].offset,
                               l.solveOrder.begin() + l.groups[g].offset + l.groups[g].count);
            std::sort(v.begin(), v.end());
            return v;
        };
        REQUIRE(first(a) == first(b));
    }
}

std::vector<BatchScene> allScenes() {
    std::vector<BatchScene> scenes;
    scenes.push_back(randomPile(1000, 1));
    scenes.push_back(randomPile(3000, 2));
    scenes.push_back(pyramid(40));
    scenes.push_back(wall(30, 20));
    scenes.push_back(denseBlock(12, 12, 12));
    scenes.push_back(chain(3000));
    scenes.push_back(plankWithBoxes());
    scenes.push_back(allInOneCell(3));
    scenes.push_back(hubTouching200(4));
    scenes.push_back(randomPile(1000, 5, Vec3{1.0e6f, -1.0e6f, 1.0e6f}));
    return scenes;
}

}  // namespace

TEST_CASE("the host reference layout keeps every invariant", "[batching]") {
    for (const BatchScene& scene : allScenes()) {
        INFO(scene.name);
        const BatchLayout layout = buildBatchesHost(scene.constraints, scene.bodies, SplitParams{});
        CHECK(validateBatchLayout(layout, scene.constraints) == "");
        // The grid is real: more than one group wherever the contacts spread over cells.
        if (scene.name.find("one cell") == std::string::npos) CHECK(layout.groups.size() > 1);
    }
}

TEST_CASE("the device layout equals its host twin bit for bit and keeps every invariant", "[batching]") {
    const int window = fixture().batcher.windowSize(64);
    for (const BatchScene& scene : allScenes()) {
        INFO(scene.name << ", " << scene.constraints.size() << " constraints");
        const BatchLayout device = runDevice(scene);
        CHECK(validateBatchLayout(device, scene.constraints) == "");
        requireSameLayout(device, buildBatchesHostStreamed(scene.constraints, scene.bodies, SplitParams{}, window));
        requireSameSplit(device, buildBatchesHost(scene.constraints, scene.bodies, SplitParams{}));
    }
}

// The serial path on a CPU device splits mid-sized steps on the host (HostSplit.h) and hands the
// device the layout: it must be the device's own split, one run a group, to the bit.
TEST_CASE("the serial path's split made on the host and uploaded is the device's", "[batching]") {
    Fixture& f = fixture();
    const StepPlan serial = StepPlan::perSet(GroupLanes::serial(), kNoPasses);
    for (const BatchScene& scene : allScenes()) {
        INFO(scene.name << ", " << scene.constraints.size() << " constraints");
        f.constraints.write(f.rt, scene.constraints);
        f.batcher.build(f.constraints, int(scene.constraints.size()), scene.bodies, SplitParams{}, serial);
        const BatchLayout device = f.batcher.download();
        const DeviceLayoutStats deviceStats = f.batcher.stats();
        BatchLayout host;
        splitHostInto(scene.constraints.data(), scene.constraints.size(), scene.bodies, SplitParams{}, true, host);
        f.batcher.upload(host, serial);
        const BatchLayout uploaded = f.batcher.download();
        REQUIRE(uploaded.serialRuns);
        CHECK(validateBatchLayout(uploaded, scene.constraints) == "");
        requireSameLayout(device, uploaded);
        for (const btoclGroup& g : device.groups) REQUIRE(g.numBatches == 1);
        const DeviceLayoutStats& stats = f.batcher.stats();
        CHECK(stats.numCellGroups == deviceStats.numCellGroups);
        CHECK(stats.numOverflowConstraints == deviceStats.numOverflowConstraints);
        CHECK(stats.cellSize == deviceStats.cellSize);
        CHECK(stats.numBatchesMax == deviceStats.numBatchesMax);
    }
    BatchLayout batched = splitHost(allScenes().front().constraints, allScenes().front().bodies, SplitParams{});
    CHECK_THROWS_AS(f.batcher.upload(batched, serial), btOpenCLSolverError);
}

TEST_CASE("other work-group sizes, round counts and a fixed cell give the host twin's layout", "[batching]") {
    const BatchScene scene = randomPile(1500, 7);
    struct Case {
        int wg, rounds;
        float cell;
    };
    for (const Case c : {Case{32, 1, 0.0f}, Case{128, 2, 0.0f}, Case{64, 4, 3.0f}, Case{64, 8, 0.9f}}) {
        INFO("workGroupSize " << c.wg << ", batchIterations " << c.rounds << ", cellSize " << c.cell);
        SplitParams params;
        params.workGroupSize = c.wg;
        params.batchIterations = c.rounds;
        params.cellSize = c.cell;
        const BatchLayout device = runDevice(scene, params);
        CHECK(validateBatchLayout(device, scene.constraints) == "");
        requireSameLayout(device, buildBatchesHostStreamed(scene.constraints, scene.bodies, params,
                                                           fixture().batcher.windowSize(c.wg)));
    }
}

TEST_CASE("a dynamic body bigger than a cell sends its constraints to the overflow group", "[batching]") {
    const BatchScene scene = plankWithBoxes();
    const BatchLayout device = runDevice(scene);
    // The plank's contacts: 2 with the ground, 100 with the boxes.
    CHECK(device.numOverflowConstraints == 102);
    REQUIRE(device.setGroupStart[BTOCL_OVERFLOW_SET + 1] - device.setGroupStart[BTOCL_OVERFLOW_SET] == 1);
    const btoclGroup& overflow = device.groups.back();
    CHECK(overflow.cell == -1);
    CHECK(overflow.count == 102);
    CHECK(overflow.numBatches == 102);  // all share the plank: one per batch, as greedy colouring
    CHECK(fixture().batcher.stats().numOverflowConstraints == 102);
    // A cell edge fixed below the boxes' span sends everything to the overflow group, still valid.
    SplitParams tiny;
    tiny.cellSize = 0.1f;
    const BatchLayout all = runDevice(scene, tiny);
    CHECK(all.numOverflowConstraints == int(scene.constraints.size()));
    CHECK(all.groups.size() == 1);
    CHECK(validateBatchLayout(all, scene.constraints) == "");
}

TEST_CASE("far from the origin the grid still has many cells", "[batching]") {
    const BatchScene near = randomPile(1000, 5);
    const BatchScene far = randomPile(1000, 5, Vec3{1.0e6f, -1.0e6f, 1.0e6f});
    const BatchLayout a = runDevice(near);
    const BatchLayout b = runDevice(far);
    CHECK(validateBatchLayout(b, far.constraints) == "");
    // float spacing at 1e6 is 1/16, so cells may shift a little; the grid must not collapse.
    INFO("groups near the origin " << a.groups.size() << ", at 1e6 m " << b.groups.size());
    CHECK(double(b.groups.size()) > 0.8 * double(a.groups.size()));
}

TEST_CASE("no constraint and one constraint", "[batching]") {
    BatchScene empty = chain(1);
    REQUIRE(empty.constraints.empty());
    const BatchLayout none = runDevice(empty);
    CHECK(none.groups.empty());
    CHECK(none.solveOrder.empty());
    CHECK(validateBatchLayout(none, empty.constraints) == "");
    CHECK(fixture().batcher.stats().numBatchesMax == 0);

    const BatchScene one = chain(2);
    REQUIRE(one.constraints.size() == 1);
    const BatchLayout single = runDevice(one);
    REQUIRE(single.groups.size() == 1);
    CHECK(single.groups[0].count == 1);
    CHECK(single.groups[0].numBatches == 1);
    CHECK(single.solveOrder == std::vector<int>{0});
    CHECK(single.batchEnd[0] == 1);
    CHECK(validateBatchLayout(single, one.constraints) == "");
}

TEST_CASE("two builds of a 1000-body pile give bitwise equal layouts", "[batching]") {
    const BatchScene scene = randomPile(1000, 11);
    const BatchLayout a = runDevice(scene);
    const BatchLayout b = runDevice(randomPile(2000, 12));  // something else in between
    (void)b;
    const BatchLayout c = runDevice(scene);
    // A second batcher: fresh buffers and kernels.
    DeviceLayout other(fixture().rt, fixture().primitives);
    DeviceBuffer<btoclConstraint> buffer;
    buffer.write(fixture().rt, scene.constraints);
    other.build(buffer, int(scene.constraints.size()), scene.bodies, SplitParams{}, splitInBatches(SplitParams{}));
    const BatchLayout d = other.download();
    for (const BatchLayout* x : {&c, &d}) {
        CHECK(x->solveOrder == a.solveOrder);
        for (const btoclGroup& g : a.groups)  // the entries past a group's last batch are unused
            for (int k = 0; k < g.numBatches; ++k)
                CHECK(x->batchEnd[size_t(g.offset + k)] == a.batchEnd[size_t(g.offset + k)]);
        CHECK(sameGroups(x->groups, a.groups));
        CHECK(x->setGroupStart == a.setGroupStart);
    }
}

TEST_CASE("batches per group stay within 1.5x of greedy colouring", "[batching]") {
    for (const BatchScene& scene : {pyramid(40), wall(30, 20), randomPile(3000, 21), denseBlock(12, 12, 12)}) {
        const BatchLayout device = runDevice(scene);
        double worst = 0, sumDevice = 0, sumGreedy = 0;
        for (const btoclGroup& g : device.groups) {
            const int greedy = greedyBatchCount(scene.constraints, device.solveOrder.data() + g.offset, g.count);
            const double ratio = double(g.numBatches) / double(greedy);
            worst = std::max(worst, ratio);
            sumDevice += g.numBatches;
            sumGreedy += greedy;
            INFO(scene.name << ": group at " << g.offset << " of " << g.count << " constraints");
            CHECK(ratio <= 1.5);
        }
        std::printf("[batching] %-28s %6zu constraints %5zu groups: batches device/greedy total %.3f, worst group %.3f\n",
                    scene.name.c_str(), scene.constraints.size(), device.groups.size(), sumDevice / sumGreedy, worst);
    }
}

TEST_CASE("the validator names broken layouts", "[batching]") {
    const BatchScene scene = pyramid(10);
    const BatchLayout good = buildBatchesHost(scene.constraints, scene.bodies, SplitParams{});
    REQUIRE(validateBatchLayout(good, scene.constraints) == "");

    BatchLayout dup = good;
    dup.solveOrder[1] = dup.solveOrder[0];
    CHECK(validateBatchLayout(dup, scene.constraints).find("twice in solveOrder") != std::string::npos);

    // One batch holding everything: boxes resting on each other share bodies.
    BatchLayout merged = good;
    for (btoclGroup& g : merged.groups) {
        g.numBatches = 1;
        merged.batchEnd[size_t(g.offset)] = g.offset + g.count;
    }
    CHECK(validateBatchLayout(merged, scene.constraints).find("twice in batch") != std::string::npos);

    // All groups in set 0: neighbouring cells share boxes.
    BatchLayout oneSet = good;
    for (int s = 1; s <= BTOCL_NUM_SETS; ++s) oneSet.setGroupStart[size_t(s)] = int(oneSet.groups.size());
    CHECK(validateBatchLayout(oneSet, scene.constraints).find("of set 0") != std::string::npos);

    BatchLayout shortGroup = good;
    shortGroup.groups[0].count -= 1;
    CHECK(validateBatchLayout(shortGroup, scene.constraints) != "");
}

TEST_CASE("bad input is refused with a clear error", "[batching]") {
    BatchScene scene = pyramid(5);
    SplitParams params;
    params.batchIterations = 0;
    CHECK_THROWS_AS(runDevice(scene, params), btOpenCLSolverError);
    params = SplitParams{};
    params.workGroupSize = 1 << 20;
    CHECK_THROWS_AS(runDevice(scene, params), btOpenCLSolverError);
    params = SplitParams{};
    params.cellSize = -1;
    CHECK_THROWS_AS(runDevice(scene, params), btOpenCLSolverError);
    scene.constraints[3].bodyB = int(scene.bodies.size()) + 5;
    CHECK_THROWS_WITH(buildBatchesHost(scene.constraints, scene.bodies, SplitParams{}),
                      Catch::Contains("names body"));
}

TEST_CASE("the host's split names the first constraint with a bad body, serial or on the pool", "[batching]") {
    BatchScene scene = pyramid(20);
    const size_t n = scene.constraints.size();
    REQUIRE(n > 200);
    BatchLayout layout;
    splitHostInto(scene.constraints.data(), n, scene.bodies, SplitParams{}, true, layout);
    const BatchLayout before = layout;
    // Two bad constraints in different chunks of the check: the lower is named either way.
    scene.constraints[n / 3].bodyA = -1;
    scene.constraints[n - 2].bodyB = int(scene.bodies.size());
    const std::string first = "constraint " + std::to_string(n / 3) + " names body -1";
    for (const size_t from : {kMinParallelItems * 1000, size_t(1)}) {
        test::ParallelFrom parallel(from);
        CHECK_THROWS_WITH(splitHostInto(scene.constraints.data(), n, scene.bodies, SplitParams{}, true, layout),
                          Catch::Contains(first));
        CHECK(layout.solveOrder == before.solveOrder);
        CHECK(layout.groups.size() == before.groups.size());
    }
}

TEST_CASE("the grid caps the cells per axis by enlarging the cell", "[batching]") {
    const BatchScene longChain = chain(3000);  // contacts from x = 0.5 to 2998.5
    const BatchLayout layout = runDevice(longChain);
    CHECK(validateBatchLayout(layout, longChain.constraints) == "");
    // Unit boxes ask for a cell of 1.1 + 0.05; 2998 m over at most 254 cells needs more.
    CHECK(layout.cellSize >= 2998.0f / BTOCL_SPLIT_MAX_CELLS);
    CHECK(layout.cellSize < 2998.0f / (BTOCL_SPLIT_MAX_CELLS - 2));
    for (const btoclGroup& g : layout.groups) {
        CHECK(g.cell >= 0);
        CHECK(g.cell < BTOCL_SPLIT_MAX_CELLS * BTOCL_SPLIT_MAX_CELLS);
    }
    // A short chain keeps the cell the boxes ask for.
    const BatchLayout shortChain = runDevice(chain(50));
    CHECK(shortChain.cellSize == Approx(1.0f * 1.1f + 0.05f));
}

TEST_CASE("non-finite contact points neither crash nor part device from host", "[batching]") {
    // The solver rejects such contacts before the split (bullet/InputChecks.h); the split must
    // still stay in bounds: NaN coordinates are left out of the box and go to cell 0; an axis of infinite width
    // counts as flat, so the grid takes the other two.
    BatchScene scene = randomPile(300, 31);
    REQUIRE(scene.constraints.size() > 20);
    scene.constraints[5].position.x = std::nanf("");
    scene.constraints[9].position.y = std::nanf("");
    const int window = fixture().batcher.windowSize(64);
    requireSameLayout(runDevice(scene), buildBatchesHostStreamed(scene.constraints, scene.bodies, SplitParams{}, window));
    scene.constraints[12].position.z = INFINITY;
    const BatchLayout device = runDevice(scene);
    requireSameLayout(device, buildBatchesHostStreamed(scene.constraints, scene.bodies, SplitParams{}, window));
    CHECK(device.groups.size() > 1);
    CHECK(validateBatchLayout(device, scene.constraints) == "");
}

namespace {

// A Bullet world's step as the solver gathers it (bodies, manifolds, then joints) after `steps`
// steps of SI, as a scene for the batcher: its constraints (a joint's after the contacts') and
// split bodies (each body's extent grown by the reach of its joints).
BatchScene gatheredScene(const std::string& name, testworld::World& w, int steps) {
    for (int i = 0; i < steps; ++i) w.step();
    StepProblem p = btocl::test::gatherProblem(w, w.stepInfo(), RowSetup::Device);
    BatchScene scene;
    scene.name = name;
    scene.constraints = p.constraints;
    scene.bodies = p.splitBodies;
    return scene;
}

int numJointConstraints(const std::vector<btoclConstraint>& constraints) {
    return int(std::count_if(constraints.begin(), constraints.end(),
                             [](const btoclConstraint& c) { return c.numRows[BTOCL_ROWS_JOINT] > 0; }));
}

// Invariant 3 of docs/architecture.md directly: outside the overflow group, the constraints of
// each dynamic body lie within one cell edge of each other on every axis (so no two cells of one
// set share it).
// Returns "" or the first body that reaches further.
std::string reachWithinCells(const BatchLayout& layout, const std::vector<btoclConstraint>& constraints) {
    std::unordered_map<int, std::pair<Vec3, Vec3>> box;  // per dynamic body: its constraints' box
    for (int gi = 0; gi < layout.setGroupStart[BTOCL_OVERFLOW_SET]; ++gi) {
        const btoclGroup& g = layout.groups[size_t(gi)];
        for (int i = g.offset; i < g.offset + g.count; ++i) {
            const btoclConstraint& c = constraints[size_t(layout.solveOrder[size_t(i)])];
            const Vec3 p{c.position.x, c.position.y, c.position.z};
            for (int side = 0; side < 2; ++side) {
                const int body = dynamicBodyOf(c, side);
                if (body < 0) continue;
                auto it = box.emplace(body, std::make_pair(p, p)).first;
                Vec3& lo = it->second.first;
                Vec3& hi = it->second.second;
                lo = Vec3{std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
                hi = Vec3{std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
            }
        }
    }
    for (const auto& [body, b] : box) {
        const float reach = std::max({b.second.x - b.first.x, b.second.y - b.first.y, b.second.z - b.first.z});
        if (reach > layout.cellSize)
            return "body " + std::to_string(body) + " reaches " + std::to_string(reach) + " m across its constraints, " +
                   "past the cell of " + std::to_string(layout.cellSize) + " m";
    }
    return "";
}

}  // namespace

TEST_CASE("layouts of worlds with joints keep every invariant", "[batching][joints]") {
    using namespace testworld;
    // Sixteen ragdolls lying on the ground 2.5 m apart, and eight chains of 12 links hanging among
    // them from a fixed point (point-to-point joints): joints beside contacts over many cells.
    World ragdolls(SolverKind::Reference);
    ragdolls.addGround();
    const btQuaternion faceDown(btVector3(1, 0, 0), SIMD_HALF_PI);
    for (int k = 0; k < 16; ++k)
        addRagdoll(ragdolls, btTransform(faceDown, btVector3(btScalar(k % 4) * 2.5f, 0.15f, btScalar(k / 4) * 2.5f)));
    for (int k = 0; k < 8; ++k) addChain(ragdolls, btVector3(btScalar(k % 4) * 2.5f + 1.25f, 7, btScalar(k / 4) * 5 + 1.25f), 12, 1);
    // Every joint type, in the air (JointScenes.h), and the random scene of all of them.
    World zoo(SolverKind::Reference);
    addJointZoo(zoo);
    World random(SolverKind::Reference);
    addRandomJointScene(random, 5, 22);

    const std::vector<BatchScene> scenes = {gatheredScene("ragdolls and chains", ragdolls, 30),
                                            gatheredScene("joint zoo", zoo, 5),
                                            gatheredScene("random joints", random, 5)};
    const int window = fixture().batcher.windowSize(64);
    for (const BatchScene& scene : scenes) {
        INFO(scene.name << ", " << scene.constraints.size() << " constraints, " << numJointConstraints(scene.constraints)
                        << " of them joints");
        REQUIRE(numJointConstraints(scene.constraints) > 0);
        // The wide path's layout (local batches): no dynamic body twice in a batch, none in two
        // groups of one set; and the device's is its host twin's.
        const BatchLayout device = runDevice(scene);
        CHECK(device.groups.size() > 1);
        CHECK(validateBatchLayout(device, scene.constraints) == "");
        CHECK(reachWithinCells(device, scene.constraints) == "");
        requireSameLayout(device, buildBatchesHostStreamed(scene.constraints, scene.bodies, SplitParams{}, window));
        std::printf("[batching] %-28s %6zu constraints (%d joints) %5zu groups, %d in the overflow group, cell %.2f m\n",
                    scene.name.c_str(), scene.constraints.size(), numJointConstraints(scene.constraints),
                    device.groups.size(), device.numOverflowConstraints, double(device.cellSize));
        // The serial path's (one run per group) and the one-group layout of a small step.
        for (const StepPlan& plan : {StepPlan::perSet(GroupLanes::serial(), kNoPasses),
                                     StepPlan::wholeStep(GroupLanes::wide(64), kNoPasses)}) {
            Fixture& f = fixture();
            f.constraints.write(f.rt, scene.constraints);
            f.batcher.build(f.constraints, int(scene.constraints.size()), scene.bodies, SplitParams{}, plan);
            CHECK(validateBatchLayout(f.batcher.download(), scene.constraints) == "");
        }
    }
}

namespace {

// A rod: two boxes of 0.2 m lying on the ground 20 m apart along x, joined by a point-to-point
// joint at the middle (each pivot 10 m from its box): each box's constraints (its contacts with
// the ground, the joint) reach 10 m. Beside it, `boxes` unit boxes on the ground in rows 2 m
// apart around the rod.
void groundRodAndBoxes(testworld::World& w, int boxes) {
    w.addGround();
    const btVector3 half(btScalar(0.1), btScalar(0.1), btScalar(0.1));
    btRigidBody* a = w.addBox(half, 1, testworld::at(btVector3(-10, btScalar(0.1), 0)));
    btRigidBody* b = w.addBox(half, 1, testworld::at(btVector3(10, btScalar(0.1), 0)));
    w.addConstraint(std::make_unique<btPoint2PointConstraint>(*a, *b, btVector3(10, 0, 0), btVector3(-10, 0, 0)));
    for (int k = 0; k < boxes; ++k)
        w.addUnitBox(btVector3(btScalar(k % 10) * 2 - 9, btScalar(0.5), btScalar(k / 10 + 1) * 2));
}

}  // namespace

TEST_CASE("a joint whose bodies are far apart goes to the overflow group or a cell big enough", "[batching][joints]") {
    using namespace testworld;
    const int window = fixture().batcher.windowSize(64);
    auto check = [&](const BatchScene& scene, const BatchLayout& layout) {
        CHECK(validateBatchLayout(layout, scene.constraints) == "");
        CHECK(reachWithinCells(layout, scene.constraints) == "");
        requireSameLayout(layout, buildBatchesHostStreamed(scene.constraints, scene.bodies, SplitParams{}, window));
    };
    // Among 40 unit boxes the rod's boxes reach 10 m, past 4x the median body (1 m): their
    // constraints, the joint's and their contacts, go to the overflow group.
    {
        World w(SolverKind::Reference);
        groundRodAndBoxes(w, 40);
        const BatchScene scene = gatheredScene("rod among boxes", w, 3);
        REQUIRE(numJointConstraints(scene.constraints) == 1);
        const int joint = int(scene.constraints.size()) - 1;  // the joints' come last
        REQUIRE(scene.constraints[size_t(joint)].numRows[BTOCL_ROWS_JOINT] == 3);
        CHECK(scene.bodies[1].extent >= 10);  // the rod's boxes: their reach, not their 0.2 m
        CHECK(scene.bodies[2].extent >= 10);
        const BatchLayout layout = runDevice(scene);
        check(scene, layout);
        REQUIRE(layout.setGroupStart[BTOCL_OVERFLOW_SET + 1] - layout.setGroupStart[BTOCL_OVERFLOW_SET] == 1);
        const btoclGroup& overflow = layout.groups.back();
        const std::vector<int> inOverflow(layout.solveOrder.begin() + overflow.offset,
                                          layout.solveOrder.begin() + overflow.offset + overflow.count);
        CHECK(std::count(inOverflow.begin(), inOverflow.end(), joint) == 1);
        // Its boxes' contacts with the ground (4 points a box, one manifold each) go with it.
        CHECK(overflow.count == 3);
        CHECK(layout.numOverflowConstraints == 3);
        CHECK(layout.cellSize < 2);  // the unit boxes keep their small cells
        CHECK(layout.groups.size() > 4);
        // Both checks have teeth: had the split planned for the boxes' own 0.2 m, the joint would
        // sit in a cell 10 m from their contacts', in a group of the same set.
        BatchScene blind = scene;
        blind.bodies[1].extent = blind.bodies[2].extent = 0.2f;
        const BatchLayout wrong = runDevice(blind);
        CHECK(wrong.numOverflowConstraints == 0);
        CHECK(reachWithinCells(wrong, blind.constraints) != "");
        CHECK(validateBatchLayout(wrong, blind.constraints).find("is in groups") != std::string::npos);
    }
    // With nothing beside it the rod sets the cell: one edge of 11 m holds each box's reach.
    {
        World w(SolverKind::Reference);
        groundRodAndBoxes(w, 0);
        const BatchScene scene = gatheredScene("rod alone", w, 3);
        REQUIRE(numJointConstraints(scene.constraints) == 1);
        const BatchLayout layout = runDevice(scene);
        check(scene, layout);
        CHECK(layout.numOverflowConstraints == 0);
        CHECK(layout.cellSize >= 10);
    }
}
