// Scenes the tests build, as free functions on a World (TestWorld.h), from the scenes library
// that the benchmark builds too (scenes/Stacks.h):
//     Pair p;
//     p.build([](World& w) { groundAndPile(w, 64); });
// Bodies are made in a fixed order, so body i of one build is body i of another; where there is
// a ground it is body 0.
#pragma once

#include "TestWorld.h"
#include "scenes/Stacks.h"

namespace testworld {

using btscenes::addColumn;
using btscenes::groundAndBrickWall;
using btscenes::groundAndColumn;
using btscenes::groundAndPile;
using btscenes::groundAndPyramid;
using btscenes::stackedBox;

}  // namespace testworld
