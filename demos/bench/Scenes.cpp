#include "Scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

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
    };
    return scenes;
}

const SceneInfo* findScene(const std::string& name) {
    for (auto& s : allScenes())
        if (name == s.name) return &s;
    return nullptr;
}

}  // namespace btbench
