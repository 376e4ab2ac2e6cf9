// The `aamap` command line. Results go to files; stderr carries logs and, on failure, one
// "aamap: error: ..." line. Exit codes: 0 ok, 1 environment, 2 bad input, 3 validation messages.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <unistd.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "aamap/git_revision.h"
#include "app/diff_command.h"
#include "app/executor.h"
#include "app/snapshot_command.h"
#include "app/view_command.h"
#include "core/error.h"
#include "core/heap.h"
#include "core/log.h"
#include "engine/vk/context.h"
#include "eval/compare.h"
#include "eval/config.h"
#include "eval/config_schema.h"
#include "eval/experiment.h"
#include "eval/report.h"
#include "eval/sweep_runner.h"
#include "eval/strategies.h"

namespace {

constexpr int kExitEnvironment = 1;
constexpr int kExitInput = 2;
constexpr int kExitValidation = 3;

const char* const kRunFooter = R"(CONFIG is a YAML experiment (configs/cornell.yaml is the default one; full schema in
docs/config.md). Paths in it are relative to the config file. Keys:
  scene: builtin:cornell | path to .obj/.gltf/.glb/.xml (Mitsuba)
  view: path to a Radiance .vf, or null (scene's view)    seed: 1
  camera: {position: [x,y,z], look_at: [x,y,z], up: [0,1,0], fov: 45 (horizontal)} instead of view
  light_file: lights.yaml (docs/lights.md)  lights: [{type: point|spot|quad|disk, name, position: [x,y,z],
            intensity|radiance|power: [r,g,b], normal, direction, inner_angle, outer_angle, size, radius}]
@SECTIONS@
  renders: [{name: NAME, series: LABEL, strategy: S, rpp: n*n or a list (a sweep),
             <strategy parameter>: value or list}]     lists sweep: the cartesian product
@STRATEGIES@
  reference: {type: uniform|file|none, rpp: max of renders, mode: shading mode, path: EXR}
--set overrides one value, e.g. --set image.width=256 --set renders.1.rpp=[1,4,16] (the value is YAML).

Writes into OUTDIR: report.html, report.md, results.csv, results.json; snapshot.png, laplacian.png,
aamap.exr, aamap.png; per render NAME.exr (linear), NAME.png (sRGB), NAME.rpp.png (rays per pixel),
NAME.flip.png and NAME.overlay.png (FLIP error); reference.*, one_ray.*, aliasing.png; plots/.
Finished renders are kept in OUTDIR/cache and reused: rerunning a killed run only traces the rest.

Environment: AAMAP_VALIDATION=1 turns on --validation; AAMAP_DEVICE sets the default --device.
Exit codes: 0 success, 1 environment error (no GPU, disk), 2 bad input (config, scene, options),
3 Vulkan validation messages.)";

// The section and strategy lines come from their schemas, so new keys and strategies show up
// here by themselves.
std::string runFooter() {
    std::string footer = kRunFooter;
    const auto fill = [&](const std::string& token, const std::string& lines) {
        footer.replace(footer.find(token), token.size(), lines);
    };
    fill("@SECTIONS@\n", aamap::sectionHelpLines());
    fill("@STRATEGIES@\n", aamap::strategyHelpLines());
    return footer;
}

bool envFlag(const char* name) {
    const char* v = std::getenv(name);
    if (v == nullptr) return false;
    const std::string s = v;
    return s == "1" || s == "true" || s == "on" || s == "yes" || s == "TRUE" || s == "ON" || s == "YES";
}

std::string envString(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

int fail(int code, const std::string& message) {
    std::fflush(stdout);
    fmt::print(stderr, "aamap: error: {}\n", message);
    return code;
}

// SIGINT/SIGTERM during a run: every finished render is already committed atomically to
// OUTDIR/cache and no output is ever half-written under its final name, so stopping at once is
// clean. Say so and how to resume (write(2) and _Exit only: async-signal-safe).
std::string interruptMessage;

void onInterrupt(int) {
    const ssize_t written = ::write(STDERR_FILENO, interruptMessage.data(), interruptMessage.size());
    (void)written;
    std::_Exit(130);
}

void stopCleanlyOnInterrupt(const std::filesystem::path& out) {
    interruptMessage = fmt::format("\naamap: interrupted; finished renders are kept in {}; run the same command "
                                   "again to resume\n", (out / "cache").string());
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
}

}  // namespace

