#pragma once
// The YAML experiment file (schema in docs/config.md). Parsing validates everything up front and
// reports problems as InputError(file, line, column, ...), so a run never fails halfway through
// on a typo. Doubles throughout so the canonical form prints the numbers the user wrote.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace aamap {

// Where a value came from, for errors raised after parsing (a view index past the end, say).
struct SourceLocation {
    std::filesystem::path file;  // the config file, or "--set key=value" for an override
    int line = 0, column = 0;    // 1-based; 0 when unknown
};

struct LightConfig {
    std::string type = "point";
    std::string name;
    std::array<double, 3> position{0, 0, 0};
    std::array<double, 3> intensity{0, 0, 0};  // W/sr per channel
    std::array<double, 3> normal{0, 0, 0};     // zero: isotropic; else a cosine lobe around it
};

struct ImageConfig {
    int width = 512, height = 512;  // the bounding box; the view's aspect ratio decides the fit
    double exposure = 1.0;          // PNG tone mapping and the snapshot's greyscale
};

struct SnapshotConfig {
    double scale = 1.5;
    int areaLightSamples = 5;
    int blurRadius = 1;
    double noiseFloor = 0.02;
    double gain = 1.0;
};

struct ShadingConfig {
    int areaLightSamples = 16;
};

struct RenderConfig {
    std::string name;      // unique, [A-Za-z0-9_-]+, used as the output file stem
    std::string strategy;  // "uniform" or "aamap"
    int rpp = 1;           // n*n rays per pixel at most
    int strata() const;    // n
};

struct ExperimentConfig {
    std::filesystem::path file;  // the config file ("" when parsed from a string without one)
    std::string scene;           // as written: "builtin:NAME" or a path relative to the config file
    std::optional<std::string> view;  // as written: a .vf path relative to the config file
    int viewIndex = 0;
    std::vector<LightConfig> lights;
    ImageConfig image;
    std::uint64_t seed = 1;
    int threads = 0;  // 0: all hardware threads
    SnapshotConfig snapshot;
    ShadingConfig shading;
    std::vector<RenderConfig> renders;

    // For errors found when the scene or view is loaded.
    SourceLocation sceneLocation, viewLocation, viewIndexLocation;

    // The scene spec for loadScene(): builtin names unchanged, paths resolved against the
    // config file's folder.
    std::string resolvedScene() const;
    std::optional<std::filesystem::path> resolvedView() const;

    // Every field with defaults filled in, keys in schema order, as JSON text (compact).
    std::string canonicalJson() const;
    // FNV-1a 64 of canonicalJson() without `threads` (which never changes an image), 16 hex digits.
    std::string hash() const;
};

// overrides: "key.path=value" strings (the --set options); value is parsed as YAML, list items
// are addressed by index ("renders.1.rpp=16"). Throws InputError.
ExperimentConfig loadConfig(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
ExperimentConfig parseConfig(const std::string& text, const std::filesystem::path& file,
                             const std::vector<std::string>& overrides = {});

}  // namespace aamap
