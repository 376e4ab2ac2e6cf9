#pragma once
// A RenderBackend without GPU or tracer, for the runner's tests.
#include <cmath>
#include <map>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "core/error.h"
#include "eval/runner.h"

namespace aamap {

// Images with a hard vertical edge whose pixels get closer to the truth with more rays; the
// aamap flags the edge column.
class FakeBackend : public RenderBackend {
public:
    static constexpr int kW = 48, kH = 32, kBand = 4;
    SceneInfo prepare() override {
        ++prepares;
        if (failPrepare) throw InputError("fake.obj", 3, 7, "not a number");
        SceneInfo info{kW, kH, "fake:scene", "fake view", 0.01, 0.02};
        info.warnings = sceneWarnings;
        return info;
    }
    SnapshotOutput snapshot() override {
        ++snapshots;
        SnapshotOutput s;
        s.aamap = ImageGrey(kW, kH, 0.0f);
        for (int y = 0; y < kH; ++y)  // FLIP spreads an edge error over a few pixels
            for (int x = kW / 2 - kBand; x <= kW / 2 + kBand; ++x) s.aamap.at(x, y) = 1.0f;
        s.snapshot = ImageRGB(kW * 3 / 2, kH * 3 / 2, glm::vec3(0.5f));
        s.totalSeconds = 0.005;
        s.passesGpuMs = {{"gbuffer", 0.1}};
        s.device = "fake GPU";
        return s;
    }
    TraceOutput trace(const RenderConfig& r, const ImageGrey* aamap, const std::function<void(int, int)>& progress) override {
        ++traces[r.strategy + std::to_string(r.rpp)];
        order.push_back(r.strategy + std::to_string(r.rpp));
        TraceOutput t;
        t.image = ImageRGB(kW, kH);
        t.primaryRays = Image<std::uint16_t>(kW, kH, 1);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const int rays = aamap && aamap->at(x, y) == 0.0f ? 1 : r.rpp;
                const float v = x < kW / 2 ? 0.05f : x > kW / 2 ? 0.8f : 0.8f * (1.0f - 1.0f / (1.0f + rays));
                t.image.at(x, y) = glm::vec3(v + (r.shadingMode == ShadingMode::Path ? 0.0f : shadingBias));
                t.primaryRays.at(x, y) = static_cast<std::uint16_t>(rays);
            }
        if (halfNoise >= 0.0f && r.strategy == "uniform" && r.rpp >= 4) {
            // Two half images that differ by +-halfNoise / sqrt(rpp) in a checkerboard: noise.
            t.halfDifference = ImageRGB(kW, kH);
            const float a = halfNoise / std::sqrt(static_cast<float>(r.rpp));
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) t.halfDifference.at(x, y) = glm::vec3((x + y) % 2 == 0 ? a : -a);
        }
        t.rays = {static_cast<std::uint64_t>(kW * kH * r.rpp), 0, 0};
        t.seconds = 0.001 * r.rpp;
        progress(1, 1);
        return t;
    }
    std::optional<std::pair<int, int>> renderSizeWithoutScene() const override {
        return sizeKnown ? std::optional<std::pair<int, int>>(std::pair{kW, kH}) : std::nullopt;
    }
    // The edge column is a silhouette, the rest of the image plain (pixel facts for the causes).
    bool hasPixelFacts() const override { return withFacts; }
    PixelFacts pixelFacts() override {
        ++factsComputed;
        PixelFacts f(kW, kH, 0);
        for (int y = 0; y < kH; ++y) f.at(kW / 2, y) = pixel_fact::Silhouette;
        return f;
    }
    float halfNoise = -1.0f;   // >= 0: uniform renders of 4+ rays return half images that differ by this / sqrt(rpp)
    float shadingBias = 0.0f;  // added to every pixel outside path mode: a biased shading mode
    bool withFacts = false;
    int factsComputed = 0;
    int prepares = 0, snapshots = 0;
    bool failPrepare = false;
    bool sizeKnown = false;  // the render size is known without prepare() (a view file, say)  // like a scene that does not load
    std::vector<std::string> sceneWarnings;  // what prepare() reports about the scene
    std::map<std::string, int> traces;
    std::vector<std::string> order;  // every trace() call, in order
    int totalTraces() const {
        int n = 0;
        for (const auto& [k, v] : traces) n += v;
        return n;
    }
};

}  // namespace aamap
