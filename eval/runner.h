#pragma once
// The experiment runner: expands nothing itself (the config already holds the concrete renders),
// adds the reference and 1-ray renders it needs, reuses every render already in OUTDIR/cache,
// traces the rest through a RenderBackend, then computes metrics and writes the report.
// The backend is an interface so that the runner (and its resumability) is tested without a GPU.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"
#include "core/log.h"
#include "core/pixel_facts.h"
#include "eval/config.h"
#include "eval/results.h"

namespace aamap {

struct SceneInfo {
    int width = 0, height = 0;  // render resolution (the view's aspect ratio inside image.*)
    std::string scene;          // the spec loaded
    std::string viewLabel;
    double loadSeconds = 0, bvhSeconds = 0;
    std::vector<std::string> warnings;  // what the scene lacks for a meaningful run (no lights, ...)
    // What the loaders warned about (file:line, approximations, missing materials), already in
    // the log: recorded for the report, not logged again.
    std::vector<std::string> loaderWarnings;
};

struct SnapshotOutput {
    ImageGrey aamap;      // render resolution
    ImageRGB snapshot;    // snapshot resolution; may be empty
    ImageGrey laplacian;  // may be empty
    // totalSeconds: one execution of the Snapshot graph for what the strategies consume (the
    // per-frame cost, charged to every aamap-driven render), readback included. setupSeconds: what
    // came before it once (pipelines, uploads, the driver's first-use work, debug-image read-back).
    double totalSeconds = 0, readbackSeconds = 0, setupSeconds = 0;
    std::vector<std::pair<std::string, double>> passesGpuMs;
    std::string device;
    std::vector<std::string> warnings;  // SnapshotResult::warnings: what the device made it change
};

struct TraceOutput {
    ImageRGB image;
    Image<std::uint16_t> primaryRays;
    ImageRGB halfDifference;  // TraceResult::halfDifference: empty unless the strategy splits its samples
    RayTotals rays;
    std::uint64_t nonFiniteSamples = 0;
    double seconds = 0;
    std::string blockSums;  // aamap-subsample: where its block sums came from, "gpu" or "cpu"
};

class RenderBackend {
public:
    virtual ~RenderBackend() = default;
    // Loads the scene and view and builds the BVH. Called at most once, and only when something
    // must be computed: a fully cached run needs neither the scene nor the GPU.
    virtual SceneInfo prepare() = 0;
    virtual SnapshotOutput snapshot() = 0;  // after prepare()
    // The render size, when it is known without loading the scene (before prepare()): a bad
    // reference image is then refused before the scene loads. nullopt: prepare() tells.
    virtual std::optional<std::pair<int, int>> renderSizeWithoutScene() const { return std::nullopt; }
    // aamap: the Snapshot's map for strategies that use it, else null. progress(done, total).
    virtual TraceOutput trace(const RenderConfig& render, const ImageGrey* aamap,
                              const std::function<void(int, int)>& progress) = 0;
    // What each pixel's sub-rays see (core/pixel_facts.h), at the render resolution; after
    // prepare(). A backend without a tracer has none: then no causes are reported.
    virtual bool hasPixelFacts() const { return false; }
    virtual PixelFacts pixelFacts() { return {}; }
};

struct RunnerOptions {
    std::string gitRevision = "unknown";
    bool plots = true;  // ANDed with config.report.plots
    // The render cache; empty: OUTDIR/cache. The variants of a swept experiment share one.
    std::filesystem::path cacheDir;
    // A sweep's time left over all its variants, their traces planned already (planWork); null:
    // the run plans and estimates its own.
    WorkEstimate* estimate = nullptr;
};

// Plans into `estimate` the traces a run of `config` still lacks in cacheDir (the oracle's
// renders, known only once the reference is, are planned by the run itself). Keys in `planned`
// are skipped, and the new ones added: variants of a sweep share renders.
void planWork(const ExperimentConfig& config, const std::filesystem::path& cacheDir, WorkEstimate& estimate,
              std::set<std::string>& planned);

namespace runner_detail {
class Runner;
}

// One run of an experiment in its four stages, each callable (and tested) alone, in this order:
//   plan      the renders it needs (listed, reference, 1-ray probe) with their cache keys; every input
//             file read and checked, the warnings that need no image; nothing traced or written;
//   execute   the Snapshot and every render, from the cache or traced (with timing.repeats, unless
//             the oracle's renders must join the same rounds); results.json after each;
//   evaluate  the reference, each render's error, map quality and causes, the oracle map and its
//             renders (timed with the others);
//   report    results.json, report.html, report.md and results.csv.
// A stage called out of order throws std::logic_error.
class ExperimentRun {
public:
    ExperimentRun(const ExperimentConfig& config, const std::filesystem::path& outDir, RenderBackend& backend,
                  const RunnerOptions& options);
    ~ExperimentRun();
    void plan();
    void execute();
    void evaluate();
    Results report();
    const Results& results() const;  // as the stages so far filled it

private:
    std::unique_ptr<runner_detail::Runner> runner_;
};

// The four stages in a row. Throws InputError, EnvironmentError, or whatever the backend throws.
// results.json is rewritten after every render; report.html, report.md and results.csv at the end.
Results runExperimentWith(const ExperimentConfig& config, const std::filesystem::path& outDir, RenderBackend& backend,
                          const RunnerOptions& options);

// A Snapshot or render the experiment needs and the cache lacks: what an executor that spreads
// the work over machines (tools/ray_executor.py) hands to one worker.
struct WorkItem {
    std::string kind;          // "snapshot" or "render"
    std::string key;           // its cache entry, OUTDIR/cache/KEY
    std::string name;          // the render's name ("snapshot" for the Snapshot)
    int threads = 0;           // tracer threads (0: all of the worker's)
    std::string needsSnapshot; // a render driven by the aamap: the Snapshot's key; else ""
    // timing.same_machine: the renders of one speedup (one rpp of one variant) share a group and
    // run on one worker; "" when free to go anywhere.
    std::string group;
};

// What runExperimentWith would compute: every missing item, the Snapshot first, each key once.
// threads >= 0 overrides the config's. Reads the cache only; loads no scene.
std::vector<WorkItem> missingWork(const ExperimentConfig& config, const std::filesystem::path& cacheDir, int threads);

// `aamap run --plan`: what a run of `config` would do, from the cache alone (nothing is loaded,
// traced or written; the cache folder is not even created).
struct PlannedRender {
    std::string name, key, strategy;
    int rpp = 1;
    bool cached = false;       // complete in the cache, timed runs included
    bool usesSnapshot = false;
    std::optional<double> seconds;  // cached: its median time; else estimated from the rate below
};
struct RunPlan {
    bool usesSnapshot = false, snapshotCached = false;
    std::string snapshotKey;
    std::vector<PlannedRender> renders;  // the listed renders, then the reference and the 1-ray probe
    int repeats = 1;
    // Seconds per ray budget unit (rpp x pixel) from the cached renders of this config in the same
    // shading mode; unknown without one.
    std::optional<double> secondsPerRayUnit;
    int pixels = 0;  // the image box's (the view's aspect may make the render smaller)
};
RunPlan planRun(const ExperimentConfig& config, const std::filesystem::path& cacheDir);

// Whether KEY is the Snapshot or a render of this config.
bool hasWorkItem(const ExperimentConfig& config, const std::string& key);

// Computes exactly the item KEY into cacheDir (its timed repeats included) and nothing else: no
// metrics, no report, no output folder. A render driven by the aamap needs the Snapshot's entry
// in cacheDir already. Throws InputError when KEY is not an item of this config.
void computeWorkItem(const ExperimentConfig& config, const std::string& key, RenderBackend& backend,
                     const RunnerOptions& options);

}  // namespace aamap
