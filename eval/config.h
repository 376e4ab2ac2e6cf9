#pragma once
// The YAML experiment file (schema in docs/config.md). Parsing validates everything up front and
// reports problems as InputError(file, line, column, ...), so a run never fails halfway through
// on a typo. Doubles throughout so the canonical form prints the numbers the user wrote.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "passes/snapshot_params.h"
#include "scene/light_file.h"
#include "tracer/shading_params.h"
#include "tracer/strategy_params.h"

namespace aamap {

// Where a value came from, for errors raised after parsing (a view index past the end, say).
struct SourceLocation {
    std::filesystem::path file;  // the config file, or "--set key=value" for an override
    int line = 0, column = 0;    // 1-based; 0 when unknown
};

// One light of `light_file` or `lights` (schema: scene/light_file.h, docs/lights.md).
using LightConfig = LightSpec;

// The `image` section (eval/config_schema.cpp imageSchema()): the size and exposure, and the pixel
// filter keys, which are the tracer's PixelFilterSettings and declared with it.
struct ImageConfig {
    ImageConfig();  // imageSchema()'s defaults
    int width, height;  // the bounding box; the view's aspect ratio decides the fit
    double exposure;    // PNG tone mapping and the snapshot's greyscale
    // Pixel reconstruction filter of every traced image (tracer/pixel_filter.h).
    PixelFilterSettings filter;
    bool defaultFilter() const {  // the plain pixel box, which no cache key names
        return filter.type == PixelFilterType::Box && (filter.radius == 0.0f || filter.radius == 0.5f);
    }
};

// `camera`: a view written in the config instead of a .vf file (scene/framing.h, lookAtView).
struct CameraConfig {
    std::array<double, 3> position{0, 0, 0};
    std::array<double, 3> lookAt{0, 0, -1};
    std::array<double, 3> up{0, 1, 0};
    double fov = 45.0;  // degrees, the full horizontal angle; the vertical one follows the image
};

// The `snapshot` section is the passes' SnapshotSettings, declared with its schema in
// passes/snapshot_params.h.

// The `shading` section is the tracer's ShadingSettings, declared with its schema in
// tracer/shading_params.h.

// One concrete render, after sweep expansion (a renders[] entry with list values becomes the
// cartesian product of its lists).
struct RenderConfig {
    std::string name;      // unique, [A-Za-z0-9_-]+, used as the output file stem
    std::string series;    // table column and plot curve ("Space 8"); renders differing in rpp only share one
    std::string strategy;  // a strategyRegistry() name
    int rpp = 1;           // n*n rays per pixel at most
    // The strategy's parameters as the tracer takes them: schema order, typed, defaults filled in.
    StrategyParams params;
    std::optional<ShadingMode> shadingMode;  // unset: the experiment's shading.mode (the reference may differ)
    int strata() const;    // n
};

// What every render is compared with: traced n x n everywhere with the same shading (uniform),
// an EXR (file), or nothing (none).
enum class ReferenceType { Uniform, File, None };
const char* toString(ReferenceType type);  // reference.type's name (eval/config_sections.cpp declares them)

struct ReferenceConfig {
    ReferenceType type = ReferenceType::Uniform;
    int rpp = 0;                     // uniform: 0 = the largest rpp of the renders (resolved by the parser)
    std::optional<ShadingMode> mode;  // uniform: its own shading mode (unset: shading.mode); path = converged
    std::string path;                // file: linear RGB EXR, relative to the config file
    SourceLocation pathLocation;
    std::optional<std::filesystem::path> resolvedPath(const std::filesystem::path& configFile) const;
    // The mode the reference is traced in.
    ShadingMode modeOr(ShadingMode experiment) const { return mode.value_or(experiment); }
};

// The metrics, timing and report sections: every default is its schema's (eval/config_schema.cpp).
struct MetricsConfig {
    MetricsConfig();
    bool flip;             // LDR-FLIP of the displayed images
    bool flipHdr;          // HDR-FLIP of the linear radiance as well
    double flipThreshold;  // % pixels above it; also the "true aliasing" threshold of map quality
    double mseThreshold;   // per-pixel display-space squared error
    double ppd;            // FLIP viewing condition (pixels per degree)
    bool mapQuality;       // aamap recall/precision; adds a 1-ray uniform render
    bool causes;           // with mapQuality: why pixels are missed or wasted (pixel facts)
    bool oracle;           // with mapQuality: every aamap-driven render again on the oracle map
};

// How traces are timed: the machine drifts, so a trade is timed over several runs, interleaved
// across renders so that drift hits all of them alike. Images do not depend on it.
struct TimingConfig {
    TimingConfig();
    int repeats;      // timed runs of every trace; times_s.trace is their median
    bool interleave;  // round r times every render once before round r + 1
    // An executor over several machines (--executor ray) traces the renders of one rpp (a speedup's
    // numerator and denominator) on one worker. Ignored by a run on one machine.
    bool sameMachine;
};

struct ReportConfig {
    ReportConfig();
    bool plots;  // run tools/report_plots.py (skipped with a warning if Python is absent)
};

struct ExperimentConfig {
    std::filesystem::path file;  // the config file ("" when parsed from a string without one)
    std::string scene;           // as written: "builtin:NAME" or a path relative to the config file
    std::optional<std::string> view;  // as written: a .vf path relative to the config file
    int viewIndex = 0;
    std::optional<CameraConfig> camera;  // wins over the scene's views; exclusive with `view`
    std::optional<std::string> lightFile;  // as written: a light file relative to the config file
    std::vector<LightConfig> lights;       // the light file's lights, then the inline `lights` list
    ImageConfig image;
    std::uint64_t seed = 1;
    int threads = 0;  // 0: all hardware threads
    SnapshotSettings snapshot;
    ShadingSettings shading;  // the tracer's own struct, bound by the schema (tracer/shading_params.h)
    std::vector<RenderConfig> renders;
    ReferenceConfig reference;
    MetricsConfig metrics;
    ReportConfig report;
    TimingConfig timing;

