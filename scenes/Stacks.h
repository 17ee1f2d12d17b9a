// Scenes of boxes on the ground, as free functions on a World (World.h):
//     groundAndPyramid(w, 10);
// Bodies are made in a fixed order, so body i of one build is body i of another; the ground is
// body 0. The defaults are the tests' scenes (their tolerances were measured on them).
#pragma once

#include "scenes/World.h"

namespace btscenes {

// A box in a stack: friction 0.7, so 0.49 combined between two boxes.
inline BodyOptions stackedBox() {
    BodyOptions o;
    o.friction = btScalar(0.7);
    return o;
}

// `boxes` unit boxes on top of each other, the lowest resting on the plane y = 0 at (x, z).
void addColumn(World& w, int boxes, btScalar x = 0, btScalar z = 0, const BodyOptions& o = stackedBox());

void groundAndColumn(World& w, int boxes, const BodyOptions& box = stackedBox(), const Ground& ground = {});

// The ground and a loose pile of `boxes` unit boxes: layers of 4 x 4, 1.05 m apart, dropped with
// small sideways offsets (deterministic), so that they land on each other's edges.
void groundAndPile(World& w, int boxes, const BodyOptions& box = {}, const Ground& ground = {});

// The ground and a 2D pyramid of unit boxes in the x-y plane, `base` boxes in its lowest row.
void groundAndPyramid(World& w, int base, const BodyOptions& box = stackedBox(), const Ground& ground = {});

// A wall's bricks: 1 x 0.5 x 0.5 m, `perRow` in the full rows.
struct BrickWall {
    int perRow = 6;
    btScalar brickMass = 1;
    BodyOptions brick = stackedBox();
};

// The ground and a brick wall in running bond: `rows` rows of perRow and perRow - 1 bricks by
// turns, the shorter rows shifted by half a brick so that every brick rests on two below.
void groundAndBrickWall(World& w, int rows, const BrickWall& wall = {}, const Ground& ground = {});

}  // namespace btscenes
