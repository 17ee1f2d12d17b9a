// Run by the library's build: for each OpenCL device of this machine and each solve path, builds
// the programs the solver uses, warms every kernel up (so that PoCL generates the code of each
// variant a step launches), and writes each program's binary into the folder given, named by
// kernelBinaryKey (ocl/KernelBinaries.h). A device that fails is skipped with a note: the library
// then compiles for it as it would without binaries. Writes <folder>/made last, listing them.
#include "OclRuntime.h"
#include "StepPipeline.h"
#include "btOpenCLConstraintSolver.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s FOLDER\n", argv[0]);
        return 2;
    }
    const fs::path dir = argv[1];
    std::error_code ec;
    fs::create_directories(dir, ec);
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".bin") fs::remove(e.path(), ec);  // another build's

    std::string made;
    std::vector<btocl::DeviceEntry> devices;
    try {
        devices = btocl::listDevices();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "kernel binaries: no OpenCL device (%s): none made\n", e.what());
    }
    for (size_t i = 0; i < devices.size(); ++i) {
        const std::string name = devices[i].platformName + " / " + devices[i].deviceName;
        // Both paths: a device runs its own by default, the other when the config or
        // BT_OPENCL_SOLVE_PATH asks for it (the tests run both).
        for (const btOpenCLSolvePath path : {btOpenCLSolvePath::Serial, btOpenCLSolvePath::Wide}) {
            const char* pathName = path == btOpenCLSolvePath::Serial ? "serial" : "wide";
            try {
                const auto t0 = std::chrono::steady_clock::now();
                btOpenCLSolverConfig config;
                config.device = std::to_string(i);
                config.solvePath = path;
                config.kernelBinaries = false;  // compiled here, whatever the folders hold
                btocl::StepPipeline pipeline(config);
                pipeline.warmUp();
                pipeline.runtime().writeProgramBinaries(dir.string());
                const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                std::printf("kernel binaries: %s, %s path: %zu program(s) in %.1f s\n", name.c_str(), pathName,
                            pipeline.runtime().programBuilds().size(), s);
                for (const btocl::OclRuntime::ProgramBuild& b : pipeline.runtime().programBuilds())
                    made += b.binaryKey + ".bin  " + name + "  " + b.name + "\n";
            } catch (const std::exception& e) {
                std::fprintf(stderr, "kernel binaries: %s, %s path, skipped: %s\n", name.c_str(), pathName, e.what());
            }
        }
    }
    std::ofstream(dir / "made") << made;
    return 0;
}
