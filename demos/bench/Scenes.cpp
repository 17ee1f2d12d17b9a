#include "Scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

namespace btbench {

namespace {

const btScalar kDensity = 1;  // unit boxes weigh 1
const btVector3 kUnitHalf(0.5f, 0.5f, 0.5f);

btTransform at(btScalar x, btScalar y, btScalar z) {
    return btTransform(btQuaternion::getIdentity(), btVector3(x, y, z));
}

// A static slab whose top face is the plane y = 0, reaching `halfWidth` from the origin.
void addGround(SceneWorld& w, btScalar halfWidth) {
    w.addStaticBox(btVector3(halfWidth, 0.5f, halfWidth), at(0, -0.5f, 0));
}

// Deterministic pseudo-random numbers in [0, 1) (the scenes must not depend on std::rand).
struct Lcg {
    uint32_t state;
    btScalar next() {
        state = state * 1664525u + 1013904223u;
        return btScalar(state >> 8) / btScalar(1u << 24);
    }
};

}  // namespace

void buildPyramid(SceneWorld& w, int baseWidth) {
    const int n = std::max(1, baseWidth);
    addGround(w, btScalar(n) + 10);
    for (int row = 0; row < n; ++row)
        for (int i = 0; i < n - row; ++i)
            w.addBox(kUnitHalf, at(btScalar(i) + 0.5f * btScalar(row) - 0.5f * btScalar(n - 1), 0.5f + btScalar(row), 0),
                     kDensity);
}

void buildTallStack(SceneWorld& w, int height) {
    addGround(w, 10);
    for (int i = 0; i < std::max(1, height); ++i) w.addBox(kUnitHalf, at(0, 0.5f + btScalar(i), 0), kDensity);
}

void buildBrickWall(SceneWorld& w, int courses) {
    const int rows = std::max(1, courses);
    const int perRow = 2 * rows;  // a wall twice as wide as it is tall (in bricks)
    const btVector3 brickHalf(0.5f, 0.25f, 0.25f);
    addGround(w, btScalar(perRow) + 10);
    for (int row = 0; row < rows; ++row) {
        const bool offset = row % 2 == 1;  // running bond: odd rows shifted half a brick, one brick fewer
        const int count = offset ? perRow - 1 : perRow;
        for (int i = 0; i < count; ++i) {
            const btScalar x = btScalar(i) + (offset ? 0.5f : 0.0f) - 0.5f * btScalar(perRow - 1);
            w.addBox(brickHalf, at(x, 0.25f + 0.5f * btScalar(row), 0), kDensity);
        }
    }
}

void buildPile(SceneWorld& w, int count) {
    const int n = std::max(1, count);
    const int side = std::max(1, int(std::lround(std::cbrt(double(n)))));
    const btScalar spacing = 1.8f;  // > sqrt(3), a unit box's diagonal: no two start overlapping
    addGround(w, btScalar(side) * spacing + 20);
    Lcg rng{12345u};
    btScalar layerShiftX = 0, layerShiftZ = 0;
    for (int k = 0; k < n; ++k) {
        const int ix = k % side, iz = (k / side) % side, iy = k / (side * side);
        // Each layer is shifted as a whole by a random fraction of the spacing, so the boxes of
        // one lattice column do not land on each other in a tower. Within a layer the spacing,
        // and between layers the height step, exceed a box's diagonal: nothing starts overlapping.
        if (ix == 0 && iz == 0) {
            layerShiftX = (rng.next() - 0.5f) * spacing;
            layerShiftZ = (rng.next() - 0.5f) * spacing;
        }
        // Random orientations so the boxes tumble into a heap instead of stacking neatly.
        btQuaternion q(btVector3(rng.next() - 0.5f, rng.next() - 0.5f, rng.next() - 0.5f + 1e-3f).normalized(),
                       rng.next() * SIMD_PI);
        const btScalar half = 0.5f * spacing * btScalar(side - 1);
        btTransform t(q, btVector3(btScalar(ix) * spacing - half + layerShiftX, 1.0f + btScalar(iy) * spacing,
                                   btScalar(iz) * spacing - half + layerShiftZ));
        w.addBox(kUnitHalf, t, kDensity);
    }
}

void buildColumnsCollapse(SceneWorld& w, int count) {
    // Columns about 1.3 x cbrt(count) boxes tall on a square grid; 12,000 boxes give 20 x 20
    // columns of 30. Each box sits `lean` further toward the grid's centre than the one below:
    // with 30 levels the column's centre of mass passes its base's edge (15 x 0.04 > 0.5), so
    // every column topples inward and they fall into one pile.
    const int n = std::max(1, count);
    const int height = std::max(3, int(std::lround(1.3 * std::cbrt(double(n)))));
    const int side = std::max(1, int(std::lround(std::sqrt(double(n) / height))));
    const btScalar spacing = 2.0f, lean = 0.04f;
    const btScalar half = 0.5f * spacing * btScalar(side - 1);
    addGround(w, half + btScalar(height) + 20);
    for (int cz = 0; cz < side; ++cz)
        for (int cx = 0; cx < side; ++cx) {
            const btScalar x0 = btScalar(cx) * spacing - half, z0 = btScalar(cz) * spacing - half;
            btVector3 toCentre(-x0, 0, -z0);
            // A column at the centre leans along +x; any direction gives the same collapse.
            toCentre = toCentre.length2() > 1e-6f ? toCentre.normalized() : btVector3(1, 0, 0);
            for (int level = 0; level < height; ++level) {
                const btVector3 p = btVector3(x0, 0.5f + btScalar(level), z0) + toCentre * (lean * btScalar(level));
                w.addBox(kUnitHalf, at(p.x(), p.y(), p.z()), kDensity);
            }
        }
}

void buildBondedBlock(SceneWorld& w, int count) {
    // Layers alternate a x a boxes and (a-1) x (a-1) boxes shifted by half a box in x and z,
    // so each box of an upper layer rests on four below it (about 24 contact points per box).
    const int n = std::max(1, count);
    const int a = std::max(2, int(std::lround(std::cbrt(double(n)))) + 1);
    const double perLayer = 0.5 * double(a * a + (a - 1) * (a - 1));
    const int layers = std::max(1, int(std::lround(double(n) / perLayer)));
    addGround(w, btScalar(a) + 10);
    for (int layer = 0; layer < layers; ++layer) {
        const bool shifted = layer % 2 == 1;
        const int m = shifted ? a - 1 : a;
        const btScalar offset = -0.5f * btScalar(m - 1);
        for (int iz = 0; iz < m; ++iz)
            for (int ix = 0; ix < m; ++ix)
                w.addBox(kUnitHalf, at(btScalar(ix) + offset, 0.5f + btScalar(layer), btScalar(iz) + offset), kDensity);
    }
}

void buildGridBlock(SceneWorld& w, int count) {
    const int n = std::max(1, count);
    const int a = std::max(1, int(std::lround(std::cbrt(double(n)))));
    const int layers = std::max(1, int(std::lround(double(n) / double(a * a))));
    addGround(w, btScalar(a) + 10);
    const btScalar offset = -0.5f * btScalar(a - 1);
    for (int layer = 0; layer < layers; ++layer)
        for (int iz = 0; iz < a; ++iz)
            for (int ix = 0; ix < a; ++ix)
                w.addBox(kUnitHalf, at(btScalar(ix) + offset, 0.5f + btScalar(layer), btScalar(iz) + offset), kDensity);
}

namespace {

// One body of a ragdoll, standing, in the ragdoll's frame (origin about its centre of mass).
struct RagdollPart {
    btVector3 half, centre;
};
enum { kPelvis, kChest, kHead, kUpperLegL, kLowerLegL, kUpperLegR, kLowerLegR, kUpperArmL, kLowerArmL, kUpperArmR,
       kLowerArmR, kNumParts };

// A 1.65 m figure of boxes, arms spread, of about 80 kg (density 1000).
const RagdollPart kRagdollParts[kNumParts] = {
    {{0.16f, 0.10f, 0.10f}, {0, 0.15f, 0}},         {{0.17f, 0.16f, 0.10f}, {0, 0.43f, 0}},
    {{0.09f, 0.10f, 0.09f}, {0, 0.73f, 0}},         {{0.07f, 0.22f, 0.07f}, {-0.09f, -0.17f, 0}},
    {{0.06f, 0.21f, 0.06f}, {-0.09f, -0.61f, 0}},   {{0.07f, 0.22f, 0.07f}, {0.09f, -0.17f, 0}},
    {{0.06f, 0.21f, 0.06f}, {0.09f, -0.61f, 0}},    {{0.15f, 0.05f, 0.05f}, {-0.33f, 0.53f, 0}},
    {{0.13f, 0.045f, 0.045f}, {-0.62f, 0.53f, 0}},  {{0.15f, 0.05f, 0.05f}, {0.33f, 0.53f, 0}},
    {{0.13f, 0.045f, 0.045f}, {0.62f, 0.53f, 0}},
};

// A joint of the ragdoll: its pivot, and the rotation that turns the joint's frame axis (x for a
// cone-twist's twist axis, z for a hinge's axis) to where the joint needs it.
struct RagdollJoint {
    int a, b;
    bool hinge;
    btVector3 pivot;
    btQuaternion frame;
    btScalar limit0, limit1, limit2;  // hinge: low, high; cone-twist: swing 1, swing 2, twist
};

btTransform frameIn(const RagdollPart& part, const RagdollJoint& j) { return btTransform(j.frame, j.pivot - part.centre); }

// As Bullet's ragdoll demo: cone-twist joints at the neck, hips and shoulders, hinges at the
// waist, knees and elbows, all limited.
void addRagdoll(SceneWorld& w, const btTransform& pose) {
    const btScalar density = 1000;
    const btScalar pi = SIMD_PI, half = SIMD_HALF_PI, quarter = SIMD_PI / 4;
    const btQuaternion hingeAboutX(btVector3(0, 1, 0), half), hingeAboutY(btVector3(1, 0, 0), -half);
    const btQuaternion twistUp(btVector3(0, 0, 1), half), twistDown(btVector3(0, 0, 1), -half);
    const btQuaternion twistLeft(btVector3(0, 0, 1), pi), twistRight = btQuaternion::getIdentity();
    const RagdollJoint joints[] = {
        {kPelvis, kChest, true, {0, 0.26f, 0}, hingeAboutX, -quarter, half, 0},
        {kChest, kHead, false, {0, 0.61f, 0}, twistUp, quarter, quarter, half},
        {kPelvis, kUpperLegL, false, {-0.09f, 0.05f, 0}, twistDown, quarter, quarter, 0},
        {kUpperLegL, kLowerLegL, true, {-0.09f, -0.395f, 0}, hingeAboutX, 0, half, 0},
        {kPelvis, kUpperLegR, false, {0.09f, 0.05f, 0}, twistDown, quarter, quarter, 0},
        {kUpperLegR, kLowerLegR, true, {0.09f, -0.395f, 0}, hingeAboutX, 0, half, 0},
        {kChest, kUpperArmL, false, {-0.175f, 0.53f, 0}, twistLeft, half, half, 0},
        {kUpperArmL, kLowerArmL, true, {-0.485f, 0.53f, 0}, hingeAboutY, -half, 0, 0},
        {kChest, kUpperArmR, false, {0.175f, 0.53f, 0}, twistRight, half, half, 0},
        {kUpperArmR, kLowerArmR, true, {0.485f, 0.53f, 0}, hingeAboutY, 0, half, 0},
    };
    btRigidBody* body[kNumParts];
    for (int i = 0; i < kNumParts; ++i) {
        const RagdollPart& p = kRagdollParts[i];
        body[i] = w.addBox(p.half, pose * btTransform(btQuaternion::getIdentity(), p.centre), density);
        body[i]->setDamping(0.05f, 0.85f);  // the demo's: limbs come to rest instead of flailing
    }
    for (const RagdollJoint& j : joints) {
        const btTransform fa = frameIn(kRagdollParts[j.a], j), fb = frameIn(kRagdollParts[j.b], j);
        if (j.hinge) {
            auto hinge = std::make_unique<btHingeConstraint>(*body[j.a], *body[j.b], fa, fb);
            hinge->setLimit(j.limit0, j.limit1);
            w.addJoint(std::move(hinge));
        } else {
            auto cone = std::make_unique<btConeTwistConstraint>(*body[j.a], *body[j.b], fa, fb);
            cone->setLimit(j.limit0, j.limit1, j.limit2);
            w.addJoint(std::move(cone));
        }
    }
}

}  // namespace

void buildRagdolls(SceneWorld& w, int count) {
    // Ragdolls lying face down, each turned at random about the vertical and tipped a little, in
    // layers of side x side about 2 m apart (a ragdoll reaches 0.83 m from its centre, so none
    // starts touching another) and 0.45 m above each other (a lying ragdoll is 0.2 m thick): the
    // column settles and slumps into one heap.
    const int n = std::max(1, count);
    const int side = std::max(1, int(std::lround(std::sqrt(double(n) / 16))));
    const btScalar spacing = 2.0f, layerHeight = 0.45f;
    addGround(w, btScalar(side) * spacing + 20);
    Lcg rng{4242u};
    const btScalar half = 0.5f * spacing * btScalar(side - 1);
    const btQuaternion faceDown(btVector3(1, 0, 0), SIMD_HALF_PI);
    for (int k = 0; k < n; ++k) {
        const int ix = k % side, iz = (k / side) % side, iy = k / (side * side);
        const btQuaternion yaw(btVector3(0, 1, 0), rng.next() * SIMD_2_PI);
        const btQuaternion tip(btVector3(rng.next() - 0.5f, 0, rng.next() - 0.5f + 1e-3f).normalized(), 0.05f * rng.next());
        const btVector3 at(btScalar(ix) * spacing - half + 0.3f * (rng.next() - 0.5f), 0.2f + btScalar(iy) * layerHeight,
                           btScalar(iz) * spacing - half + 0.3f * (rng.next() - 0.5f));
        addRagdoll(w, btTransform(tip * yaw * faceDown, at));
    }
}

void buildMachine(SceneWorld& w, int chains) {
    // Rows of eight units under static beams 12 m up, rows 4 m apart; one unit per metre of beam:
    // a chain of 12 links hanging from the beam (point-to-point joints; its lowest link pushed
    // sideways), and beside it a double pendulum of two rods on hinges, started level. Below
    // every four chains a paddle of 2 t turns on a motor-driven hinge and strikes the chains' ends.
    const int n = std::max(1, chains);
    const int perRow = std::min(n, 8), rows = (n + perRow - 1) / perRow;
    const btScalar density = 1000, top = 12, rowGap = 4;
    const btVector3 linkHalf(0.05f, 0.2f, 0.05f), rodHalf(0.04f, 0.04f, 0.3f);
    const int links = 12;
    const btScalar reach = 1.6f, hub = top - 0.4f * btScalar(links) - reach + 0.5f;
    addGround(w, btScalar(std::max(perRow, rows * 4)) + 10);
    for (int row = 0; row < rows; ++row) {
        const int units = std::min(perRow, n - row * perRow);
        const btScalar z = btScalar(row) * rowGap - 0.5f * rowGap * btScalar(rows - 1);
        const btScalar x0 = -0.5f * btScalar(perRow - 1);
        btRigidBody* beam = w.addStaticBox(btVector3(0.5f * btScalar(perRow) + 1, 0.1f, 0.1f), at(0, top + 0.1f, z));
        for (int i = 0; i < units; ++i) {
            const btScalar x = x0 + btScalar(i);
            // The chain.
            btRigidBody* above = beam;
            btVector3 pivotAbove(x, -0.1f, 0);  // in the beam's frame: its underside
            for (int k = 0; k < links; ++k) {
                const btScalar y = top - 0.2f - 0.4f * btScalar(k);
                const btVector3 kick(0, 0, k == links - 1 ? ((row + i) % 2 ? 3.0f : -3.0f) : 0.0f);
                btRigidBody* link = w.addBox(linkHalf, at(x, y, z), density, kick);
                w.addJoint(std::make_unique<btPoint2PointConstraint>(*above, *link, pivotAbove, btVector3(0, 0.2f, 0)));
                above = link;
                pivotAbove = btVector3(0, -0.2f, 0);
            }
            // The double pendulum, level along z, swinging about x.
            const btScalar xp = x + 0.5f;
            btRigidBody* rod1 = w.addBox(rodHalf, at(xp, top - 0.05f, z + 0.3f), density);
            btRigidBody* rod2 = w.addBox(rodHalf, at(xp, top - 0.05f, z + 0.9f), density);
            w.addJoint(std::make_unique<btHingeConstraint>(*beam, *rod1, btVector3(xp, -0.1f, 0), btVector3(0, 0.05f, -0.3f),
                                                           btVector3(1, 0, 0), btVector3(1, 0, 0)));
            auto elbow = std::make_unique<btHingeConstraint>(*rod1, *rod2, btVector3(0, 0, 0.3f), btVector3(0, 0, -0.3f),
                                                             btVector3(1, 0, 0), btVector3(1, 0, 0));
            elbow->setLimit(-2, 2);
            w.addJoint(std::move(elbow));
        }
        // The paddles: boards across four chains, turning about x at 1.5 rad/s, level at first
        // (clear of the chains); they strike them on their first quarter turn.
        for (int first = 0; first < units; first += 4) {
            const int last = std::min(units, first + 4) - 1;
            const btScalar x = x0 + 0.5f * btScalar(first + last);
            const btTransform level(btQuaternion(btVector3(1, 0, 0), SIMD_HALF_PI), btVector3(x, hub, z));
            btRigidBody* paddle = w.addBox(btVector3(0.5f * btScalar(last - first + 1), reach, 0.08f), level, density);
            auto axle = std::make_unique<btHingeConstraint>(*paddle, btVector3(0, 0, 0), btVector3(1, 0, 0));
            axle->enableAngularMotor(true, 1.5f, 500);
            w.addJoint(std::move(axle));
        }
    }
}

const std::vector<SceneInfo>& allScenes() {
    static const std::vector<SceneInfo> scenes = {
        {"pyramid", "2D pyramid of unit boxes; size = boxes in the bottom row", buildPyramid, 20, 300, 5, true},
        {"stack", "one tall column of unit boxes; size = boxes", buildTallStack, 20, 300, 5, true},
        {"wall", "brick wall in running bond, twice as wide as tall; size = courses", buildBrickWall, 10, 300, 3, true},
        {"pile", "boxes dropped from a lattice with random orientations; size = boxes", buildPile, 1000, 300, 27, false},
        {"columns", "the paper's Figure 1: leaning columns that topple into one pile; size = boxes", buildColumnsCollapse,
         12000, 300, 48, false},
        {"block", "dense block, layers offset by half a box; size = boxes", buildBondedBlock, 12000, 100, 60, true},
        {"block-grid", "dense block of boxes aligned face to face; size = boxes", buildGridBlock, 12000, 100, 64, true},
        {"ragdolls", "ragdolls (11 boxes, 10 limited cone-twist and hinge joints) dropped into a heap; size = ragdolls",
         buildRagdolls, 200, 600, 2, false},
        {"machine", "chains and double pendulums under beams, struck by motor-driven paddles; size = chains",
         buildMachine, 64, 600, 4, false},
    };
    return scenes;
}

const SceneInfo* findScene(const std::string& name) {
    for (auto& s : allScenes())
        if (name == s.name) return &s;
    return nullptr;
}

}  // namespace btbench
