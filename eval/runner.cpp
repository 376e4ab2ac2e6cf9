#include "eval/runner.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "core/image_io.h"
#include "core/log.h"
#include "eval/cache_records.h"
#include "eval/evaluate.h"
#include "eval/render_cache.h"
#include "eval/report.h"
#include "eval/strategies.h"
#include "eval/timing_machines.h"

namespace aamap {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// The runner's parts; ExperimentRun (eval/runner.h) holds a Runner.
namespace runner_detail {

// A render the experiment needs: a listed one, the reference or the 1-ray probe.
struct Job {
    RenderConfig render;
    std::string key;
    // The map an aamap-driven render reads: null for the Snapshot's, else the oracle's (and the
    // digest of its pixels, which its key adds).
    const ImageGrey* map = nullptr;
    std::string mapDigest;
};

// What a job's key hashes: the render's settings, and the map when it is not the Snapshot's.
nlohmann::ordered_json keyObject(const ExperimentConfig& c, const Job& job) {
    nlohmann::ordered_json j = renderKeyObject(c, job.render);
    if (job.map != nullptr) j["oracle_map"] = job.mapDigest;
    return j;
}

bool usesAamap(const RenderConfig& render) {
    const StrategyDescriptor* info = findStrategy(render.strategy);
    return info != nullptr && info->usesAamap;
}

// Every render an experiment needs, with the order and names run() reports them under.
struct JobList {
    std::vector<Job> jobs;  // the listed renders, then the reference and the 1-ray probe
    std::size_t listed = 0;
    std::optional<Job> reference, oneRay;
    bool mapQuality = false;
};

JobList jobsOf(const ExperimentConfig& c) {
    JobList list;
    for (const RenderConfig& r : c.renders) list.jobs.push_back({r, renderKey(c, r)});
    list.listed = list.jobs.size();
    if (c.reference.type == ReferenceType::Uniform) {
        RenderConfig r{"reference", "reference", baselineStrategyName(), c.reference.rpp, {}, c.reference.mode};
        list.reference = Job{r, renderKey(c, r)};
        list.jobs.push_back(*list.reference);
    }
    list.mapQuality = c.metrics.mapQuality && c.usesAamap() && c.reference.type != ReferenceType::None;
    if (list.mapQuality) {  // true aliasing is what a 1-ray image gets wrong
        RenderConfig r{"one_ray", "one_ray", baselineStrategyName(), 1, {}, std::nullopt};
        list.oneRay = Job{r, renderKey(c, r)};
        list.jobs.push_back(*list.oneRay);
    }
    return list;
}

struct Traced {
    RenderRecord record;  // as cached (name of whichever job computed it first)
    ImageRGB image;
    Image<std::uint16_t> rays;
    ImageRGB halfDifference;  // empty unless the strategy splits its samples (a uniform render)
};

ImageGrey raysToGrey(const Image<std::uint16_t>& rays) {
    ImageGrey g(rays.width(), rays.height());
    std::transform(rays.pixels().begin(), rays.pixels().end(), g.pixels().begin(),
                   [](std::uint16_t v) { return static_cast<float>(v); });
    return g;
}

Image<std::uint16_t> greyToRays(const ImageGrey& g) {
    Image<std::uint16_t> rays(g.width(), g.height());
    std::transform(g.pixels().begin(), g.pixels().end(), rays.pixels().begin(),
                   [](float v) { return static_cast<std::uint16_t>(std::clamp(v, 0.0f, 65535.0f) + 0.5f); });
    return rays;
}

class Runner {
public:
    Runner(const ExperimentConfig& config, const fs::path& outDir, RenderBackend& backend, const RunnerOptions& options)
        : c_(config), out_(outDir), backend_(backend), options_(options), cache_(options.cacheDir.empty() ? outDir / "cache" : options.cacheDir, outDir),
          machine_(currentMachine()) {}

    // The run's stages, in order (ExperimentRun in eval/runner.h).
    void plan();
    void execute();
    void evaluate();
    Results report();
    const Results& results() const { return results_; }
    void computeOnly(const std::string& key);

private:
    // The scene is loaded on first need only: a run whose work is all cached never loads it.
    const SceneInfo& scene() {
        if (!scene_) {
            scene_ = backend_.prepare();
            warnings_.insert(warnings_.end(), scene_->loaderWarnings.begin(), scene_->loaderWarnings.end());
            for (const std::string& w : scene_->warnings) warn(w);
        }
        return *scene_;
    }
    void warn(const std::string& message) {
        spdlog::warn("{}", message);
        warnings_.push_back(message);
    }
    void loadOrRenderSnapshot(bool writeOutputs = true);
    const ImageGrey* mapFor(const Job& job) const {
        return usesAamap(job.render) ? (job.map != nullptr ? job.map : &*aamap_) : nullptr;
    }
    void traceOracle(Results& results, const std::vector<Job>& jobs, std::size_t listed, const ImageRGB& reference,
                     const ImageRGB& oneRay);
    PixelFacts loadOrComputeFacts();
    const Traced& loadOrTrace(const Job& job, int index, int count);
    RenderRecord recordFor(const Job& job, const Traced& t, bool cached) const;
    void repeatTraces(const std::vector<Job>& jobs);
    void planTraces(const std::vector<Job>& jobs);
    void traceFinished(const Job& job, double seconds);
    ImageRGB loadFileReference(const std::vector<Job>& jobs);
    void checkReference(const ImageRGB& reference);
    void checkConvergence(ReferenceInfo& info, const Traced& reference);
    void addAntialiasingShares(Results& results, const std::vector<Job>& jobs, std::size_t listed,
                               const ImageRGB& reference) const;
    void writeNamedOutputs(const std::string& name, const Traced& t, int rpp, std::vector<std::string>& outputs) const;

