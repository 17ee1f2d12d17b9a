// The JSON summary of a side-by-side run.
#pragma once

#include "BenchOptions.h"
#include "Scenes.h"
#include "SolverSide.h"

#include <string>
#include <vector>

namespace btbench {

struct RunFacts {
    const SceneInfo* scene = nullptr;
    int size = 0, steps = 0, driftFromStep = 0;
    int restingFromStep = 0;  // the resting window: the states of steps restingFromStep..steps
    btScalar divergenceFinal = 0, divergenceMax = 0;  // same body, SI world vs ours (when both ran)
    bool compared = false;                           // both sides stepped at least once
    std::string deviceName, pngFile;
    std::string solvePath, sortAndScan;  // ours: its solve path and the split's sort and scan
    int pngFrame = -1;
    std::vector<std::string> pngPanels;  // names of the sides drawn, left to right
    double wallSeconds = 0;
};

// The summary as indented JSON text. `siRandomized` (null unless --with-si-randomized) is a third
// side, Bullet's solver with its order randomized: reported beside the others, compared with none.
std::string summariseRun(const BenchOptions& options, const RunFacts& facts, const SolverSide* si,
                         const SolverSide* ours, const SolverSide* siRandomized = nullptr);

}  // namespace btbench
