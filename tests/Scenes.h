// Scenes the tests build, as free functions on a World (TestWorld.h):
//     Pair p;
//     p.build([](World& w) { groundAndPile(w, 64); });
// Bodies are made in a fixed order, so body i of one build is body i of another; where there is
// a ground it is body 0.
#pragma once

#include "TestWorld.h"

namespace testworld {

// A box in a stack: friction 0.7, so 0.49 combined between two boxes.
inline BodyOptions stackedBox() {
    BodyOptions o;
    o.friction = btScalar(0.7);
    return o;
}

// `boxes` unit boxes on top of each other, the lowest resting on the plane y = 0 at (x, z).
inline void addColumn(World& w, int boxes, btScalar x = 0, btScalar z = 0, const BodyOptions& o = stackedBox()) {
    for (int i = 0; i < boxes; ++i) w.addUnitBox(btVector3(x, btScalar(0.5) + btScalar(i), z), o);
}

inline void groundAndColumn(World& w, int boxes) {
    w.addGround();
    addColumn(w, boxes);
}

// The ground and a loose pile of `boxes` unit boxes: layers of 4 x 4, 1.05 m apart, dropped with
// small sideways offsets (deterministic), so that they land on each other's edges.
inline void groundAndPile(World& w, int boxes) {
    w.addGround();
    for (int i = 0; i < boxes; ++i) {
        const int layer = i / 16, k = i % 16;
        w.addUnitBox(btVector3(btScalar(k % 4) * 1.1f + 0.05f * btScalar(layer % 3), 0.5f + btScalar(layer) * 1.05f,
                               btScalar(k / 4) * 1.1f - 0.04f * btScalar(layer % 2)));
    }
}

// The ground and a 2D pyramid of unit boxes in the x-y plane, `base` boxes in its lowest row.
inline void groundAndPyramid(World& w, int base) {
    w.addGround();
    for (int row = 0; row < base; ++row)
        for (int i = 0; i < base - row; ++i)
            w.addUnitBox(btVector3(btScalar(i + 0.5 * row - 0.5 * (base - 1)), btScalar(0.5) + row, 0), stackedBox());
}

// The ground and a brick wall in running bond: 1 x 0.5 x 0.5 m bricks of 1 kg, `rows` rows of 6
// and 5 by turns, the rows of 5 shifted by half a brick so that every brick rests on two below.
inline void groundAndBrickWall(World& w, int rows) {
    w.addGround();
    const btVector3 half(btScalar(0.5), btScalar(0.25), btScalar(0.25));
    for (int row = 0; row < rows; ++row) {
        const int n = (row % 2) ? 5 : 6;
        const btScalar shift = (row % 2) ? btScalar(0.5) : btScalar(0);
        for (int i = 0; i < n; ++i)
            w.addBox(half, 1, at(btVector3(i + shift - btScalar(2.5), btScalar(0.25) + btScalar(0.5) * row, 0)),
                     stackedBox());
    }
}

}  // namespace testworld
