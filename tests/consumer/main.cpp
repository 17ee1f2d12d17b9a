// Creates the solver from the installed package and prints the device it chose.
#include <btOpenCLConstraintSolver.h>

#include <cstdio>

int main() {
    try {
        btOpenCLConstraintSolver solver;
        std::printf("device: %s\n", solver.getDeviceName().c_str());
        return 0;
    } catch (const btOpenCLSolverError& e) {
        std::fprintf(stderr, "consumer: %s\n", e.what());
        return 1;
    }
}
