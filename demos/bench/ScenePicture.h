// Picture of one or more worlds of the same scene, side by side, from one camera.
#pragma once

#include "Raster.h"
#include "scenes/World.h"

#include <string>
#include <vector>

namespace btbench {

struct Panel {
    const btscenes::World* world;
    std::string label;  // drawn in the panel's top-left corner (e.g. the solver's name); empty: none
};

// One panel per world, left to right; the camera is fitted to the first world's dynamic boxes.
Image drawWorlds(const std::vector<Panel>& panels, int panelWidth, int panelHeight);

}  // namespace btbench
