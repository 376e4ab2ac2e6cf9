#pragma once
// `aamap view`: the subcommand's options (CLI11) and its run. The viewer itself is viewer/.
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "viewer/viewer.h"

namespace aamap {

struct ViewCommand {
    CLI::App* command = nullptr;
    std::string config;
    std::vector<std::string> overrides;
    std::string camera;  // --camera: YAML as the config's camera key; replaces the config's view
    ViewerOptions options;
};

// Registers `view` on the app; the returned object receives the parsed values.
std::unique_ptr<ViewCommand> addViewCommand(CLI::App& app);
// Throws as runViewer() and loadConfig() do (InputError, EnvironmentError, ValidationFailure).
void runViewCommand(const ViewCommand& view);

}  // namespace aamap
