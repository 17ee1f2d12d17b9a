#include "scenes/Stacks.h"

#include "scenes/SceneRandom.h"

#include <algorithm>
#include <cmath>

namespace btscenes {

namespace {

void addGround(World& w, const Ground& g) { w.addGround(g.surface, btQuaternion::getIdentity(), g.halfWidth); }

// The ground of the benchmark's scenes, reaching halfWidth from the origin.
void addGround(World& w, const BodyOptions& surface, btScalar halfWidth) { addGround(w, Ground{surface, halfWidth}); }

}  // namespace

void addColumn(World& w, int boxes, btScalar x, btScalar z, const BodyOptions& o, const btVector3& leanDirection,
               btScalar leanPerBox) {
    for (int i = 0; i < boxes; ++i) {
        btVector3 p(x, btScalar(0.5) + btScalar(i), z);
        if (leanPerBox != 0) p += leanDirection * (leanPerBox * btScalar(i));
        w.addUnitBox(p, o);
    }
}

void groundAndColumn(World& w, int boxes, const BodyOptions& box, const Ground& ground) {
    addGround(w, ground);
    addColumn(w, boxes, 0, 0, box);
}

void groundAndPile(World& w, int boxes, const BodyOptions& box, const Ground& ground) {
    addGround(w, ground);
    for (int i = 0; i < boxes; ++i) {
        const int layer = i / 16, k = i % 16;
        w.addUnitBox(btVector3(btScalar(k % 4) * 1.1f + 0.05f * btScalar(layer % 3), 0.5f + btScalar(layer) * 1.05f,
                               btScalar(k / 4) * 1.1f - 0.04f * btScalar(layer % 2)),
                     box);
    }
}

void groundAndPyramid(World& w, int base, const BodyOptions& box, const Ground& ground) {
    addGround(w, ground);
    for (int row = 0; row < base; ++row)
        for (int i = 0; i < base - row; ++i)
            w.addUnitBox(btVector3(btScalar(i + 0.5 * row - 0.5 * (base - 1)), btScalar(0.5) + row, 0), box);
}

void groundAndBrickWall(World& w, int rows, const BrickWall& wall, const Ground& ground) {
    addGround(w, ground);
    const btVector3 half(btScalar(0.5), btScalar(0.25), btScalar(0.25));
    const btScalar left = btScalar(0.5) * btScalar(wall.perRow - 1);  // a full row's first brick is at x = -left
    for (int row = 0; row < rows; ++row) {
        const bool shifted = row % 2 == 1;
        const int n = shifted ? wall.perRow - 1 : wall.perRow;
        const btScalar shift = shifted ? btScalar(0.5) : btScalar(0);
        const btScalar y = btScalar(0.25) + btScalar(0.5) * row;
        for (int i = 0; i < n; ++i) w.addBox(half, wall.brickMass, at(btVector3(btScalar(i) + shift - left, y, 0)), wall.brick);
    }
}

void groundAndTumblingPile(World& w, int boxes) {
    const BodyOptions surface = roughSurface();
    const int n = std::max(1, boxes);
    const int side = std::max(1, int(std::lround(std::cbrt(double(n)))));
    const btScalar spacing = 1.8f;  // > sqrt(3), a unit box's diagonal: no two start overlapping
    addGround(w, surface, btScalar(side) * spacing + 20);
    SceneRandom rng = SceneRandom::fromState(12345u);
    btScalar layerShiftX = 0, layerShiftZ = 0;
    for (int k = 0; k < n; ++k) {
        const int ix = k % side, iz = (k / side) % side, iy = k / (side * side);
        // Each layer is shifted as a whole by a random fraction of the spacing, so the boxes of
        // one lattice column do not land on each other in a tower. Within a layer the spacing,
        // and between layers the height step, exceed a box's diagonal: nothing starts overlapping.
        if (ix == 0 && iz == 0) {
            layerShiftX = (rng.uniform() - 0.5f) * spacing;
            layerShiftZ = (rng.uniform() - 0.5f) * spacing;
        }
        // Random orientations so the boxes tumble into a heap instead of stacking neatly.
        btQuaternion q(btVector3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f + 1e-3f).normalized(),
                       rng.uniform() * SIMD_PI);
        const btScalar half = 0.5f * spacing * btScalar(side - 1);
        const btVector3 p(btScalar(ix) * spacing - half + layerShiftX, 1.0f + btScalar(iy) * spacing,
                          btScalar(iz) * spacing - half + layerShiftZ);
        w.addBox(btVector3(0.5f, 0.5f, 0.5f), 1, at(p, q), surface);
    }
}