int main(int argc, char** argv) {
    aamap::keepFreedMemoryForReuse();
    CLI::App app{"aamap: analytic antialiasing maps for selective high-fidelity rendering.\n"
                 "A Vulkan snapshot of the scene finds the edges that need antialiasing; an Embree\n"
                 "tracer spends its rays there.",
                 "aamap"};
    app.set_version_flag("--version", fmt::format("aamap 0.1.0 ({})", AAMAP_GIT_REVISION));
    app.require_subcommand(1);
    app.fallthrough();  // -v/-q work after the subcommand too
    app.footer("Run 'aamap run --help' for the experiment options and config keys.");
    bool verbose = false, quiet = false;
    app.add_flag("-v,--verbose", verbose, "Debug logging");
    app.add_flag("-q,--quiet", quiet, "Warnings and errors only");

    CLI::App* run = app.add_subcommand("run", "Run an experiment: snapshot, aamap, renders, metrics, report");
    CLI::App* report = app.add_subcommand("report", "Rebuild report.html, report.md, results.csv and the plots from OUTDIR/results.json");
    std::string reportDir;
    report->add_option("OUTDIR", reportDir, "An experiment's output folder")->required();
    bool reportNoPlots = false;
    report->add_flag("--no-plots", reportNoPlots, "Skip tools/report_plots.py (the report notes it)");
    aamap::app::SnapshotOptions snapshotOptions;
    CLI::App* snapshot = aamap::app::addSnapshotCommand(app, snapshotOptions);
    const std::unique_ptr<aamap::ViewCommand> view = aamap::addViewCommand(app);
    CLI::App* compare = app.add_subcommand("compare", "Merge several experiments' results into one report and CSV, "
                                                      "with a column for each setting that differs between them, and "
                                                      "per scene the time-error Pareto front over all their renders");
    std::vector<std::string> compareDirs;
    std::string compareOut;
    bool compareNoPlots = false;
    compare->add_option("OUTDIR", compareDirs, "Experiment output folders (each with results.json; a sweep's folder counts as all its variants)")->required();
    compare->add_option("-o,--out", compareOut, "Where compare.html, compare.md and compare.csv go")
        ->required()
        ->type_name("OUT");
    compare->add_flag("--no-plots", compareNoPlots, "Skip the error-against-time plot (tools/report_plots.py --compare)");
    aamap::app::DiffOptions diffOptions;
    CLI::App* diff = aamap::app::addDiffCommand(app, diffOptions);
    std::string configPath, outDir, device = envString("AAMAP_DEVICE");
    std::vector<std::string> overrides;
    bool validation = envFlag("AAMAP_VALIDATION"), noPlots = false, listWork = false;
    int threads = -1;
    std::string executor = "local", rayAddress, onlyKey, cacheDir;
    run->add_option("CONFIG", configPath, "Experiment YAML file")->required();
    run->add_option("-o,--out", outDir, "Output folder (default: out/<config stem>)")->type_name("OUTDIR");
    run->add_option("--set", overrides, "Override a config value: key.path=value (repeatable)")
        ->expected(1)
        ->allow_extra_args(false)  // "--set a=1 CONFIG": CONFIG is not a second override
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->type_name("KEY=VALUE");
    run->add_option("--device", device, "Vulkan device: index or name substring (default: best GPU)")
        ->type_name("NAME");
    run->add_flag("--validation", validation, "Enable the Vulkan validation layer; any message fails the run (exit 3)");
    run->add_option("--threads", threads, "Tracer threads (overrides the config; 0 = all)")->check(CLI::NonNegativeNumber);
    // Needs no CONFIG: it acts while parsing, before CONFIG is found missing.
    int devicesListed = 0;
    run->add_flag_callback("--list-devices", [&devicesListed] {
           std::vector<std::string> devices;
           try {
               devices = aamap::VulkanContext::listDevices();
           } catch (const std::exception& e) {
               fmt::print(stderr, "aamap: {}\n", e.what());
           }
           for (std::size_t i = 0; i < devices.size(); ++i) fmt::print("{}: {}\n", i, devices[i]);
           devicesListed = devices.empty() ? 1 : 2;
           throw CLI::Success();
       })->trigger_on_parse()->description("Print the Vulkan devices and exit");
    run->add_flag_callback("--list-keys", [] {
           fmt::print("{}", aamap::configKeysMarkdown());
           throw CLI::Success();
       })->trigger_on_parse()->description("Print every schema key (type, range, default, meaning) as a Markdown table and exit");
    run->add_flag("--no-plots", noPlots, "Skip tools/report_plots.py (the report notes it)");
    run->add_option("--executor", executor, "Where the renders run: local (this process) or ray (a Ray cluster; "
                                            "docs/experiments.md)")
        ->check(CLI::IsMember({"local", "ray"}));
    run->add_option("--ray-address", rayAddress, "--executor ray: the cluster to join (default: start a local one)")
        ->type_name("ADDR");
    bool planOnly = false;
    run->add_flag("--plan", planOnly, "Print the variants, renders, what is cached, the rays and the time of each "
                                      "render, and exit: nothing is traced or written");
    run->add_flag("--list-work", listWork, "Print the Snapshots and renders the cache lacks as JSON and exit");
    run->add_option("--only", onlyKey, "Compute exactly the one Snapshot or render with this cache key, then exit")
        ->type_name("KEY");
    run->add_option("--cache", cacheDir, "The render cache (default: OUTDIR/cache)")->type_name("DIR");
    run->footer(runFooter());

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (devicesListed == 1) return fail(kExitEnvironment, "no Vulkan devices found");
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version, --list-devices
        return fail(kExitInput, fmt::format("{}\nRun 'aamap --help' for usage.", e.what()));
    }
    aamap::initLogging(verbose ? spdlog::level::debug : quiet ? spdlog::level::warn : spdlog::level::info);

    try {
        if (report->parsed()) {
            aamap::rebuildReport(reportDir, !reportNoPlots);
            return 0;
        }
        if (compare->parsed()) {
            aamap::writeComparison({compareDirs.begin(), compareDirs.end()}, compareOut, {}, !compareNoPlots);
            return 0;
        }
        if (diff->parsed()) {
            aamap::app::runDiffCommand(diffOptions);
            return 0;
        }
        if (view->command->parsed()) {
            aamap::runViewCommand(*view);
            return 0;
        }
        if (snapshot->parsed()) {
            if (aamap::app::runSnapshotCommand(snapshotOptions, validation || snapshotOptions.validation,
                                               snapshotOptions.device.empty() ? device : snapshotOptions.device) != 0)
                return fail(kExitValidation, "Vulkan validation messages (see above)");
            return 0;
        }
        if (executor == "ray" && (listWork || !onlyKey.empty()))
            return fail(kExitInput, "run: --executor ray cannot be combined with --list-work or --only");
        if (!rayAddress.empty() && executor != "ray") return fail(kExitInput, "run: --ray-address needs --executor ray");
        if (executor == "ray") {
            aamap::loadExperiment(configPath, overrides);  // a bad config fails here, before any cluster starts
            aamap::app::execRayExecutor(argc, argv, rayAddress);
        }
        const aamap::Experiment experiment = aamap::loadExperiment(configPath, overrides);
        const std::filesystem::path out =
            outDir.empty() ? std::filesystem::path("out") / std::filesystem::path(configPath).stem() : std::filesystem::path(outDir);
        aamap::RunOptions options;
        options.validation = validation;
        options.device = device;
        options.threads = threads;
        options.gitRevision = AAMAP_GIT_REVISION;
        options.plots = !noPlots;
        options.cacheDir = cacheDir;
        if (planOnly) {
            fmt::print("{}", aamap::planText(experiment, out, cacheDir));
            return 0;
        }
        if (listWork) {
            fmt::print("{}", aamap::app::workListJson(experiment, out, options, {configPath, overrides, threads, validation}));
            return 0;
        }
        if (!onlyKey.empty()) {
            aamap::computeExperimentItem(experiment, onlyKey, out, options);
            return 0;
        }
        if (experiment.sweptKeys.empty())
            spdlog::info("config {} (hash {}), output {}", configPath, experiment.variants.front().hash(), out.string());
        else
            spdlog::info("config {}: {} variants sweeping {}, output {}", configPath, experiment.variants.size(),
                         fmt::join(experiment.sweptKeys, ", "), out.string());
        stopCleanlyOnInterrupt(out);
        aamap::runSweptExperiment(experiment, out, options);
        return 0;
    } catch (const aamap::InputError& e) {
        return fail(kExitInput, e.what());
    } catch (const aamap::ValidationFailure& e) {
        return fail(kExitValidation, e.what());
    } catch (const aamap::EnvironmentError& e) {
        return fail(kExitEnvironment, e.what());
    } catch (const std::exception& e) {
        return fail(kExitEnvironment, e.what());
    }
}
