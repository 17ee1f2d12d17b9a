// Command line of btocl_bench.
#pragma once

#include <string>
#include <vector>

namespace btbench {

struct BenchOptions {
    std::string scene;
    int steps = -1;       // -1: the scene's default
    int size = -1;        // -1: the scene's default
    int iterations = 10;  // btContactSolverInfo::m_numIterations for both solvers
    double dt = 1.0 / 60.0;
    bool runSi = true, runOurs = true;
    std::string solvePath = "auto";    // btOpenCLSolverConfig::solvePath
    std::string order = "fixed";       // rotated: btOpenCLSolverConfig::rotatePoints; randomized: SOLVER_RANDMIZE_ORDER
    int wholeStepMaxRows = -1;         // btOpenCLSolverConfig::wholeStepMaxRows
    int hostStepMaxRows = -1;          // btOpenCLSolverConfig::hostStepMaxRows
    int splitStepsOnHost = -1;         // btOpenCLSolverConfig::splitStepsOnHost
    bool withSiRandomized = false;     // a third world: Bullet's solver with SOLVER_RANDMIZE_ORDER
    bool standIn = false;        // put a second Bullet SI solver where ours goes (checks the harness)
    bool validate = false;       // btOpenCLSolverConfig::validate
    bool allowOclError = false;  // exit 0 even when our solver reports an error
    double maxDivergence = -1;   // >= 0: exit 3 when the trajectories part by more than this
    std::string pngFile;
    int frame = -1;              // step whose state is drawn (0 = before the first step); -1: the last
    std::string jsonFile;
    bool smoke = false;          // the scene's small smoke-test size and 20 steps (unless given)
    bool listScenes = false;
    bool help = false;
};

// Parses the arguments after the program name. Throws std::invalid_argument with a message
// naming the bad argument.
BenchOptions parseBenchOptions(const std::vector<std::string>& args);
// The --help text: what the program does and every option.
std::string benchUsage();

}  // namespace btbench
