// The benchmark's scenes: the scenes library's builders (scenes/Stacks.h, scenes/Joints.h) with
// the benchmark's surfaces (friction 0.8 everywhere) and grounds, each sized by one number,
// `size`, whose meaning the scene's description gives. The same scene with the same size always
// builds the same bodies and joints in the same order.
#pragma once

#include "scenes/World.h"

#include <string>
#include <vector>

namespace btbench {

using btscenes::World;

struct SceneInfo {
    const char* name;
    const char* description;
    void (*build)(World&, int size);
    int defaultSize;
    int defaultSteps;
    int smokeSize;          // small enough for a CTest smoke run
    bool startsAtRest;      // every box should stay where it starts (drift measured from step 0)
};

const std::vector<SceneInfo>& allScenes();
const SceneInfo* findScene(const std::string& name);

}  // namespace btbench
