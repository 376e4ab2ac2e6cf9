#pragma once
// `aamap view CONFIG`: a window over the same Snapshot and tracer code as `aamap run`
// (docs/viewer.md). Built only when CMake finds GLFW 3; otherwise runViewer() says so.
#include <filesystem>
#include <string>

#include "eval/config.h"

namespace aamap {

struct ViewerOptions {
    std::string device;       // ContextOptions::device
    bool validation = false;  // any validation message fails the command (exit 3)
    int threads = -1;         // >= 0 overrides the config's `threads`
    std::string render;       // the config render to trace; "" = the aamap render with the most rpp
    std::string mode = "aamap";  // the view shown first (snapshot|laplacian|aamap|rpp|render|error)
    bool trace = false;       // start a selective trace of the first view right away
    int frames = 0;           // > 0: present that many frames, then quit (waiting for --trace first)
    std::filesystem::path screenshot;  // the last frame's content, read back from the swapchain
    int zoom = 0;             // window = render size x zoom; 0 = fit about 512 pixels
};

// The keys and mouse bindings, for --help and docs/viewer.md.
const char* viewerControls();
// False when the build had no GLFW (runViewer then throws EnvironmentError saying so).
bool viewerBuilt();
// Throws EnvironmentError (no GLFW build, no display, no Vulkan window support), InputError (config,
// scene) or ValidationFailure (eval/experiment.h).
void runViewer(const ExperimentConfig& config, const ViewerOptions& options);

}  // namespace aamap
