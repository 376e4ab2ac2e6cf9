#pragma once
// `aamap diff REFERENCE TEST [--heatmap OUT.png] [--exposure E] [--threshold T] [--ppd P]
// [--mse-threshold M] [--json]`: the experiment's image metrics for any two images (EXR, linear;
// or PNG, sRGB), as pbrt-v4's `imgtool diff` does for its own.
#include <string>

#include <CLI/CLI.hpp>

namespace aamap::app {

struct DiffOptions {
    std::string reference, test, heatmap;
    float exposure = 1.0f;
    float threshold = 0.1f;       // FLIP above it: a pixel in error
    float ppd = 0.0f;             // 0: FLIP's default (67.02)
    double mseThreshold = 0.0;    // 0: the default (2/255)^2
    bool json = false;
};

CLI::App* addDiffCommand(CLI::App& app, DiffOptions& options);

// Prints the figures on stdout (a table, or one JSON object). Throws InputError for an unreadable
// image or two images of different sizes (exit 2), EnvironmentError when the heatmap cannot be
// written.
void runDiffCommand(const DiffOptions& options);

}  // namespace aamap::app