    const ExperimentConfig& c_;
    fs::path out_;
    RenderBackend& backend_;
    RunnerOptions options_;
    RenderCache cache_;
    MachineInfo machine_;
    std::optional<SceneInfo> scene_;
    std::optional<ImageGrey> aamap_;
    std::optional<ImageGrey> oracleMap_;
    std::optional<SnapshotRecord> snapshotRecord_;
    std::map<std::string, Traced> traced_;  // by key
    std::map<std::string, bool> reused_;    // by key: came from the cache
    int tracedNow_ = 0;
    WorkEstimate ownEstimate_;  // the whole run's time left, logged after each trace
    // A sweep's estimate over all its variants (RunnerOptions::estimate), else ownEstimate_.
    WorkEstimate& estimate() { return options_.estimate != nullptr ? *options_.estimate : ownEstimate_; }
    std::vector<std::string> warnings_;  // for the top of the report

    // The stages' shared state: what plan() decided and read, the results as they fill.
    enum class Stage { None, Planned, Executed, Evaluated, Reported };
    void require(Stage before, const char* stage) const;
    void copyRepeatedTimes();
    Stage stage_ = Stage::None;
    JobList list_;
    std::optional<ImageRGB> fileReference_;
    bool oracleLater_ = false;
    Results results_;
};

void Runner::loadOrRenderSnapshot(bool writeOutputs) {
    const std::string key = snapshotKey(c_);
    if (cache_.has(key)) {
        try {  // damaged by hand or by a full disk: rendered again
            snapshotRecord_ = readSnapshotRecord(cache_.record(key));
            snapshotRecord_->cached = true;
            aamap_ = readExrGrey(cache_.entry(key) / "aamap.exr");
            spdlog::info("snapshot: reused from {}", cache_.entry(key).string());
        } catch (const std::exception& e) {
            spdlog::warn("snapshot: cache entry {} is unreadable ({}); rendering it again", cache_.entry(key).string(),
                         e.what());
            snapshotRecord_.reset();
        }
    }
    if (!snapshotRecord_) {
        const SceneInfo& s = scene();
        spdlog::info("snapshot: rendering (cache key {})", key);
        SnapshotOutput snap = backend_.snapshot();
        for (const std::string& w : snap.warnings) warn(w);
        SnapshotRecord record;
        record.key = key;
        record.width = s.width;
        record.height = s.height;
        record.totalSeconds = snap.totalSeconds;
        record.readbackSeconds = snap.readbackSeconds;
        record.setupSeconds = snap.setupSeconds;
        record.passesGpuMs = snap.passesGpuMs;
        record.vulkanDevice = snap.device;
        record.machine = machine_;
        record.gitRevision = options_.gitRevision;
        const float exposure = static_cast<float>(c_.image.exposure);
        cache_.commit(key, [&](const fs::path& dir) {
            writeExr(dir / "aamap.exr", snap.aamap);
            if (!snap.snapshot.empty()) writePng(dir / "snapshot.png", toneMap(snap.snapshot, exposure));
            if (!snap.laplacian.empty()) writePng(dir / "laplacian.png", quantise(snap.laplacian));
            writeRecord(dir / "record.json", toJson(record));
        });
        snapshotRecord_ = record;
        aamap_ = readExrGrey(cache_.entry(key) / "aamap.exr");  // as a later run reads it
    }
    if (!writeOutputs) return;
    for (const char* f : {"snapshot.png", "laplacian.png", "aamap.exr"})
        if (fs::exists(cache_.entry(key) / f)) copyFileAtomically(cache_.entry(key) / f, out_ / f);
    writePng(out_ / "aamap.png", quantise(*aamap_));
    const auto flagged = std::count_if(aamap_->pixels().begin(), aamap_->pixels().end(), [](float v) { return v > 0; });
    spdlog::info("aamap flags {:.1f}% of pixels", 100.0 * static_cast<double>(flagged) /
                                                     static_cast<double>(std::max<std::size_t>(1, aamap_->size())));
}

// The pixel facts depend on the scene, the view and the image size; the key of a 1-ray render
// covers them (and more, which only costs a recomputation), under a prefix of its own.
PixelFacts Runner::loadOrComputeFacts() {
    RenderConfig probe{"pixel_facts", "pixel_facts", baselineStrategyName(), 1, {}, std::nullopt};
    const std::string key = "facts-" + renderKey(c_, probe);
    if (cache_.has(key)) {
        try {
            return greyToRays(readExrGrey(cache_.entry(key) / "facts.exr"));
        } catch (const std::exception& e) {
            spdlog::warn("pixel facts in {} are unreadable ({}); computing them again", cache_.entry(key).string(), e.what());
        }
    }
    scene();
    spdlog::info("pixel facts: tracing {} sub-rays per pixel", pixel_fact::kGrid * pixel_fact::kGrid);
    const auto start = std::chrono::steady_clock::now();
    PixelFacts facts = backend_.pixelFacts();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    cache_.commit(key, [&](const fs::path& dir) {
        writeExr(dir / "facts.exr", raysToGrey(facts));
        writeRecord(dir / "record.json", toJson(PixelFactsRecord{key, seconds}));
    });
    spdlog::info("pixel facts: {:.2f} s", seconds);
    return facts;
}

const Traced& Runner::loadOrTrace(const Job& job, int index, int count) {
    if (auto it = traced_.find(job.key); it != traced_.end()) return it->second;
    Traced t;
    const fs::path entry = cache_.entry(job.key);
    if (cache_.has(job.key)) {
        try {
            t.record = readCachedRender(cache_.record(job.key)).record;
            t.image = readExr(entry / "image.exr");
            t.rays = greyToRays(readExrGrey(entry / "rpp.exr"));
            if (fs::is_regular_file(entry / "halves.exr")) t.halfDifference = readExr(entry / "halves.exr");
            spdlog::info("[job {}/{}] {}: reused (cache {})", index, count, job.render.name, job.key);
            reused_[job.key] = true;
            return traced_.emplace(job.key, std::move(t)).first->second;
        } catch (const std::exception& e) {  // damaged by hand or by a full disk: trace it again
            spdlog::warn("{}: cache entry {} is unreadable ({}); tracing it again", job.render.name, entry.string(),
                         e.what());
            t = Traced{};
        }
    }
    const SceneInfo& s = scene();
    Progress progress(fmt::format("[job {}/{}] trace {}", index, count, job.render.name));
    TraceOutput out = backend_.trace(job.render, mapFor(job),
                                     [&progress](int done, int total) { progress.update(done, total); });
    progress.finish();
    traceFinished(job, out.seconds);

    RenderRecord& r = t.record;
    r.name = job.render.name;
    r.series = job.render.series;
    r.key = job.key;
    r.scene = s.scene;
    r.view = s.viewLabel;
    r.width = out.image.width();
    r.height = out.image.height();
    r.strategy = job.render.strategy;
    const Json renderConfig = keyObject(c_, job);  // what the key hashes
    r.parameters = {{"rpp", job.render.rpp}, {"strata", job.render.strata()}, {"seed", c_.seed},
                    {"shading_area_light_samples", c_.shading.areaLightSamples},
                    {"shading", renderConfig["shading"]}};
    const Json params = strategyParamsJson(job.render);  // items() must not outlive it
    for (const auto& [k, v] : params.items()) r.parameters[k] = v;
    if (!out.blockSums.empty()) r.parameters["block_sums"] = out.blockSums;
    r.maxRaysPerPixel = job.render.rpp;
    r.times.load = s.loadSeconds;
    r.times.bvhBuild = s.bvhSeconds;
    r.times.trace = out.seconds;
    r.times.traceRuns = {out.seconds};
    if (job.map != nullptr) {
        r.parameters["map"] = "oracle";  // given, not computed: no Snapshot cost
    } else if (usesAamap(job.render)) {
        const SnapshotRecord& snapshot = *snapshotRecord_;
        r.parameters["snapshot"] = snapshotSettingsJson(c_);
        r.parameters["snapshot_key"] = snapshot.key;
        r.times.snapshotTotal = snapshot.totalSeconds;
        r.times.readback = snapshot.readbackSeconds;
        r.times.snapshotSetup = snapshot.setupSeconds;
        r.times.snapshotPassesGpuMs = snapshot.passesGpuMs;
        r.vulkanDevice = snapshot.vulkanDevice;
    }
    // readback is part of snapshot_total, so it is not added again
    r.times.total = r.times.load + r.times.bvhBuild + r.times.snapshotSetup + r.times.snapshotTotal + r.times.trace;
    r.rays = out.rays;
    const double sum = std::accumulate(out.primaryRays.pixels().begin(), out.primaryRays.pixels().end(), 0.0);
    r.meanPrimaryRpp = sum / static_cast<double>(std::max<std::size_t>(1, out.primaryRays.size()));
    r.nonFiniteSamples = out.nonFiniteSamples;
    r.gitRevision = options_.gitRevision;
    r.configHash = c_.hash();
    r.machine = machine_;
    if (out.nonFiniteSamples > 0) spdlog::warn("{}: {} non-finite samples dropped", r.name, out.nonFiniteSamples);
    spdlog::info("{}: {:.2f} s, {:.2f} primary rays/pixel, {} rays in all", r.name, out.seconds, r.meanPrimaryRpp,
                 r.rays.total());

    const Json record = toJson(CachedRender{r, renderConfig});
    cache_.commit(job.key, [&](const fs::path& dir) {
        writeExr(dir / "image.exr", out.image);
        writeExr(dir / "rpp.exr", raysToGrey(out.primaryRays));
        if (!out.halfDifference.empty()) writeExr(dir / "halves.exr", out.halfDifference);
        writeRecord(dir / "record.json", record);  // last: marks the entry complete
    });
    t.image = std::move(out.image);
    t.rays = std::move(out.primaryRays);
    t.halfDifference = std::move(out.halfDifference);
    reused_[job.key] = false;
    ++tracedNow_;
    return traced_.emplace(job.key, std::move(t)).first->second;
}

// A trace's size for the run's time left: its ray budget per pixel (every render has the same
// pixel count). Adaptive renders trace fewer rays than their budget; the measured rate absorbs
// the mix once they have run.
double traceUnits(const Job& job) { return std::max(1, job.render.rpp); }

// Plans into `estimate` the timed traces `jobs` still lack in the cache (keys in `seen` once).
void planMissingTraces(const ExperimentConfig& c, const RenderCache& cache, const std::vector<Job>& jobs,
                       WorkEstimate& estimate, std::set<std::string>& seen) {
    for (const Job& job : jobs) {
        if (!seen.insert(job.key).second) continue;
        int runs = 0;
        if (cache.has(job.key)) {
            try {
                runs = std::max<int>(1, static_cast<int>(readCachedRender(cache.record(job.key)).record.times.traceRuns.size()));
            } catch (const std::exception&) {
                runs = 0;  // unreadable: loadOrTrace traces it again
            }
        }
        const int missing = std::max(0, std::max(1, c.timing.repeats) - runs);
        if (missing > 0) estimate.plan(missing * traceUnits(job), missing);
    }
}

// Counts the traces the run will do: every job missing from the cache once, plus the timed runs
// timing.repeats asks for that its record does not have yet.
void Runner::planTraces(const std::vector<Job>& jobs) {
    std::set<std::string> seen;
    planMissingTraces(c_, cache_, jobs, estimate(), seen);
}

void Runner::traceFinished(const Job& job, double seconds) {
    estimate().finished(traceUnits(job), seconds);
    spdlog::info("{}", estimate().text());
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// timing.repeats: every job traces again until it has `repeats` timed runs (a cached record keeps
// its runs and gets only those it lacks). Interleaved, round r times every job once before round
// r + 1 starts, so the machine's drift hits all renders alike. The image of each run must equal
// the first bit for bit (images depend on the seed only); times_s.trace becomes the median.
void Runner::repeatTraces(const std::vector<Job>& jobs) {
    const int repeats = c_.timing.repeats;
    if (repeats <= 1) return;
    std::vector<const Job*> unique;  // one job per key, in the order they were traced
    for (const Job& job : jobs)
        if (std::none_of(unique.begin(), unique.end(), [&](const Job* u) { return u->key == job.key; }))
            unique.push_back(&job);
    std::vector<std::string> changed;
    const auto runOnce = [&](const Job& job) {
        Traced& t = traced_.at(job.key);
        scene();
        Progress progress(fmt::format("[run {}/{}] trace {}", t.record.times.traceRuns.size() + 1, repeats,
                                      job.render.name));
        TraceOutput out = backend_.trace(job.render, mapFor(job),
                                         [&progress](int done, int total) { progress.update(done, total); });
        progress.finish();
        traceFinished(job, out.seconds);
        if (out.image.pixels() != t.image.pixels())
            warn(fmt::format("{}: a repeated trace gave a different image (the tracer should be deterministic)",
                             job.render.name));
        t.record.times.traceRuns.push_back(out.seconds);
        if (std::find(changed.begin(), changed.end(), job.key) == changed.end()) changed.push_back(job.key);
    };
    const auto runs = [&](const Job& job) { return static_cast<int>(traced_.at(job.key).record.times.traceRuns.size()); };
    if (c_.timing.interleave) {
        for (int round = 2; round <= repeats; ++round)
            for (const Job* job : unique)
                if (runs(*job) < round) runOnce(*job);
    } else {
        for (const Job* job : unique)
            while (runs(*job) < repeats) runOnce(*job);
    }
    for (const std::string& key : changed) {  // the cache keeps every run, for the next rerun
        StageTimes& times = traced_.at(key).record.times;
        times.trace = median(times.traceRuns);
        times.total = times.load + times.bvhBuild + times.snapshotSetup + times.snapshotTotal + times.trace;
        CachedRender entry = readCachedRender(cache_.record(key));
        entry.record.times = times;
        writeRecord(cache_.record(key), toJson(entry));
    }
}

// reference.type file: read and checked against the render size before anything is traced.
ImageRGB Runner::loadFileReference(const std::vector<Job>& jobs) {
    const fs::path path = *c_.reference.resolvedPath(c_.file);
    const SourceLocation& at = c_.reference.pathLocation;
    ImageRGB reference;
    try {
        reference = readExr(path);
    } catch (const InputError& e) {
        throw InputError(at.file, at.line, at.column, fmt::format("reference '{}': {}", c_.reference.path, e.what()));
    }
    // The render size needs the scene's view, unless every image is cached already (then the
    // cached image says it and the scene stays unloaded).
    const bool allCached = std::all_of(jobs.begin(), jobs.end(), [&](const Job& j) { return cache_.has(j.key); }) &&
                           (!c_.usesAamap() || cache_.has(snapshotKey(c_)));
    int width = 0, height = 0;
    if (allCached) {
        const ImageRGB& first = loadOrTrace(jobs.front(), 1, static_cast<int>(jobs.size())).image;
        width = first.width();
        height = first.height();
    } else if (const auto size = backend_.renderSizeWithoutScene()) {
        std::tie(width, height) = *size;  // refused before a long scene load, if it must be
    } else {
        width = scene().width;
        height = scene().height;
    }
    if (reference.width() != width || reference.height() != height)
        throw InputError(at.file, at.line, at.column,
                         fmt::format("reference '{}' is {}x{}, the renders are {}x{}", c_.reference.path,
                                     reference.width(), reference.height(), width, height));
    return reference;
}

// With a ground-truth reference (another renderer's image, or another shading mode), a render's
// error mixes the shading mode's bias with the antialiasing still missing. The most-sampled
// uniform render (the shading floor) carries the bias alone; every other render is also measured
// against it, which is its antialiasing share.
void Runner::addAntialiasingShares(Results& results, const std::vector<Job>& jobs, std::size_t listed,
                                   const ImageRGB& reference) const {
    const bool groundTruth =
        c_.reference.type == ReferenceType::File || c_.reference.modeOr(c_.shading.mode) != c_.shading.mode;
    if (!groundTruth) return;
    std::optional<std::size_t> floor;
    for (std::size_t i = 0; i < listed; ++i)
        if (jobs[i].render.strategy == baselineStrategyName() && (!floor || jobs[i].render.rpp > jobs[*floor].render.rpp)) floor = i;
    if (!floor) return;
    const ImageRGB& floorImage = traced_.at(jobs[*floor].key).image;
    if (floorImage.width() != reference.width() || floorImage.height() != reference.height()) return;
    const std::string& floorName = results.renders[*floor].name;
    results.referenceInfo.shadingFloor = floorName;
    for (std::size_t i = 0; i < listed; ++i)
        if (i != *floor)
            results.renders[i].metrics["antialiasing"] =
                evaluateAgainstRender(floorName, floorImage, traced_.at(jobs[i].key).image, c_.metrics,
                                      static_cast<float>(c_.image.exposure));
}

// A reference that shows nothing makes every error figure meaningless: say so at the top.
void Runner::checkReference(const ImageRGB& reference) {
    const bool black = std::all_of(reference.pixels().begin(), reference.pixels().end(), [](const glm::vec3& p) {
        return !(p.r > 0.0f) && !(p.g > 0.0f) && !(p.b > 0.0f);
    });
    if (black) warn("the reference image is black everywhere: the error figures compare black images");
}

// A traced reference's own noise (and antialiasing left) is a floor under every error figure
// measured against it: estimated from its two half images, and a warning when it is not converged.
void Runner::checkConvergence(ReferenceInfo& info, const Traced& reference) {
    if (reference.halfDifference.empty() || reference.halfDifference.width() != reference.image.width() ||
        reference.halfDifference.height() != reference.image.height())
        return;  // one ray per pixel, or an entry cached without its halves
    const int rpp = info.rpp.value_or(c_.reference.rpp);
    info.noise = estimateReferenceNoise(reference.image, reference.halfDifference, rpp, c_.metrics,
                                        static_cast<float>(c_.image.exposure));
    const Json& n = *info.noise;
    const double floor = n["floor_pct"].get<double>();
    spdlog::info("reference noise floor: {}% of pixels in error from the reference's own noise", readableNumber(floor));
    if (!n["noisy"].get<bool>()) return;
    const std::string advice = n["suggested_rpp"].is_number()
                                   ? fmt::format("reference.rpp: {} would bring it under {}%", n["suggested_rpp"].get<int>(),
                                                 readableNumber(kConvergedFloorPercent))
                                   : fmt::format("even {} rays per pixel would not bring it under {}%: use a converged "
                                                 "reference image (reference.type: file)",
                                                 kMaxSuggestedRpp, readableNumber(kConvergedFloorPercent));
    warn(fmt::format("the reference ({} rpp, {} shading) is noisy: its own noise alone puts {}% of pixels above the "
                     "error threshold, so the error figures measure the reference, not the renders (the report leaves "
                     "the error pixels out); {}",
                     rpp, info.mode, readableNumber(floor), advice));
}

// metrics.oracle: the map the reference itself asks for (eval/evaluate.h oracleMap), and every
// aamap-driven render traced again on it. The oracle says where rays are needed, not how many:
// its pixels get the strategy's full budget, as a map value of 1 does.
void Runner::traceOracle(Results& results, const std::vector<Job>& jobs, std::size_t listed, const ImageRGB& reference,
                         const ImageRGB& oneRay) {
    OracleMap oracle = oracleMap(oneRay, reference, c_.metrics, static_cast<float>(c_.image.exposure));
    OracleResults& summary = results.oracle.emplace();
    summary.rounds = oracle.rounds;
    summary.residualErrorPercent = oracle.residualErrorPercent;
    oracleMap_ = std::move(oracle.map);
    const auto& px = oracleMap_->pixels();
    const std::string digest = fnv1a64Hex(std::string(reinterpret_cast<const char*>(px.data()), px.size() * sizeof(float)));
    const auto flagged = std::count(px.begin(), px.end(), 1.0f);
    summary.flaggedFraction = static_cast<double>(flagged) / static_cast<double>(std::max<std::size_t>(1, px.size()));
    writePng(out_ / "oracle.png", quantise(*oracleMap_));

    std::vector<Job> oracleJobs;
    std::vector<std::string> mapRenders;
    for (std::size_t i = 0; i < listed; ++i) {
        if (!usesAamap(jobs[i].render)) continue;
        Job o{jobs[i].render, "", &*oracleMap_, digest};
        o.render.name = "oracle_" + jobs[i].render.name;
        const std::string keyJson = keyObject(c_, o).dump();
        o.key = "oracle-" + fnv1a64Hex(keyJson);
        spdlog::debug("{}: cache key {} from {}", o.render.name, o.key, keyJson);
        oracleJobs.push_back(std::move(o));
        mapRenders.push_back(jobs[i].render.name);
    }
    spdlog::info("oracle map: flags {:.1f}% of pixels after {} round(s); {} render(s) on it",
                 100.0 * summary.flaggedFraction, summary.rounds, oracleJobs.size());
    planTraces(oracleJobs);
    const float exposure = static_cast<float>(c_.image.exposure);
    for (std::size_t k = 0; k < oracleJobs.size(); ++k) {
        const Job& job = oracleJobs[k];
        const Traced& t = loadOrTrace(job, static_cast<int>(k) + 1, static_cast<int>(oracleJobs.size()));
        RenderRecord rec = recordFor(job, t, reused_[job.key]);
        writeNamedOutputs(job.render.name, t, job.render.rpp, rec.outputs);
        rec.metrics = evaluateRender(reference, t.image, c_.metrics, exposure, out_, rec.name, rec.outputs);
        results.oracle->runs.push_back({mapRenders[k], std::move(rec)});
        writeResults(out_ / "results.json", results);
    }
    // Every render's repeated runs in one set of rounds: the renders, then the oracle's.
    std::vector<Job> all = jobs;
    all.insert(all.end(), oracleJobs.begin(), oracleJobs.end());
    repeatTraces(all);
    for (std::size_t k = 0; k < oracleJobs.size(); ++k) results.oracle->runs[k].record.times = traced_.at(oracleJobs[k].key).record.times;
}

RenderRecord Runner::recordFor(const Job& job, const Traced& t, bool cached) const {
    RenderRecord r = t.record;
    r.name = job.render.name;  // a cached entry may have been made under another name
    r.series = job.render.series;
    r.cached = cached;
    r.configHash = c_.hash();
    return r;
}

void Runner::writeNamedOutputs(const std::string& name, const Traced& t, int rpp, std::vector<std::string>& outputs) const {
    copyFileAtomically(cache_.entry(t.record.key) / "image.exr", out_ / (name + ".exr"));
    writePng(out_ / (name + ".png"), toneMap(t.image, static_cast<float>(c_.image.exposure)));
    writePng(out_ / (name + ".rpp.png"), falseColour(t.rays, rpp));
    outputs = {name + ".exr", name + ".png", name + ".rpp.png"};
    const StrategyDescriptor* strategy = findStrategy(t.record.strategy);
    if (strategy != nullptr && strategy->marksTraced) {
        // The paper's Figure 5: traced pixels white, interpolated ones (no primary ray) black.
        ImageGrey mask(t.rays.width(), t.rays.height());
        std::transform(t.rays.pixels().begin(), t.rays.pixels().end(), mask.pixels().begin(),
                       [](std::uint16_t v) { return v > 0 ? 1.0f : 0.0f; });
        writePng(out_ / (name + ".traced.png"), quantise(mask));
        outputs.push_back(name + ".traced.png");
    }
}

void Runner::plan() {
    results_ = Results{};
    results_.gitRevision = options_.gitRevision;
    results_.configHash = c_.hash();
    results_.configJson = c_.canonicalJson();
    list_ = jobsOf(c_);
    const std::vector<Job>& jobs = list_.jobs;

    // Every input file is read before any work, so a bad one leaves the output folder as it was.
    fileReference_.reset();
    if (c_.reference.type == ReferenceType::File) fileReference_ = loadFileReference(jobs);
    if (list_.reference)
        for (const Job& job : jobs)
            if (job.render.rpp > c_.reference.rpp) {
                warn(fmt::format("the reference traces {} rays per pixel, fewer than render '{}' ({}): its error is "
                                 "measured against a noisier image",
                                 c_.reference.rpp, job.render.name, job.render.rpp));
                break;
            }
    // Cache mode with B bounces renders paths of up to B + 2 segments (camera, B diffuse bounces,
    // the light): against a path reference of another length the difference is not the cache's.
    if (list_.reference && c_.shading.mode == ShadingMode::Cache && c_.reference.mode == ShadingMode::Path &&
        c_.shading.cache.bounces > 0 &&
        c_.shading.maxDepth != c_.shading.cache.bounces + 2)
        warn(fmt::format("shading.cache.bounces {} renders paths of up to {} segments, the path-traced reference up to "
                         "shading.max_depth {}: set shading.max_depth: {} to measure the cache against the same light "
                         "transport",
                         c_.shading.cache.bounces, c_.shading.cache.bounces + 2, c_.shading.maxDepth,
                         c_.shading.cache.bounces + 2));
    // With the oracle, the repeated runs wait for its renders, so that they are timed in the same
    // rounds as the renders they are compared with (the machine's drift hits them alike).
    oracleLater_ = list_.mapQuality && c_.metrics.oracle && (list_.reference || fileReference_);
    stage_ = Stage::Planned;
}

void Runner::copyRepeatedTimes() {
    // The records were taken before the repeated runs.
    if (c_.timing.repeats <= 1) return;
    for (std::size_t i = 0; i < list_.listed; ++i) results_.renders[i].times = traced_.at(list_.jobs[i].key).record.times;
    if (list_.reference && results_.reference) results_.reference->times = traced_.at(list_.reference->key).record.times;
    if (list_.oneRay && results_.oneRay) results_.oneRay->times = traced_.at(list_.oneRay->key).record.times;
}

void Runner::execute() {
    require(Stage::Planned, "execute");
    const std::vector<Job>& jobs = list_.jobs;
    if (c_.usesAamap()) loadOrRenderSnapshot();
    else spdlog::info("no render uses the aamap: snapshot skipped");
    results_.snapshot = snapshotRecord_;

    if (options_.estimate == nullptr) planTraces(jobs);  // a sweep planned every variant's already
    const int count = static_cast<int>(jobs.size());
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const Job& job = jobs[i];
        const Traced& t = loadOrTrace(job, static_cast<int>(i) + 1, count);
        const bool cached = reused_[job.key];
        RenderRecord rec = recordFor(job, t, cached);
        writeNamedOutputs(job.render.name, t, job.render.rpp, rec.outputs);
        if (i < list_.listed) results_.renders.push_back(std::move(rec));
        else if (list_.reference && job.key == list_.reference->key && job.render.name == "reference")
            results_.reference = std::move(rec);
        else results_.oneRay = std::move(rec);
        writeResults(out_ / "results.json", results_);
    }
    if (!oracleLater_) {
        repeatTraces(jobs);
        copyRepeatedTimes();
    }
    // Jobs with equal keys (the reference is also a listed render, say) are traced once.
    const std::size_t reused = traced_.size() - static_cast<std::size_t>(tracedNow_);
    spdlog::info("{} job(s): {} traced, {} reused from {}, {} shared with an identical job", jobs.size(), tracedNow_,
                 reused, cache_.dir().string(), jobs.size() - traced_.size());
    stage_ = Stage::Executed;
}

void Runner::evaluate() {
    require(Stage::Executed, "evaluate");
    const std::vector<Job>& jobs = list_.jobs;
    const std::size_t listed = list_.listed;
    const std::optional<Job>& refJob = list_.reference;
    const std::optional<Job>& oneRayJob = list_.oneRay;
    const bool mapQuality = list_.mapQuality;
    Results& results = results_;

    // The reference every render is measured against.
    std::optional<ImageRGB> reference;
    results.referenceInfo.type = toString(c_.reference.type);
    if (refJob) {
        reference = traced_.at(refJob->key).image;
        results.referenceInfo.rpp = c_.reference.rpp;
        results.referenceInfo.mode = toString(c_.reference.modeOr(c_.shading.mode));
    } else if (fileReference_) {
        reference = std::move(fileReference_);
        results.referenceInfo.path = c_.reference.resolvedPath(c_.file)->string();
    }
    if (reference) checkReference(*reference);
    if (refJob) checkConvergence(results.referenceInfo, traced_.at(refJob->key));
    if (reference) {
        const float exposure = static_cast<float>(c_.image.exposure);
        // Causes need the 1-ray image's error (map quality) and LDR-FLIP, and a tracer's facts.
        const bool causes = mapQuality && c_.metrics.causes && c_.metrics.flip &&
                            backend_.hasPixelFacts();
        ImageGrey oneRayError;
        std::optional<PixelFacts> facts;
        if (mapQuality) {
            results.mapQuality = evaluateMap(traced_.at(oneRayJob->key).image, *reference, *aamap_, c_.metrics,
                                             exposure, out_, &oneRayError);
            if (causes) {
                facts = loadOrComputeFacts();
                results.mapQuality["causes"] =
                    evaluateMapCauses(*facts, *reference, traced_.at(oneRayJob->key).image, exposure, oneRayError, *aamap_,
                                      static_cast<float>(c_.metrics.flipThreshold), out_);
            }
        }
        for (std::size_t i = 0; i < listed; ++i) {
            RenderRecord& rec = results.renders[i];
            const Traced& t = traced_.at(jobs[i].key);
            ImageGrey flipError;
            rec.metrics = evaluateRender(*reference, t.image, c_.metrics, exposure, out_, rec.name, rec.outputs, &flipError);
            if (facts)
                rec.metrics["causes"] = evaluateRenderCauses(*facts, *reference, t.image, exposure, flipError, oneRayError, t.rays,
                                                             static_cast<float>(c_.metrics.flipThreshold), out_,
                                                             rec.name, rec.outputs);
        }
        addAntialiasingShares(results, jobs, listed, *reference);
        if (oracleLater_) {
            traceOracle(results, jobs, listed, *reference, traced_.at(oneRayJob->key).image);
            copyRepeatedTimes();
        }
        if (mapQuality) {
            spdlog::info("map quality: recall {:.3f}, precision {:.3f}, flagged {:.1f}%",
                         results.mapQuality["recall"].get<double>(), results.mapQuality["precision"].get<double>(),
                         100.0 * results.mapQuality["flagged_fraction"].get<double>());
        }
    } else {
        results.warnings.push_back("reference.type is 'none': no error metrics, Table 3 is empty");
    }
    stage_ = Stage::Evaluated;
}

Results Runner::report() {
    require(Stage::Evaluated, "report");
    for (const std::string& w : mixedMachineWarnings(results_)) warn(w);
    results_.warnings.insert(results_.warnings.begin(), warnings_.begin(), warnings_.end());
    writeResults(out_ / "results.json", results_);
    writeReport(out_, toJson(results_), options_.plots && c_.report.plots);
    stage_ = Stage::Reported;
    return results_;
}

void Runner::require(Stage before, const char* stage) const {
    if (stage_ != before)
        throw std::logic_error(fmt::format("experiment run: {} called out of order (plan, execute, evaluate, report)",
                                           stage));
}

void Runner::computeOnly(const std::string& key) {
    if (c_.usesAamap() && key == snapshotKey(c_)) {
        loadOrRenderSnapshot(false);
        return;
    }
    const JobList list = jobsOf(c_);
    const auto job = std::find_if(list.jobs.begin(), list.jobs.end(), [&](const Job& j) { return j.key == key; });
    if (job == list.jobs.end())
        throw InputError(c_.file, fmt::format("no Snapshot or render of this config has the cache key {}", key));
    if (usesAamap(job->render)) {
        if (!cache_.has(snapshotKey(c_)))
            throw EnvironmentError(fmt::format("{}: render '{}' needs the Snapshot {}, which is not in the cache",
                                               cache_.dir().string(), job->render.name, snapshotKey(c_)));
        loadOrRenderSnapshot(false);
    }
    loadOrTrace(*job, 1, 1);
    repeatTraces({*job});
}

// A cached render lacks work when it has fewer timed runs than timing.repeats asks for.
bool complete(const RenderCache& cache, const std::string& key, int repeats) {
    if (!cache.has(key)) return false;
    if (repeats <= 1) return true;
    try {
        return static_cast<int>(readCachedRender(cache.record(key)).record.times.traceRuns.size()) >= repeats;
    } catch (const std::exception&) {
        return false;  // unreadable: the run traces it again
    }
}

}  // namespace runner_detail

using runner_detail::complete;
using runner_detail::jobsOf;
using runner_detail::Job;
using runner_detail::JobList;
using runner_detail::median;
using runner_detail::planMissingTraces;
using runner_detail::Runner;
using runner_detail::usesAamap;

ExperimentRun::ExperimentRun(const ExperimentConfig& config, const fs::path& outDir, RenderBackend& backend,
                             const RunnerOptions& options)
    : runner_(std::make_unique<Runner>(config, outDir, backend, options)) {}
ExperimentRun::~ExperimentRun() = default;
void ExperimentRun::plan() { runner_->plan(); }
void ExperimentRun::execute() { runner_->execute(); }
void ExperimentRun::evaluate() { runner_->evaluate(); }
Results ExperimentRun::report() { return runner_->report(); }
const Results& ExperimentRun::results() const { return runner_->results(); }

std::vector<WorkItem> missingWork(const ExperimentConfig& config, const fs::path& cacheDir, int threads) {
    const RenderCache cache(cacheDir);
    std::vector<WorkItem> items;
    const std::string snapKey = config.usesAamap() ? snapshotKey(config) : "";
    if (!snapKey.empty() && !cache.has(snapKey)) items.push_back({"snapshot", snapKey, "snapshot", 1, "", ""});
    const JobList list = jobsOf(config);
    for (std::size_t i = 0; i < list.jobs.size(); ++i) {
        const Job& job = list.jobs[i];
        if (complete(cache, job.key, config.timing.repeats) ||
            std::any_of(items.begin(), items.end(), [&](const WorkItem& w) { return w.key == job.key; }))
            continue;
        WorkItem w{"render", job.key, job.render.name, threads >= 0 ? threads : config.threads, "", ""};
        if (usesAamap(job.render)) w.needsSnapshot = snapKey;
        // A speedup divides the time of one listed render by another's at the same rpp.
        if (config.timing.sameMachine && i < list.listed) w.group = fmt::format("{}:rpp={}", config.hash(), job.render.rpp);
        items.push_back(std::move(w));
    }
    return items;
}

void planWork(const ExperimentConfig& config, const fs::path& cacheDir, WorkEstimate& estimate,
              std::set<std::string>& planned) {
    planMissingTraces(config, RenderCache(cacheDir), jobsOf(config).jobs, estimate, planned);
}

RunPlan planRun(const ExperimentConfig& config, const fs::path& cacheDir) {
    RunPlan plan;
    plan.repeats = std::max(1, config.timing.repeats);
    plan.pixels = config.image.width * config.image.height;
    const auto record = [&](const std::string& key) -> std::optional<RenderRecord> {
        const fs::path file = cacheDir / key / "record.json";
        if (!fs::is_regular_file(file)) return std::nullopt;
        try {
            return readCachedRender(file).record;
        } catch (const std::exception&) {
            return std::nullopt;  // unreadable: the run traces it again
        }
    };
    plan.usesSnapshot = config.usesAamap();
    if (plan.usesSnapshot) {
        plan.snapshotKey = snapshotKey(config);
        plan.snapshotCached = fs::is_regular_file(cacheDir / plan.snapshotKey / "record.json");
    }
    std::vector<double> rates;
    for (const Job& job : jobsOf(config).jobs) {
        PlannedRender p{job.render.name, job.key, job.render.strategy, job.render.rpp, false, usesAamap(job.render), {}};
        if (const std::optional<RenderRecord> r = record(job.key)) {
            p.cached = static_cast<int>(r->times.traceRuns.size()) >= plan.repeats || plan.repeats <= 1;
            p.seconds = r->times.trace;
            const double units = static_cast<double>(r->maxRaysPerPixel) * r->width * r->height;
            if (units > 0 && r->times.trace > 0 && !job.render.shadingMode) rates.push_back(r->times.trace / units);
        }
        plan.renders.push_back(std::move(p));
    }
    if (!rates.empty()) plan.secondsPerRayUnit = median(rates);
    for (PlannedRender& p : plan.renders)
        if (!p.seconds && plan.secondsPerRayUnit) p.seconds = *plan.secondsPerRayUnit * p.rpp * plan.pixels;
    return plan;
}

bool hasWorkItem(const ExperimentConfig& config, const std::string& key) {
    if (config.usesAamap() && key == snapshotKey(config)) return true;
    const JobList list = jobsOf(config);
    return std::any_of(list.jobs.begin(), list.jobs.end(), [&](const Job& j) { return j.key == key; });
}

void computeWorkItem(const ExperimentConfig& config, const std::string& key, RenderBackend& backend,
                     const RunnerOptions& options) {
    if (options.cacheDir.empty()) throw EnvironmentError("computeWorkItem needs the cache folder");
    Runner runner(config, {}, backend, options);
    runner.computeOnly(key);
}

Results runExperimentWith(const ExperimentConfig& config, const fs::path& outDir, RenderBackend& backend,
                          const RunnerOptions& options) {
    std::error_code ec;
    const bool existed = fs::exists(outDir, ec);
    fs::create_directories(outDir, ec);
    if (ec) throw EnvironmentError(fmt::format("{}: cannot create output folder: {}", outDir.string(), ec.message()));
    try {
        ExperimentRun run(config, outDir, backend, options);
        run.plan();
        run.execute();
        run.evaluate();
        return run.report();
    } catch (...) {
        // A run that fails before finishing anything leaves no trace: drop the folders it made
        // if they are still empty. fs::remove never deletes a non-empty folder, so finished
        // renders in the cache (and anything the user had there) survive.
        if (!existed) {
            fs::remove(outDir / "cache", ec);
            fs::remove(outDir, ec);
        }
        throw;
    }
}

}  // namespace aamap
