// Creates the solver from the installed package and prints the version of its headers and the
// device it chose.
#include <btOpenCLConstraintSolver.h>

#include <cstdio>

static_assert(BTOCL_VERSION == BTOCL_VERSION_MAJOR * 10000 + BTOCL_VERSION_MINOR * 100 + BTOCL_VERSION_PATCH,
              "BTOCL_VERSION and its parts disagree");

int main() {
    std::printf("version: %d.%d.%d (%s)\n", BTOCL_VERSION_MAJOR, BTOCL_VERSION_MINOR, BTOCL_VERSION_PATCH,
                BTOCL_VERSION_STRING);
    try {
        btOpenCLConstraintSolver solver;
        std::printf("device: %s\n", solver.getDeviceName().c_str());
        return 0;
    } catch (const btOpenCLSolverError& e) {
        std::fprintf(stderr, "consumer: %s\n", e.what());
        return 1;
    }
}
