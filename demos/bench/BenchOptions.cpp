#include "BenchOptions.h"

#include "CliChecks.h"

#include <CLI/CLI.hpp>

#include <stdexcept>

namespace btbench {

namespace {

using btdemo::integerIn;
using btdemo::numberIn;

// The options, bound to the fields of `o` (and `solver`, turned into o.runSi/o.runOurs after
// parsing). The same set serves parsing and the --help text.
void addBenchOptions(CLI::App& app, BenchOptions& o, std::string& solver) {
    app.description(
        "Steps the same scene in two identical worlds, one with btSequentialImpulseConstraintSolver and\n"
        "one with btOpenCLConstraintSolver, and prints a JSON summary on stdout (progress on stderr).");
    app.footer(
        "Exit status: 0; 1 when a solver reports an error; 2 for bad arguments; 3 when --max-divergence\n"
        "is exceeded; 4 when --validate finds broken invariants.");
    app.get_formatter()->column_width(34);
    // --help is a field of BenchOptions, like --list, so that both can go without --scene.
    app.set_help_flag();
    // A repeated option takes its last value.
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);

    app.add_option("--scene", o.scene, "scene to run (see --list); required unless --help or --list")
        ->type_name("NAME");
    app.add_option("--steps", o.steps, "steps to run (default: the scene's, or 20 with --smoke)")
        ->type_name("N")
        ->transform(integerIn(0, 1000000));
    app.add_option("--size", o.size, "scene size; what it counts depends on the scene (default: the scene's)")
        ->type_name("K")
        ->transform(integerIn(1, 2000000));
    app.add_option("--iterations", o.iterations, "solver iterations, the same for both solvers")
        ->type_name("N")
        ->transform(integerIn(1, 10000))
        ->capture_default_str();
    app.add_option("--dt", o.dt, "time step in seconds")
        ->type_name("S")
        ->check(numberIn(1e-5, 1.0))
        ->capture_default_str();
    app.add_option("--solver", solver, "which sides to run: both, si (Bullet's alone) or ocl (ours alone)")
        ->type_name("WHICH")
        ->check(CLI::IsMember({"both", "si", "ocl"}))
        ->capture_default_str();
    app.add_option("--whole-step-max-rows", o.wholeStepMaxRows,
                   "our solver's wholeStepMaxRows: steps of at most this many rows solved whole, unsplit (-1: automatic, 0: never)")
        ->check(CLI::Range(-1, 2000000000));
    app.add_option("--host-step-max-rows", o.hostStepMaxRows,
                   "our solver's hostStepMaxRows: steps of at most this many rows solved on the calling thread (-1: automatic, 0: never)")
        ->check(CLI::Range(-1, 2000000000));
    app.add_option("--split-steps-on-host", o.splitStepsOnHost,
                   "our solver's splitStepsOnHost: split steps solved on the calling thread (-1: where recent steps ran faster, 0: never, 1: always)")
        ->check(CLI::Range(-1, 1));
    app.add_option("--solve-path", o.solvePath,
                   "our solver's path: auto (BT_OPENCL_SOLVE_PATH, else by device type), serial or wide")
        ->type_name("PATH")
        ->check(CLI::IsMember({"auto", "serial", "wide"}))
        ->capture_default_str();
    app.add_option("--order", o.order,
                   "our solver's order: rotated (each iteration starts a manifold's points at another), fixed (as Bullet's) "
                   "or randomized (SOLVER_RANDMIZE_ORDER in its world's solver info)")
        ->type_name("ORDER")
        ->check(CLI::IsMember({"rotated", "fixed", "randomized"}))
        ->capture_default_str();
    app.add_flag("--with-si-randomized", o.withSiRandomized,
                 "a third world: Bullet's solver with SOLVER_RANDMIZE_ORDER (JSON side siRandomized)");
    app.add_flag("--stand-in", o.standIn, "use a second btSequentialImpulseConstraintSolver in place of ours");
    app.add_flag("--validate", o.validate, "check split and batch invariants every step (exit 4 if broken)");
    app.add_flag("--allow-ocl-error", o.allowOclError,
                 "exit 0 even when our solver reports an error (the JSON still has it)");
    app.add_option("--max-divergence", o.maxDivergence,
                   "exit 3 when the same body differs by more than D between the worlds")
        ->type_name("D")
        ->check(numberIn(0, 1e30));
    app.add_option("--png", o.pngFile, "picture of step K (see --frame), SI left, ours right")->type_name("FILE");
    app.add_option("--frame", o.frame, "step drawn by --png, 0 = before the first step (default: the last)")
        ->type_name("K")
        ->transform(integerIn(0, 1000000));
    app.add_option("--json", o.jsonFile, "also write the JSON summary to FILE")->type_name("FILE");
    app.add_flag("--smoke", o.smoke, "the scene's small test size and 20 steps (unless --size/--steps say)");
    app.add_flag("--list", o.listScenes, "list the scenes with their default sizes and steps");
    app.add_flag("-h,--help", o.help, "print this help");
}

}  // namespace

std::string benchUsage() {
    BenchOptions unused;
    std::string solver = "both";
    CLI::App app("", "btocl_bench");
    addBenchOptions(app, unused, solver);
    return app.help();
}

BenchOptions parseBenchOptions(const std::vector<std::string>& args) {
    BenchOptions o;
    std::string solver = "both";
    CLI::App app("", "btocl_bench");
    addBenchOptions(app, o, solver);
    try {
        // CLI11 takes the arguments last first.
        app.parse(std::vector<std::string>(args.rbegin(), args.rend()));
    } catch (const CLI::ParseError& e) {
        throw std::invalid_argument(e.what());
    }
    o.runSi = solver != "ocl";
    o.runOurs = solver != "si";
    if (!o.help && !o.listScenes && o.scene.empty()) throw std::invalid_argument("--scene is required");
    return o;
}

}  // namespace btbench
