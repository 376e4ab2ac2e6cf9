#pragma once
// `aamap snapshot SCENE [--view VF [--view-index N] | --camera YAML] [--lights FILE] [--explain] [--dot FILE]
// [-o OUTDIR]`: the Snapshot alone (no tracing), its images, and its compiled render graph.
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace aamap::app {

struct SnapshotOptions {
    std::string scene, view, camera, lights, dot, outDir = "out/snapshot";
    int viewIndex = 0;
    // Render size (bounding box for the view's aspect ratio); 0: the scene file's size, else 512.
    int width = 0, height = 0;
    float exposure = 1.0f;
    int shadowResolution = 256;
    bool noShadows = false;
    // The config's snapshot section (passes/snapshot_params.h): --set snapshot.KEY=V, and an option
    // --KEY per key generated from its declaration (the text as written, checked as --set is).
    std::vector<std::string> set;
    std::map<std::string, std::string> keys;  // key name -> value text of its generated option
    bool explain = false;
    std::string device;       // "" = AAMAP_DEVICE or the best GPU
    bool validation = false;  // or AAMAP_VALIDATION=1
};

// Adds the subcommand to `app`; the returned options are filled when it is parsed.
CLI::App* addSnapshotCommand(CLI::App& app, SnapshotOptions& options);

// Runs it. Throws InputError for bad input (scene, view, light file) and EnvironmentError for
// Vulkan failures; returns 3 when the validation layer reported messages, else 0.
int runSnapshotCommand(const SnapshotOptions& options, bool validation, const std::string& device);

}  // namespace aamap::app
