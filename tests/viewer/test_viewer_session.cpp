// The viewer's parts below the window (label viewer): the tracer's tile hook that feeds the live
// view, the camera rig, and ViewerSession's Snapshot and cancellable trace on a headless context
// (lavapipe, validation on through the GPU fixture).
#include <algorithm>
#include <atomic>
#include <mutex>
#include <set>
#include <string>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "../gpu/gpu_fixture.h"
#include "core/image_io.h"
#include "eval/config.h"
#include "eval/experiment.h"
#include "eval/strategy_settings.h"
#include "scene/load_scene.h"
#include "tracer/tracer.h"
#include "viewer/camera_rig.h"
#include "viewer/session.h"

namespace aamap {
namespace {

TraceSettings smallTrace(int w, int h) {
    TraceSettings ts;
    ts.width = w;
    ts.height = h;
    ts.shading.areaLightSamples = 4;
    return ts;
}

// The tiles the hook reports cover the image once per phase, and copying their pixels as they
// arrive rebuilds the final image exactly; the hook changes nothing in the result.
TEST(ViewerStrategies, GCyclesThroughEveryStrategyThatUsesTheAamap) {
    std::set<std::string> seen;
    std::string s = "uniform";  // not one of them: G starts at the first
    for (std::size_t i = 0; i < 2 * strategyRegistry().size(); ++i) {
        s = nextViewerStrategy(s);
        EXPECT_TRUE(findStrategy(s)->usesAamap) << s;
        seen.insert(s);
    }
    std::size_t usingTheMap = 0;
    for (const StrategyDescriptor& d : strategyRegistry()) usingTheMap += d.usesAamap ? 1 : 0;
    EXPECT_EQ(seen.size(), usingTheMap);
    EXPECT_EQ(nextViewerStrategy("aamap"), "aamap-subsample");
}

TEST(TileHook, TilesRebuildTheFinalImageAndChangeNothing) {
    const Scene scene = loadScene("builtin:cornell");
    const Tracer tracer(scene);
    const int W = 40, H = 37;  // not a multiple of the 16-pixel tile
    StrategySettings strategy;
    strategy.name = "uniform";
    strategy.strata = 2;
    const TraceResult plain = tracer.render(scene.views[0], smallTrace(W, H), strategy);

    TraceSettings ts = smallTrace(W, H);
    std::mutex mutex;
    ImageRGB live(W, H, glm::vec3(-1.0f));
    Image<int> covered(W, H, 0);
    ts.onTileFinished = [&](const TileUpdate& t) {
        std::lock_guard lock(mutex);
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                live.at(x, y) = t.image.at(x, y);
                ++covered.at(x, y);
            }
    };
    const TraceResult hooked = tracer.render(scene.views[0], ts, strategy);
    EXPECT_EQ(hooked.image, plain.image);
    EXPECT_EQ(live, hooked.image);
    EXPECT_TRUE(std::all_of(covered.pixels().begin(), covered.pixels().end(), [](int c) { return c == 1; }));
}

// Throwing from the hook cancels the render: render() rethrows, and the tracer is usable again.
TEST(TileHook, ThrowingCancelsTheRender) {
    const Scene scene = loadScene("builtin:cornell");
    const Tracer tracer(scene);
    StrategySettings strategy;
    strategy.name = "uniform";
    TraceSettings ts = smallTrace(64, 64);
    ts.threads = 2;
    std::atomic<int> tiles{0};
    struct Stop {};
    ts.onTileFinished = [&](const TileUpdate&) {
        ++tiles;
        throw Stop{};
    };
    EXPECT_THROW(tracer.render(scene.views[0], ts, strategy), Stop);
    EXPECT_LT(tiles.load(), 16);  // of 16 tiles: the rest were cancelled (each thread ends its tile at most)
    const TraceResult again = tracer.render(scene.views[0], smallTrace(64, 64), strategy);
    EXPECT_EQ(again.image, tracer.render(scene.views[0], smallTrace(64, 64), strategy).image);
}

TEST(CameraRig, OrbitKeepsThePivotAndResetReturns) {
    View start;
    start.position = {0, 0, 5};
    start.direction = {0, 0, -1};
    CameraRig rig(start, 5.0f);
    EXPECT_TRUE(rig.atStart());
    rig.orbit(0.7f, 0.3f);
    const View v = rig.view();
    EXPECT_FALSE(rig.atStart());
    EXPECT_NEAR(glm::length(v.position), 5.0f, 1e-4f);                  // still 5 from the pivot (origin)
    EXPECT_NEAR(glm::dot(glm::normalize(v.direction), -glm::normalize(v.position)), 1.0f, 1e-5f);  // looks at it
    EXPECT_EQ(v.horizontalFovDeg, start.horizontalFovDeg);
    rig.reset();
    EXPECT_TRUE(rig.atStart());
    rig.look(0.2f, 0.0f);
    EXPECT_EQ(rig.view().position, start.position);  // looking turns in place
    rig.fly({0, 0, 0.2f});
    EXPECT_NEAR(glm::distance(rig.view().position, start.position), 1.0f, 1e-4f);  // 0.2 pivot distances
}

class Session : public test::GpuTest {
protected:
    static ExperimentConfig config(int size, int rpp) {
        return parseConfig(fmt::format("scene: builtin:cornell\nimage: {{width: {0}, height: {0}}}\n"
                                       "shading: {{area_light_samples: 16}}\n"
                                       "renders: [{{name: sel, strategy: aamap-subsample, rpp: {1}, spacing: 8}}]\n"
                                       "reference: {{type: none}}\n",
                                       size, rpp),
                           "session.yaml");
    }
};

// The Snapshot the session shows is the offline one (same prepareScene and settings).
TEST_F(Session, SnapshotIsTheOfflineSnapshot) {
    const ExperimentConfig c = config(64, 4);
    PreparedScene p = prepareScene(c);
    SnapshotRenderer renderer(context(), p.scene);
    const SnapshotResult offline = renderer.render(p.view, p.width, p.height, snapshotSettingsFor(c));
    ViewerSession session(context(), c, prepareScene(c), c.renders[0], 1);
    session.update();
    std::string why;
    const ImageRGB8 shown = session.display(ViewMode::Aamap, why);
    ASSERT_TRUE(why.empty()) << why;
    ASSERT_EQ(shown.width(), offline.aamap.width());
    const ImageGrey8 q = quantise(offline.aamap);
    for (std::size_t i = 0; i < q.size(); ++i) ASSERT_EQ(shown.pixels()[i], glm::u8vec3(q.pixels()[i])) << i;
    EXPECT_NE(session.status(ViewMode::Aamap).find("blur 1"), std::string::npos);
}

// A camera move cancels the trace in flight; tracing again at the start view gives the offline
// render (the hook and the cancel leave no trace in the tracer).
TEST_F(Session, MovingCancelsTheTrace) {
    const ExperimentConfig c = config(128, 36);
    ViewerSession session(context(), c, prepareScene(c), c.renders[0], 1);
    session.update();
    session.startTrace();
    session.camera().orbit(0.2f, 0.0f);
    session.update();  // re-runs the Snapshot, cancels the trace
    EXPECT_FALSE(session.tracing());
    EXPECT_NE(session.status(ViewMode::Render).find("cancelled"), std::string::npos)
        << session.status(ViewMode::Render);
    std::string why;
    EXPECT_TRUE(session.display(ViewMode::Render, why).size() > 0);  // the partial render stays visible

    session.camera().reset();
    session.update();
    ViewerParams p = session.params();
    p.strata = 2;  // cheaper for the comparison
    session.setParams(p);
    session.startTrace();
    session.waitForTrace();
    const ImageRGB8 shown = session.display(ViewMode::Render, why);

    PreparedScene prepared = prepareScene(c);
    SnapshotRenderer renderer(context(), prepared.scene);
    const SnapshotResult snap = renderer.render(prepared.view, prepared.width, prepared.height, snapshotSettingsFor(c));
    RenderConfig r = c.renders[0];
    r.rpp = 4;
    const Tracer tracer(prepared.scene);
    const TraceResult offline = tracer.render(prepared.view, traceSettingsFor(c, r, prepared.width, prepared.height, 1),
                                              toStrategySettings(r, &snap.aamap));
    EXPECT_EQ(shown, toneMap(offline.image, 1.0f));
}

}  // namespace
}  // namespace aamap
