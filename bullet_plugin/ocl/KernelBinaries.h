// Program binaries made when the library is built (bullet_plugin/tools/make_kernel_binaries.cpp),
// for the OpenCL devices of the machine that builds it: a program built from its binary skips the
// device's compiler, which on PoCL with an empty cache costs seconds (docs/performance.md,
// "Start-up"). PoCL's binary holds the code of every kernel variant the warm-up made, so that no
// launch compiles either. A file is named by a hash of all its code depends on (source, options,
// device, driver), so it meets only the program it was made from; one the device refuses is
// passed over and the source compiled (OclRuntime::buildProgramSource).
#pragma once

#include "OclInclude.h"

#include <string>
#include <vector>

namespace btocl {

// The file name (without extension) of a program's binary: a hash of the program's source and
// build options and of the device's and driver's names and versions.
std::string kernelBinaryKey(const std::string& source, const std::string& options, const cl::Device& device);

// Where binaries are looked for: `dir` alone when it is not empty; else the environment variable
// BT_OPENCL_KERNEL_BINARIES alone when it is set ("off": nowhere); else the build tree's folder and
// the installed one, in that order.
std::vector<std::string> kernelBinaryDirs(const std::string& dir = "");

// The bytes of the first file <dir>/<key>.bin of `dirs`; empty when there is none.
std::vector<unsigned char> readKernelBinary(const std::vector<std::string>& dirs, const std::string& key);

// Writes <dir>/<key>.bin (the folder made if need be). Throws btOpenCLSolverError when it cannot.
void writeKernelBinary(const std::string& dir, const std::string& key, const std::vector<unsigned char>& bytes);

}  // namespace btocl
