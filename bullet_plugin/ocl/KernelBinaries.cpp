#include "KernelBinaries.h"

#include "btOpenCLSolverError.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace btocl {
namespace {

// FNV-1a, 64 bits: a name, not a guard against tampering (the folders are as trusted as the library).
struct Fnv1a {
    std::uint64_t h = 14695981039346656037ull;
    void add(const std::string& s) {
        for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
        h = (h ^ 0xffu) * 1099511628211ull;  // a separator: "ab"+"c" differs from "a"+"bc"
    }
};

}  // namespace

std::string kernelBinaryKey(const std::string& source, const std::string& options, const cl::Device& device) {
    Fnv1a f;
    f.add(source);
    f.add(options);
    cl::Platform platform(device.getInfo<CL_DEVICE_PLATFORM>());
    f.add(platform.getInfo<CL_PLATFORM_NAME>());
    f.add(platform.getInfo<CL_PLATFORM_VERSION>());
    f.add(device.getInfo<CL_DEVICE_NAME>());
    f.add(device.getInfo<CL_DEVICE_VERSION>());
    f.add(device.getInfo<CL_DRIVER_VERSION>());
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(f.h));
    return hex;
}

std::vector<std::string> kernelBinaryDirs(const std::string& dir) {
    if (!dir.empty()) return {dir};
    if (const char* env = std::getenv("BT_OPENCL_KERNEL_BINARIES"); env && *env) {
        const std::string value = env;
        if (value == "off") return {};
        return {value};
    }
    return {BTOCL_KERNEL_BINARIES_BUILD_DIR, BTOCL_KERNEL_BINARIES_INSTALL_DIR};
}

std::vector<unsigned char> readKernelBinary(const std::vector<std::string>& dirs, const std::string& key) {
    for (const std::string& dir : dirs) {
        std::ifstream in(std::filesystem::path(dir) / (key + ".bin"), std::ios::binary | std::ios::ate);
        const std::streamsize size = in ? std::streamsize(in.tellg()) : 0;
        if (size <= 0) continue;
        std::vector<unsigned char> bytes(static_cast<size_t>(size));
        in.seekg(0);
        if (in.read(reinterpret_cast<char*>(bytes.data()), size)) return bytes;
    }
    return {};
}

void writeKernelBinary(const std::string& dir, const std::string& key, const std::vector<unsigned char>& bytes) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    const std::filesystem::path file = std::filesystem::path(dir) / (key + ".bin");
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) throw btOpenCLSolverError("btOpenCLConstraintSolver: cannot write the kernel binary " + file.string());
}

}  // namespace btocl