    bool usesAamap() const;  // some render needs the Snapshot

    // The schema keys written in the config or by --set ("image.width", "shading.max_depth"):
    // where the config is silent, a Mitsuba scene file's own settings decide.
    std::set<std::string> written;
    bool given(const std::string& key) const { return written.contains(key); }
    bool sizeGiven() const { return given("image.width") || given("image.height"); }

    // For errors found when the scene or view is loaded.
    SourceLocation sceneLocation, viewLocation, viewIndexLocation, cameraLocation;

    // The scene spec for loadScene(): builtin names unchanged, paths resolved against the
    // config file's folder.
    std::string resolvedScene() const;
    std::optional<std::filesystem::path> resolvedView() const;
    std::optional<std::filesystem::path> resolvedLightFile() const;

    // Every field with defaults filled in, keys in schema order, as JSON text (compact).
    std::string canonicalJson() const;
    // What identifies the experiment: canonicalJson()'s content with the schema sections reduced to
    // the keys not at their default (so a key added later changes no hash) and without `threads`
    // (which never changes an image).
    std::string hashJson() const;
    std::string hash() const;  // FNV-1a 64 of hashJson(), 16 hex digits

};

// The cache key of one render: FNV-1a 64 of the canonical JSON of everything its image depends on
// (scene, view, lights, image, seed, shading, strategy, rpp, parameters, and the snapshot settings
// when the strategy uses the aamap) -- not its name, series, threads or the metrics.
std::string renderKey(const ExperimentConfig& config, const RenderConfig& render);
// What renderKey hashes, as an object ({format, scene, seed, shading, strategy, rpp, params, ...})
// and as the compact text that is hashed.
nlohmann::ordered_json renderKeyObject(const ExperimentConfig& config, const RenderConfig& render);
// A Mitsuba scene file brings its own render settings (integrator depths, film size and filter),
// which apply where the config is silent.
bool sceneDecidesRendering(const ExperimentConfig& config);
// The render's strategy parameters as typed values (an integer stays one): for records and reports.
nlohmann::ordered_json strategyParamsJson(const RenderConfig& render);
std::string renderKeyJson(const ExperimentConfig& config, const RenderConfig& render);
// The snapshot section with its defaults filled in, as in canonicalJson() and the keys.
nlohmann::ordered_json snapshotSettingsJson(const ExperimentConfig& config);
// The same for the Snapshot and its aamap.
std::string snapshotKey(const ExperimentConfig& config);
// Every key --set can reach, '#' standing for a list index ("renders.#.rpp").
std::vector<std::string> settableKeys();
std::string fnv1a64Hex(const std::string& text);

// The `snapshot` section from overrides alone ("snapshot.blur_radius=2", the --set options of
// `aamap snapshot`), read as `aamap run` reads its --set: the same checks and errors. Throws InputError.
SnapshotSettings snapshotFromOverrides(const std::vector<std::string>& overrides);

// The --camera option of `aamap snapshot` and `aamap view`: the config's camera mapping as YAML
// flow text ("{position: [0, 1, 5], look_at: [0, 1, 0], fov: 50}"). Throws InputError.
CameraConfig parseCameraOption(const std::string& text);
// The same camera as --set overrides ("camera.position=[0, 1, 5]", ...).
std::vector<std::string> cameraOverrides(const CameraConfig& camera);

// An experiment with its sweeps of settings outside the renders list expanded (eval/config_sweeps.h):
// one variant per point of the cartesian product, the first swept key varying slowest. Without
// such sweeps, one variant and no swept keys.
struct Experiment {
    std::vector<ExperimentConfig> variants;
    std::vector<std::string> sweptKeys;                 // "scene", "snapshot.blur_radius", ...
    std::vector<SourceLocation> sweptAt;                // where each swept list is written
    std::vector<std::vector<std::string>> sweptValues;  // per variant, the value of each swept key
    std::vector<std::string> folders;                   // per variant, a file-safe sub-folder name
};
inline constexpr std::size_t kMaxConfigVariants = 256;

Experiment loadExperiment(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
Experiment parseExperiment(const std::string& text, const std::filesystem::path& file,
                           const std::vector<std::string>& overrides = {});

// overrides: "key.path=value" strings (the --set options); value is parsed as YAML, list items
// are addressed by index ("renders.1.rpp=16"). Throws InputError, also for a sweep outside the
// renders (the commands that take one experiment; `aamap run` takes them all: loadExperiment).
ExperimentConfig loadConfig(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
ExperimentConfig parseConfig(const std::string& text, const std::filesystem::path& file,
                             const std::vector<std::string>& overrides = {});

}  // namespace aamap
