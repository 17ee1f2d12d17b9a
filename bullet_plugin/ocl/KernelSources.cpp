#include "KernelSources.h"

#include "btOpenCLSolverError.h"

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

namespace btocl {
namespace {

std::string readKernelFile(const std::string& name) {
    if (const char* dir = std::getenv("BT_OPENCL_KERNEL_DIR"); dir && *dir) {
        std::ifstream in(std::string(dir) + "/" + name);
        if (!in) throw btOpenCLSolverError("kernel file '" + name + "' not found in BT_OPENCL_KERNEL_DIR=" + dir);
        std::ostringstream ss;
        ss << in.rdbuf();
        return ss.str();
    }
    for (const EmbeddedKernelFile& f : embeddedKernelFiles())
        if (name == f.name) return f.text;
    throw btOpenCLSolverError("kernel file '" + name + "' is not embedded in the library");
}

// Inlines local includes so a program builds from one string, with no include path.
void appendWithIncludes(const std::string& text, std::set<std::string>& seen, std::string& out) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        const auto first = line.find_first_not_of(" \t");
        if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
            const auto open = line.find('"');
            const auto close = line.find('"', open + 1);
            if (open != std::string::npos && close != std::string::npos) {
                const std::string name = line.substr(open + 1, close - open - 1);
                if (seen.insert(name).second) appendWithIncludes(readKernelFile(name), seen, out);
                continue;
            }
        }
        out += line;
        out += '\n';
    }
}

}  // namespace

std::string inlineKernelIncludes(const std::string& source) {
    std::set<std::string> seen;
    std::string out;
    appendWithIncludes(source, seen, out);
    return out;
}

std::string loadKernelSource(const std::string& name) { return inlineKernelIncludes(readKernelFile(name)); }

std::string loadKernelSources(const std::vector<std::string>& names) {
    std::set<std::string> seen;
    std::string out;
    for (const std::string& name : names) appendWithIncludes(readKernelFile(name), seen, out);
    return out;
}

}  // namespace btocl
