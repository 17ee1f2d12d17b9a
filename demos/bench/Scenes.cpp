#include "Scenes.h"

#include "scenes/Joints.h"
#include "scenes/Stacks.h"

#include <algorithm>

namespace btbench {

namespace {

using btscenes::roughSurface;

// The ground of the scenes the tests share, reaching halfWidth from the origin.
btscenes::Ground roughGround(btScalar halfWidth) { return btscenes::Ground{roughSurface(), halfWidth}; }

void buildPyramid(World& w, int baseWidth) {
    const int n = std::max(1, baseWidth);
    btscenes::groundAndPyramid(w, n, roughSurface(), roughGround(btScalar(n) + 10));
}

void buildTallStack(World& w, int height) {
    btscenes::groundAndColumn(w, std::max(1, height), roughSurface(), roughGround(10));
}

void buildHingeChain(World& w, int links) { btscenes::addHingeChain(w, btVector3(0, 10, 0), std::max(1, links)); }

void buildBrickWall(World& w, int courses) {
    const int rows = std::max(1, courses);
    btscenes::BrickWall wall;
    wall.perRow = 2 * rows;  // a wall twice as wide as it is tall (in bricks)
    wall.brickMass = btscenes::boxMass(1, btVector3(0.5f, 0.25f, 0.25f));  // the density of the other scenes' boxes
    wall.brick = roughSurface();
    btscenes::groundAndBrickWall(w, rows, wall, roughGround(btScalar(wall.perRow) + 10));
}

}  // namespace

const std::vector<SceneInfo>& allScenes() {
    using namespace btscenes;
    static const std::vector<SceneInfo> scenes = {
        {"pyramid", "2D pyramid of unit boxes; size = boxes in the bottom row", buildPyramid, 20, 300, 5, true},
        {"stack", "one tall column of unit boxes; size = boxes", buildTallStack, 20, 300, 5, true},
        {"wall", "brick wall in running bond, twice as wide as tall; size = courses", buildBrickWall, 10, 300, 3, true},
        {"pile", "boxes dropped from a lattice with random orientations; size = boxes", groundAndTumblingPile, 1000, 300,
         27, false},
        {"columns", "the paper's Figure 1: leaning columns that topple into one pile; size = boxes",
         groundAndLeaningColumns, 12000, 300, 48, false},
        {"block", "dense block, layers offset by half a box; size = boxes", groundAndBondedBlock, 12000, 100, 60, true},
        {"block-grid", "dense block of boxes aligned face to face; size = boxes", groundAndGridBlock, 12000, 100, 64, true},
        {"ragdolls", "ragdolls (11 boxes, 10 limited cone-twist and hinge joints) dropped into a heap; size = ragdolls",
         groundAndRagdollPile, 200, 600, 2, false},
        {"machine", "chains and double pendulums under beams, struck by motor-driven paddles; size = chains",
         groundAndMachine, 64, 600, 4, false},
        {"basic", "Bullet's BasicDemo: a lattice of 0.2 m boxes dropped from 2 m, sleeping on; size = boxes a side",
         basicDemoLattice, 5, 300, 3, false},
        {"pyramid3d", "stepped 3D pyramid of unit boxes; size = boxes a side at the base",
         groundAnd3dPyramid, 12, 300, 4, true},
        {"chain", "a hinge chain pinned at one end, swinging down, sleeping on; size = links", buildHingeChain, 20, 300,
         5, false},
    };
    return scenes;
}

const SceneInfo* findScene(const std::string& name) {
    for (auto& s : allScenes())
        if (name == s.name) return &s;
    return nullptr;
}

}  // namespace btbench
