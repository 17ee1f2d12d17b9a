// Scenes of boxes on the ground, as free functions on a World (World.h):
//     groundAndPyramid(w, 10);
// Bodies are made in a fixed order, so body i of one build is body i of another; the ground is
// body 0. The defaults are the tests' scenes (their tolerances were measured on them); the
// benchmark passes its own surfaces and ground (roughSurface()).
#pragma once

#include "scenes/World.h"

namespace btscenes {

// A box in a stack: friction 0.7, so 0.49 combined between two boxes.
inline BodyOptions stackedBox() {
    BodyOptions o;
    o.friction = btScalar(0.7);
    return o;
}

// Every body of the benchmark's scenes, the ground too: friction 0.8, so 0.64 combined.
inline BodyOptions roughSurface() {
    BodyOptions o;
    o.friction = btScalar(0.8);
    return o;
}

// `boxes` unit boxes on top of each other, the lowest resting on the plane y = 0 at (x, z); with
// a lean, each box stands leanPerBox further along leanDirection than the one below.
void addColumn(World& w, int boxes, btScalar x = 0, btScalar z = 0, const BodyOptions& o = stackedBox(),
               const btVector3& leanDirection = btVector3(0, 0, 0), btScalar leanPerBox = 0);

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

// The benchmark's larger scenes, sized by one number (at least 1) whose meaning each says; each
// makes its own ground, reaching well past the scene, and every body is of roughSurface().

// `boxes` unit boxes dropped from a lattice of cbrt(boxes) a side, 1.8 m apart (more than a
// box's diagonal), each layer shifted at random and each box turned at random, so that they
// tumble into a heap.
void groundAndTumblingPile(World& w, int boxes);

// The paper's Figure 1: columns about 1.3 cbrt(boxes) tall on a square grid 2 m apart, each box
// 0.04 m further toward the grid's centre than the one below, so that every column topples
// inward and they fall into one pile. 12,000 boxes: 20 x 20 columns of 30.
void groundAndLeaningColumns(World& w, int boxes);

// A dense block of about `boxes` unit boxes whose layers alternate a x a and (a-1) x (a-1) boxes
// shifted by half a box in x and z, so that each box of an upper layer rests on four below it.
void groundAndBondedBlock(World& w, int boxes);

// A dense block of about `boxes` unit boxes aligned face to face, layers of a x a.
void groundAndGridBlock(World& w, int boxes);

// Scenes as a new user first builds them, after Bullet's own examples, on Bullet's default surface.
// BasicDemo (its bodies may fall asleep, Bullet's default): an n x n x n lattice of 0.2 m boxes of 1 kg, 0.2 m apart (touching), dropped from
// 2 m onto a large static box.
void basicDemoLattice(World& w, int n);
// A stepped 3D pyramid of unit boxes, base x base boxes in its lowest layer, one fewer each way
// in each layer above (base 12: 650 boxes; base 20: 2,870, about BenchmarkDemo's 3,000). Awake
// throughout, as a benchmark needs it.
void groundAnd3dPyramid(World& w, int base);

}  // namespace btscenes