void groundAndLeaningColumns(World& w, int boxes) {
    const BodyOptions surface = roughSurface();
    // With 30 levels a column's centre of mass passes its base's edge (15 x 0.04 > 0.5).
    const int n = std::max(1, boxes);
    const int height = std::max(3, int(std::lround(1.3 * std::cbrt(double(n)))));
    const int side = std::max(1, int(std::lround(std::sqrt(double(n) / height))));
    const btScalar spacing = 2.0f, lean = 0.04f;
    const btScalar half = 0.5f * spacing * btScalar(side - 1);
    addGround(w, surface, half + btScalar(height) + 20);
    for (int cz = 0; cz < side; ++cz)
        for (int cx = 0; cx < side; ++cx) {
            const btScalar x0 = btScalar(cx) * spacing - half, z0 = btScalar(cz) * spacing - half;
            btVector3 toCentre(-x0, 0, -z0);
            // A column at the centre leans along +x; any direction gives the same collapse.
            toCentre = toCentre.length2() > 1e-6f ? toCentre.normalized() : btVector3(1, 0, 0);
            addColumn(w, height, x0, z0, surface, toCentre, lean);
        }
}

void groundAndBondedBlock(World& w, int boxes) {
    const BodyOptions surface = roughSurface();
    // About 24 contact points per box.
    const int n = std::max(1, boxes);
    const int a = std::max(2, int(std::lround(std::cbrt(double(n)))) + 1);
    const double perLayer = 0.5 * double(a * a + (a - 1) * (a - 1));
    const int layers = std::max(1, int(std::lround(double(n) / perLayer)));
    addGround(w, surface, btScalar(a) + 10);
    for (int layer = 0; layer < layers; ++layer) {
        const bool shifted = layer % 2 == 1;
        const int m = shifted ? a - 1 : a;
        const btScalar offset = -0.5f * btScalar(m - 1);
        for (int iz = 0; iz < m; ++iz)
            for (int ix = 0; ix < m; ++ix)
                w.addUnitBox(btVector3(btScalar(ix) + offset, 0.5f + btScalar(layer), btScalar(iz) + offset), surface);
    }
}

void groundAndGridBlock(World& w, int boxes) {
    const BodyOptions surface = roughSurface();
    const int n = std::max(1, boxes);
    const int a = std::max(1, int(std::lround(std::cbrt(double(n)))));
    const int layers = std::max(1, int(std::lround(double(n) / double(a * a))));
    addGround(w, surface, btScalar(a) + 10);
    const btScalar offset = -0.5f * btScalar(a - 1);
    for (int layer = 0; layer < layers; ++layer)
        for (int iz = 0; iz < a; ++iz)
            for (int ix = 0; ix < a; ++ix)
                w.addUnitBox(btVector3(btScalar(ix) + offset, 0.5f + btScalar(layer), btScalar(iz) + offset), surface);
}

void basicDemoLattice(World& w, int n) {
    w.allowSleeping();
    const btVector3 groundHalf(50, 50, 50);
    w.addBox(groundHalf, 0, at(btVector3(0, -50, 0)));
    const btVector3 half(btScalar(0.1), btScalar(0.1), btScalar(0.1));
    const int a = std::max(1, n);
    for (int k = 0; k < a; ++k)
        for (int i = 0; i < a; ++i)
            for (int j = 0; j < a; ++j)
                w.addBox(half, 1, at(btVector3(btScalar(0.2 * i), btScalar(2 + 0.2 * k), btScalar(0.2 * j))));
}

void groundAnd3dPyramid(World& w, int base) {
    const int n = std::max(1, base);
    addGround(w, BodyOptions{}, btScalar(n) + 10);
    for (int layer = 0; layer < n; ++layer) {
        const int side = n - layer;
        const btScalar offset = -0.5f * btScalar(side - 1);
        for (int iz = 0; iz < side; ++iz)
            for (int ix = 0; ix < side; ++ix)
                w.addUnitBox(btVector3(btScalar(ix) + offset, 0.5f + btScalar(layer), btScalar(iz) + offset));
    }
}

}  // namespace btscenes
