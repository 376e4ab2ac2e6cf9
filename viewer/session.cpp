#include "viewer/session.h"

#include <algorithm>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "eval/metrics/flip.h"
#include "eval/metrics/magma.h"
#include "eval/metrics/pixel_error.h"
#include "eval/strategies.h"
#include "eval/strategy_settings.h"

namespace aamap {
namespace {

// Thrown from the tile callback: TBB cancels the other tiles and render() rethrows it.
struct TraceCancelled {};

ImageRGB8 greyToRgb(const ImageGrey8& g) {
    ImageRGB8 rgb(g.width(), g.height());
    std::transform(g.pixels().begin(), g.pixels().end(), rgb.pixels().begin(),
                   [](std::uint8_t v) { return glm::u8vec3(v); });
    return rgb;
}

bool sameView(const View& a, const View& b) { return a.position == b.position && a.direction == b.direction; }

std::string millions(std::uint64_t rays) { return fmt::format("{:.2f}M", static_cast<double>(rays) * 1e-6); }

}  // namespace

const char* toString(ViewMode mode) {
    switch (mode) {
        case ViewMode::Snapshot: return "snapshot";
        case ViewMode::Laplacian: return "laplacian";
        case ViewMode::Aamap: return "aamap";
        case ViewMode::RaysPerPixel: return "rpp";
        case ViewMode::Render: return "render";
        case ViewMode::Error: return "error";
    }
    return "?";
}

bool parse(const std::string& name, ViewMode& mode) {
    for (ViewMode m : {ViewMode::Snapshot, ViewMode::Laplacian, ViewMode::Aamap, ViewMode::RaysPerPixel,
                       ViewMode::Render, ViewMode::Error})
        if (name == toString(m)) {
            mode = m;
            return true;
        }
    return false;
}

struct ViewerSession::TraceJob {
    RenderConfig render;
    View view;
    ImageGrey aamap;  // the map the render was started with (the strategy keeps a pointer)
    bool atConfigView = false;
    bool traceRender = true;  // false: only the reference and the error of the finished render
    std::atomic<bool> cancel{false};
};

ViewerSession::ViewerSession(VulkanContext& context, const ExperimentConfig& config, PreparedScene prepared,
                             const RenderConfig& render, int threads)
    : context_(context),
      config_(withSceneRenderSettings(config, prepared.scene, sceneNotes_)),
      prepared_(std::move(prepared)),
      baseRender_(render),
      threads_(threads),
      width_(prepared_.width),
      height_(prepared_.height),
      camera_(prepared_.view, pivotDistanceFor(prepared_.scene, prepared_.view)),
      snapshotRenderer_(context, prepared_.scene),
      tracer_(prepared_.scene) {
    for (const std::string& note : sceneNotes_) spdlog::info("{}", note);
    params_.blurRadius = config.snapshot.filter.blurRadius;
    params_.noiseFloor = config.snapshot.filter.noiseFloor;
    params_.strata = render.strata();
    const StrategyDescriptor* strategy = findStrategy(render.strategy);
    if (strategy != nullptr && strategy->usesAamap) params_.strategy = render.strategy;
    for (const auto& [key, value] : render.params.entries()) params_.strategyParams.set(key, value);
}

ViewerSession::~ViewerSession() { cancelTrace(); }

std::string nextViewerStrategy(const std::string& current) {
    std::vector<std::string> names;
    for (const StrategyDescriptor& s : strategyRegistry())
        if (s.usesAamap) names.push_back(s.name);
    const auto at = std::find(names.begin(), names.end(), current);
    return at == names.end() || at + 1 == names.end() ? names.front() : *(at + 1);
}

void ViewerSession::setParams(const ViewerParams& p) {
    ViewerParams c = p;
    // The config's ranges: snapshot.blur_radius and snapshot.noise_floor as declared.
    c.blurRadius = std::get<int>(snapshotSchema().find("blur_radius")->spec.clamp(c.blurRadius));
    c.noiseFloor = std::get<double>(snapshotSchema().find("noise_floor")->spec.clamp(c.noiseFloor));
    c.strata = std::clamp(c.strata, 1, 16);
    const StrategyDescriptor* strategy = findStrategy(c.strategy);
    if (strategy == nullptr || !strategy->usesAamap) {  // the viewer tunes the map: strategies that use it
        c.strategy = ViewerParams{}.strategy;
        strategy = findStrategy(c.strategy);
    }
    for (const auto& [key, value] : p.strategyParams.entries())
        if (const ParamSpec* spec = strategy->param(key)) c.strategyParams.set(key, spec->clamp(value));
    if (c.blurRadius != params_.blurRadius || c.noiseFloor != params_.noiseFloor) snapshotDirty_ = true;
    params_ = c;
}

RenderConfig ViewerSession::renderFromParams() const {
    RenderConfig r;
    r.name = "view";
    r.series = "view";
    r.strategy = params_.strategy;
    r.rpp = params_.strata * params_.strata;
    r.shadingMode = baseRender_.shadingMode;
    // The strategy's parameters in schema order: the viewer's values (seeded from the config's
    // render), defaults for the rest.
    for (const ParamSpec& spec : findStrategy(r.strategy)->params) {
        const ParamValue* v = params_.strategyParams.find(spec.name);
        r.params.set(spec.name, v != nullptr ? *v : spec.defaultParam());
    }
    return r;
}

void ViewerSession::update() {
    const View view = camera_.view();
    const bool moved = !snapshot_ || !sameView(view, snapshotView_);
    if (!moved && !snapshotDirty_) return;
    if (moved && snapshot_) {
        cancelTrace();  // its view is gone
        std::lock_guard lock(mutex_);
        if (renderComplete_) traceStatus_ += " (camera moved since)";
        renderComplete_ = false;  // no longer this view's render: no reference for it
    }
    SnapshotSettings settings = snapshotSettingsFor(config_);
    settings.filter.blurRadius = params_.blurRadius;
    settings.filter.noiseFloor = static_cast<float>(params_.noiseFloor);
    settings.keepDebugImages = true;
    snapshot_ = snapshotRenderer_.render(view, width_, height_, settings);
    for (const std::string& w : snapshot_->warnings) spdlog::warn("{}", w);
    snapshotView_ = view;
    snapshotDirty_ = false;
}

void ViewerSession::cancelTrace() {
    if (job_) job_->cancel = true;
    if (worker_.joinable()) worker_.join();  // at most one tile per thread more
    job_.reset();
}

void ViewerSession::waitForTrace() {
    if (worker_.joinable()) worker_.join();
}

void ViewerSession::startTrace() {
    update();
    cancelTrace();
    auto job = std::make_unique<TraceJob>();
    job->render = renderFromParams();
    job->view = snapshotView_;
    job->aamap = snapshot_->aamap;
    job->atConfigView = camera_.atStart();
    {
        std::lock_guard lock(mutex_);
        live_ = ImageRGB(width_, height_, glm::vec3(0.0f));
        liveRays_ = Image<std::uint16_t>(width_, height_, 0);
        haveRender_ = true;
        renderComplete_ = false;
        tilesDone_ = 0;
        tilesTotal_ = 0;
        traceStatus_ = "tracing";
        referenceStatus_.clear();  // reference_ stays: reused while the view is the same
        errorMap_.reset();
        errorStatus_.clear();
        tracedRender_ = job->render;
    }
    job_ = std::move(job);
    running_ = true;
    worker_ = std::thread([this, j = job_.get()] { runTrace(*j); });
}

void ViewerSession::runTrace(TraceJob& job) {
    const auto cancellable = [&job](const TileUpdate&) {
        if (job.cancel.load(std::memory_order_relaxed)) throw TraceCancelled{};
    };
    bool inReference = !job.traceRender;
    try {
        if (job.traceRender) {
            TraceSettings ts = traceSettingsFor(config_, job.render, width_, height_, threads_);
            ts.onTileDone = [this](int done, int total) {
                std::lock_guard lock(mutex_);
                tilesDone_ = done;
                tilesTotal_ = total;
            };
            ts.onTileFinished = [this, &job](const TileUpdate& t) {
                if (job.cancel.load(std::memory_order_relaxed)) throw TraceCancelled{};
                std::lock_guard lock(mutex_);
                for (int y = t.y0; y < t.y1; ++y)
                    for (int x = t.x0; x < t.x1; ++x) {
                        live_.at(x, y) = t.image.at(x, y);
                        liveRays_.at(x, y) = t.primaryRays.at(x, y);
                    }
            };
            StrategySettings strategy = toStrategySettings(job.render, &job.aamap);
            strategy.exposure = static_cast<float>(config_.image.exposure);  // as `aamap run` renders it
            TraceResult r = tracer_.render(job.view, ts, strategy);
            const double meanRpp = static_cast<double>(r.rays.primary) / (static_cast<double>(width_) * height_);
            spdlog::info("view: {} traced in {:.2f} s, {} rays ({:.2f} primary/pixel)", r.strategy, r.seconds,
                         r.rays.total(), meanRpp);
            std::lock_guard lock(mutex_);
            live_ = std::move(r.image);  // with the interpolated pixels of multi-phase strategies
            liveRays_ = std::move(r.primaryRays);
            renderComplete_ = true;
            traceStatus_ = fmt::format("trace {:.2f} s, {} rays ({:.2f} primary/px)", r.seconds,
                                       millions(r.rays.total()), meanRpp);
        }
        if (!referenceWanted_) {
            running_ = false;
            return;
        }
        // The reference, lazily: what `aamap run` compares with, at this view.
        inReference = true;
        std::optional<ImageRGB> reference;
        ImageRGB render;
        {
            std::lock_guard lock(mutex_);
            render = live_;
            if (reference_ && sameView(referenceView_, job.view)) reference = reference_;  // tuning: same view
        }
        std::string why;
        if (reference) {
            // kept from an earlier trace of this view
        } else if (config_.reference.type == ReferenceType::Uniform) {
            {
                std::lock_guard lock(mutex_);
                referenceStatus_ = fmt::format("tracing the reference ({} rpp)", config_.reference.rpp);
            }
            const RenderConfig ref{"reference", "reference", baselineStrategyName(), config_.reference.rpp, {}, config_.reference.mode};
            TraceSettings ts = traceSettingsFor(config_, ref, width_, height_, threads_);
            ts.onTileFinished = cancellable;
            reference = tracer_.render(job.view, ts, toStrategySettings(ref, nullptr)).image;
        } else if (config_.reference.type == ReferenceType::File) {
            if (!job.atConfigView) why = "the reference file shows the config's view: press R to return to it";
            else reference = readExr(*config_.reference.resolvedPath(config_.file));
            if (reference && (reference->width() != width_ || reference->height() != height_)) {
                why = fmt::format("the reference file is {}x{}, the render {}x{}", reference->width(),
                                  reference->height(), width_, height_);
                reference.reset();
            }
        } else {
            why = "the config has no reference (reference.type: none)";
        }
        if (!reference) {
            std::lock_guard lock(mutex_);
            referenceStatus_ = why;
        } else {
            const float exposure = static_cast<float>(config_.image.exposure);
            metrics::FlipOptions fo;
            fo.ppd = static_cast<float>(config_.metrics.ppd);
            fo.threshold = static_cast<float>(config_.metrics.flipThreshold);
            const metrics::FlipResult f = metrics::flipDisplay(*reference, render, exposure, fo);
            metrics::PixelErrorOptions po;
            po.exposure = exposure;
            po.errorThreshold = config_.metrics.mseThreshold;
            const metrics::PixelError pe = metrics::pixelError(*reference, render, po);
            std::lock_guard lock(mutex_);
            errorMap_ = f.errorMap;
            errorStatus_ = fmt::format("FLIP {:.4f} ({:.1f}% > {}), MSE {:.2e} ({:.1f}% px in error)", f.mean,
                                       100.0 * f.fractionAbove, config_.metrics.flipThreshold, pe.mse,
                                       100.0 * pe.fractionInError);
            reference_ = std::move(reference);
            referenceView_ = job.view;
            referenceStatus_.clear();
        }
    } catch (const TraceCancelled&) {
        std::lock_guard lock(mutex_);
        if (inReference) referenceStatus_ = "reference cancelled";
        else traceStatus_ = "trace cancelled";
    } catch (const std::exception& e) {
        spdlog::error("view: trace failed: {}", e.what());
        std::lock_guard lock(mutex_);
        traceStatus_ = fmt::format("trace failed: {}", e.what());
    }
    running_ = false;
}

ImageRGB8 ViewerSession::display(ViewMode mode, std::string& why) {
    const float exposure = static_cast<float>(config_.image.exposure);
    why.clear();
    if (mode == ViewMode::Snapshot || mode == ViewMode::Laplacian || mode == ViewMode::Aamap) {
        if (!snapshot_) {
            why = "no Snapshot yet";
            return {};
        }
        if (mode == ViewMode::Snapshot) return toneMap(snapshot_->snapshot, exposure);
        if (mode == ViewMode::Laplacian) return greyToRgb(quantise(snapshot_->laplacian));
        return greyToRgb(quantise(snapshot_->aamap));  // exactly what `aamap run` writes as aamap.png
    }
    bool needReference = false;
    if (mode == ViewMode::Error && !running_) {
        std::lock_guard lock(mutex_);
        needReference = renderComplete_ && !errorMap_ && referenceStatus_.empty();
    }
    if (needReference) {
        // First look at the error of a finished render: compute the reference now, in the background.
        referenceWanted_ = true;
        if (worker_.joinable()) worker_.join();
        auto job = std::make_unique<TraceJob>();
        job->view = snapshotView_;
        job->atConfigView = camera_.atStart();
        job->traceRender = false;
        job_ = std::move(job);
        running_ = true;
        worker_ = std::thread([this, j = job_.get()] { runTrace(*j); });
    }
    std::lock_guard lock(mutex_);
    if (!haveRender_) {
        why = "no render yet: press T to trace this view";
        return {};
    }
    switch (mode) {
        case ViewMode::RaysPerPixel: return falseColour(liveRays_, tracedRender_.rpp);
        case ViewMode::Render: return toneMap(live_, exposure);
        default: break;
    }
    if (!errorMap_) {
        why = referenceStatus_.empty() ? "the error map follows the render" : referenceStatus_;
        return {};
    }
    return toneMap(metrics::magmaImage(*errorMap_), 1.0f);
}

std::string ViewerSession::status(ViewMode mode) const {
    std::string s = fmt::format("aamap view [{}]", toString(mode));
    if (snapshot_) {
        std::vector<std::string> passes;
        for (const PassTiming& p : snapshot_->passTimes) passes.push_back(fmt::format("{} {:.1f}", p.pass, p.gpuMilliseconds));
        s += fmt::format(" | snapshot {:.0f} ms (GPU ms: {})", snapshot_->totalSeconds * 1e3, fmt::join(passes, ", "));
    }
    s += fmt::format(" | blur {} floor {:.3f} | {} n={} ({} rpp)", params_.blurRadius, params_.noiseFloor,
                     params_.strategy, params_.strata, params_.strata * params_.strata);
    const RenderConfig traced = renderFromParams();
    for (const auto& [key, value] : traced.params.entries()) s += fmt::format(" {}={}", key, toString(value));
    std::lock_guard lock(mutex_);
    if (haveRender_) {
        if (running_ && traceStatus_ == "tracing" && tilesTotal_ > 0)
            s += fmt::format(" | tracing {}%", 100 * tilesDone_ / tilesTotal_);
        else
            s += " | " + traceStatus_;
    }
    if (!errorStatus_.empty()) s += " | " + errorStatus_;
    else if (!referenceStatus_.empty()) s += " | " + referenceStatus_;
    return s;
}

}  // namespace aamap
