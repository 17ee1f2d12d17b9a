// Picture of one or more worlds of the same scene, side by side, from one camera.
#pragma once

#include "Raster.h"
#include "scenes/World.h"

#include <vector>

namespace btbench {

// One panel per world, left to right; the camera is fitted to the first world's dynamic boxes.
Image drawWorlds(const std::vector<const btscenes::World*>& worlds, int panelWidth, int panelHeight);

}  // namespace btbench
