#include "BenchOptions.h"

#include <stdexcept>

namespace btbench {

const char* benchUsage() {
    return "usage: btocl_bench --scene NAME [--steps N] [--iterations N] [--size K] [--dt S]\n"
           "                   [--solver both|si|ocl] [--stand-in] [--validate] [--allow-ocl-error]\n"
           "                   [--max-divergence D] [--png FILE [--frame K]] [--json FILE] [--smoke]\n"
           "       btocl_bench --list\n"
           "Steps the same scene in two identical worlds, one with btSequentialImpulseConstraintSolver and\n"
           "one with btOpenCLConstraintSolver, and prints a JSON summary on stdout (progress on stderr).\n"
           "  --stand-in          use a second btSequentialImpulseConstraintSolver in place of ours\n"
           "  --allow-ocl-error   exit 0 even when our solver reports an error (the JSON still has it)\n"
           "  --max-divergence D  exit 3 when the same body differs by more than D between the worlds\n"
           "  --png FILE          picture of step K (default: the last), SI left, ours right\n"
           "  --smoke             the scene's small test size and 20 steps (unless --size/--steps say)\n";
}

namespace {

long parseInteger(const std::string& flag, const std::string& text, long lo, long hi) {
    size_t used = 0;
    long value = 0;
    try {
        value = std::stol(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || text.empty() || value < lo || value > hi)
        throw std::invalid_argument(flag + " wants an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                    "], got '" + text + "'");
    return value;
}

double parseReal(const std::string& flag, const std::string& text, double lo, double hi) {
    size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || text.empty() || !(value >= lo && value <= hi))
        throw std::invalid_argument(flag + " wants a number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                    "], got '" + text + "'");
    return value;
}

}  // namespace

BenchOptions parseBenchOptions(const std::vector<std::string>& args) {
    BenchOptions o;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw std::invalid_argument(a + " needs a value");
            return args[++i];
        };
        if (a == "--scene") o.scene = value();
        else if (a == "--steps") o.steps = int(parseInteger(a, value(), 0, 1000000));
        else if (a == "--size") o.size = int(parseInteger(a, value(), 1, 2000000));
        else if (a == "--iterations") o.iterations = int(parseInteger(a, value(), 1, 10000));
        else if (a == "--dt") o.dt = parseReal(a, value(), 1e-5, 1.0);
        else if (a == "--solver") {
            const std::string& s = value();
            if (s == "both") o.runSi = o.runOurs = true;
            else if (s == "si") { o.runSi = true; o.runOurs = false; }
            else if (s == "ocl") { o.runSi = false; o.runOurs = true; }
            else throw std::invalid_argument("--solver wants both, si or ocl, got '" + s + "'");
        }
        else if (a == "--stand-in") o.standIn = true;
        else if (a == "--validate") o.validate = true;
        else if (a == "--allow-ocl-error") o.allowOclError = true;
        else if (a == "--max-divergence") o.maxDivergence = parseReal(a, value(), 0, 1e30);
        else if (a == "--png") o.pngFile = value();
        else if (a == "--frame") o.frame = int(parseInteger(a, value(), 0, 1000000));
        else if (a == "--json") o.jsonFile = value();
        else if (a == "--smoke") o.smoke = true;
        else if (a == "--list") o.listScenes = true;
        else if (a == "--help" || a == "-h") o.help = true;
        else throw std::invalid_argument("unknown argument '" + a + "'");
    }
    if (!o.help && !o.listScenes && o.scene.empty()) throw std::invalid_argument("--scene is required");
    return o;
}

}  // namespace btbench
