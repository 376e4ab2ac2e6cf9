#include "app/view_command.h"

#include <cstdlib>

#include <fmt/format.h>

#include "core/error.h"
#include "eval/config.h"

namespace aamap {
namespace {

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

}  // namespace

std::unique_ptr<ViewCommand> addViewCommand(CLI::App& app) {
    auto view = std::make_unique<ViewCommand>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Open a window on a config: the Snapshot, the aamap and the selective render, live (GLFW + Vulkan)");
    view->command = cmd;
    ViewerOptions& o = view->options;
    o.device = env("AAMAP_DEVICE");
    const std::string v = env("AAMAP_VALIDATION");
    o.validation = v == "1" || v == "true" || v == "on" || v == "yes";
    cmd->add_option("CONFIG", view->config, "Experiment YAML file (as for 'aamap run')")->required();
    cmd->add_option("--set", view->overrides, "Override a config value: key.path=value (repeatable)")
        ->expected(1)
        ->allow_extra_args(false)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->type_name("KEY=VALUE");
    cmd->add_option("--camera", view->camera,
                    "Camera as YAML, the config's camera keys: '{position: [x, y, z], look_at: [x, y, z], fov: 45}'")
        ->type_name("YAML");
    cmd->add_option("--device", o.device, "Vulkan device: index or name substring (default: best GPU)")->type_name("NAME");
    cmd->add_flag("--validation", o.validation, "Enable the Vulkan validation layer; any message fails (exit 3)");
    cmd->add_option("--threads", o.threads, "Tracer threads (overrides the config; 0 = all)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--render", o.render, "The config render to trace (default: the aamap render with the most rays per pixel)")
        ->type_name("NAME");
    cmd->add_option("--mode", o.mode, "The view shown first")
        ->check(CLI::IsMember({"snapshot", "laplacian", "aamap", "rpp", "render", "error"}))
        ->capture_default_str();
    cmd->add_flag("--trace", o.trace, "Start a selective trace of the first view right away");
    cmd->add_option("--frames", o.frames, "Present N frames, then quit (after the --trace finishes)")
        ->check(CLI::PositiveNumber)
        ->type_name("N");
    cmd->add_option("--screenshot", o.screenshot, "Write the last frame's view as a PNG (read back from the GPU)")
        ->type_name("PNG");
    cmd->add_option("--zoom", o.zoom, "Window = render size x ZOOM (default: about 512 pixels)")->check(CLI::PositiveNumber);
    cmd->footer(fmt::format("{}\n\nNeeds a display (DISPLAY or WAYLAND_DISPLAY); headless: xvfb-run -a aamap view CONFIG.\n"
                            "{}See docs/viewer.md.",
                            viewerControls(),
                            viewerBuilt() ? "" : "This build has no GLFW: the command only says it is unavailable.\n"));
    return view;
}

void runViewCommand(const ViewCommand& view) {
    if (!view.options.screenshot.empty() && view.options.frames <= 0)
        throw InputError("--screenshot", 0, 0, "--screenshot needs --frames N (the screenshot is the last frame)");
    std::vector<std::string> overrides = view.overrides;
    if (!view.camera.empty()) {  // the config's camera, replacing its view file if it names one
        overrides.push_back("view=null");
        for (std::string& o : cameraOverrides(parseCameraOption(view.camera))) overrides.push_back(std::move(o));
    }
    const ExperimentConfig config = loadConfig(view.config, overrides);
    runViewer(config, view.options);
}

}  // namespace aamap
