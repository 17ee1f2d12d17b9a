// The benchmark's scenes: plain functions that fill a SceneWorld with a static ground and
// dynamic boxes (btBoxShape, mass from density), some joined by joints. Each is sized by one
// number, `size`, whose meaning the scene's description gives. The same function with the same
// size always builds the same bodies and joints in the same order.
#pragma once

#include "SceneWorld.h"

#include <string>
#include <vector>

namespace btbench {

void buildPyramid(SceneWorld& w, int baseWidth);       // 2D pyramid, baseWidth boxes at the bottom
void buildTallStack(SceneWorld& w, int height);        // one column of `height` boxes
void buildBrickWall(SceneWorld& w, int courses);       // `courses` rows of half-offset bricks
void buildPile(SceneWorld& w, int count);              // `count` boxes dropped from a lattice
void buildColumnsCollapse(SceneWorld& w, int count);   // the paper's Figure 1: leaning columns
void buildBondedBlock(SceneWorld& w, int count);       // dense block, layers offset by half a box
void buildGridBlock(SceneWorld& w, int count);         // dense block, boxes aligned in a grid
void buildRagdolls(SceneWorld& w, int count);          // `count` ragdolls dropped onto each other
void buildMachine(SceneWorld& w, int chains);          // chains, hinged pendulums, motor-driven paddles

struct SceneInfo {
    const char* name;
    const char* description;
    void (*build)(SceneWorld&, int size);
    int defaultSize;
    int defaultSteps;
    int smokeSize;          // small enough for a CTest smoke run
    bool startsAtRest;      // every box should stay where it starts (drift measured from step 0)
};

const std::vector<SceneInfo>& allScenes();
const SceneInfo* findScene(const std::string& name);

}  // namespace btbench
