#include "scenes/Stacks.h"

namespace btscenes {

namespace {

void addGround(World& w, const Ground& g) { w.addGround(g.surface, btQuaternion::getIdentity(), g.halfWidth); }

}  // namespace

void addColumn(World& w, int boxes, btScalar x, btScalar z, const BodyOptions& o) {
    for (int i = 0; i < boxes; ++i) w.addUnitBox(btVector3(x, btScalar(0.5) + btScalar(i), z), o);
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

}  // namespace btscenes
