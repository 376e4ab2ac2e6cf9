#pragma once
// The viewer's state without any window: the scene set up exactly as `aamap run` does
// (eval/experiment.h), the Snapshot re-run on demand, and one selective trace at a time on a
// background thread whose tiles show up as they finish. The window (viewer.cpp) only presents
// what display() returns and maps keys to the setters.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/image.h"
#include "core/image_io.h"
#include "eval/config.h"
#include "eval/experiment.h"
#include "passes/snapshot.h"
#include "passes/snapshot_params.h"
#include "tracer/strategies/subsample.h"
#include "tracer/tracer.h"
#include "viewer/camera_rig.h"

namespace aamap {

class VulkanContext;

enum class ViewMode { Snapshot, Laplacian, Aamap, RaysPerPixel, Render, Error };
const char* toString(ViewMode mode);
bool parse(const std::string& name, ViewMode& mode);  // "snapshot", "laplacian", "aamap", "rpp", "render", "error"

// What the keys adjust. Snapshot side: blur radius and noise floor. Trace side: the render's
// strategy (aamap or aamap-subsample), n (n x n rays per pixel at most), spacing and threshold.
// The Snapshot side starts at the config section's defaults (passes/snapshot_params.h), the trace
// side at adaptive subsampling's declaration (tracer/strategies/subsample.h).
struct ViewerParams {
    int blurRadius = SnapshotSettings().filter.blurRadius;
    float noiseFloor = SnapshotSettings().filter.noiseFloor;
    std::string strategy = kSubsampleStrategyName;
    int strata = 4;
    // Parameters of the traced strategy (spacing, threshold, ...), by name; setParams clamps those
    // the strategy declares into its schema's ranges and keeps the others for a switch back.
    StrategyParams strategyParams = resolveParams(*findStrategy(strategy), {});
};

// The strategy G switches to: the next one in the registry that uses the aamap (the viewer
// traces only those), after `current`.
std::string nextViewerStrategy(const std::string& current);

class ViewerSession {
public:
    // render: the config render the viewer traces (its strategy and parameters seed ViewerParams).
    ViewerSession(VulkanContext& context, const ExperimentConfig& config, PreparedScene prepared,
                  const RenderConfig& render, int threads);
    ~ViewerSession();  // cancels and joins the trace
    ViewerSession(const ViewerSession&) = delete;
    ViewerSession& operator=(const ViewerSession&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }
    CameraRig& camera() { return camera_; }
    const ViewerParams& params() const { return params_; }
    void setParams(const ViewerParams& p);  // clamps; a change that moves the aamap re-runs the Snapshot

    // Re-runs the Snapshot (and the aamap) for the current camera and parameters, if either changed
    // since the last one; a moved camera or a changed map also cancels the trace in flight.
    void update();
    void startTrace();   // a selective trace of the current view (cancels one in flight)
    void cancelTrace();
    bool tracing() const { return running_.load(); }
    void waitForTrace();  // until the trace (and the reference, if wanted) is done
    // The error view asks for the reference lazily: traced after the render (reference.type
    // uniform), read from the file (type file, and only at the config's view), or unavailable.
    void wantReference() { referenceWanted_ = true; }

    // The image mode shows, as sRGB bytes; empty with `why` set when it has nothing to show yet.
    ImageRGB8 display(ViewMode mode, std::string& why);
    std::string status(ViewMode mode) const;

private:
    struct TraceJob;
    void runTrace(TraceJob& job);
    RenderConfig renderFromParams() const;

    VulkanContext& context_;
    std::vector<std::string> sceneNotes_;  // what the scene file decides (withSceneRenderSettings)
    ExperimentConfig config_;              // the config with it
    PreparedScene prepared_;
    RenderConfig baseRender_;
    int threads_;
    int width_, height_;
    CameraRig camera_;
    ViewerParams params_;
    SnapshotRenderer snapshotRenderer_;
    Tracer tracer_;

    std::optional<SnapshotResult> snapshot_;
    View snapshotView_;
    bool snapshotDirty_ = true;

    // Shared with the trace thread, under mutex_.
    mutable std::mutex mutex_;
    ImageRGB live_;                 // the render, filled tile by tile
    Image<std::uint16_t> liveRays_;
    bool haveRender_ = false;
    bool renderComplete_ = false;  // the trace finished, at the current view
    int tilesDone_ = 0, tilesTotal_ = 0;
    std::string traceStatus_;       // "tracing 40%", "done 1.23 s, 4.5M rays", "cancelled"
    std::optional<ImageRGB> reference_;  // at referenceView_; reused while tuning at that view
    View referenceView_;
    std::string referenceStatus_;
    std::optional<ImageGrey> errorMap_;
    std::string errorStatus_;
    RenderConfig tracedRender_;

    std::unique_ptr<TraceJob> job_;
    std::thread worker_;
    std::atomic<bool> running_{false};
    std::atomic<bool> referenceWanted_{false};
};

}  // namespace aamap
