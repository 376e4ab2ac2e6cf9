// SnapshotRenderer: raster + aamap filter chain as one render graph, run on the GPU.
#include "passes/snapshot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "engine/vk/context.h"
#include "engine/vk/graph_executor.h"
#include "passes/gbuffer.h"
#include "passes/gpu_aamap.h"
#include "scene/camera.h"
#include "scene/lights.h"

namespace aamap {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

const std::string kSnapshot = "snapshot";
const std::string kDepth = "depth";

// Only what the light approximation needs (the mesh without UVs and ids, and the lights), so
// the renderer does not depend on the caller keeping the Scene alive.
Scene lightingCopy(const Scene& scene) {
    Scene s;
    s.name = scene.name;
    s.mesh.positions = scene.mesh.positions;
    s.mesh.normals = scene.mesh.normals;
    s.mesh.triangles = scene.mesh.triangles;
    s.materials = scene.materials;
    s.pointLights = scene.pointLights;
    s.areaLights = scene.areaLights;
    return s;
}

// Clip planes that enclose the scene's bounding sphere. Depth is reversed (see below), so a
// tiny near plane costs no precision.
void clipPlanes(const Bounds& bounds, glm::vec3 eye, bool empty, float& nearPlane, float& farPlane) {
    if (empty) {
        nearPlane = 1e-3f;
        farPlane = 1e3f;
        return;
    }
    const float radius = 0.5f * glm::length(bounds.extent());
    const float distance = glm::length(eye - bounds.centre());
    farPlane = std::max((distance + radius) * 1.01f, 1e-3f);
    nearPlane = std::max((distance - radius) * 0.99f, farPlane * 1e-6f);
}

}  // namespace

struct SnapshotRenderer::Impl {
    VulkanContext& context;
    Scene lighting;
    Bounds bounds;
    bool emptyMesh;
    passes::GBufferPass gbuffer;
    passes::FilterChain chain;
    vk::GraphExecutor executor;
    int lightSamples = -1;  // k the light buffer was built for

    Impl(VulkanContext& c, const Scene& scene)
        : context(c),
          lighting(lightingCopy(scene)),
          bounds(sceneBounds(scene)),
          emptyMesh(scene.mesh.triangles.empty()),
          gbuffer(c, scene),
          chain(c),
          executor(c) {}

    void updateLights(int k) {
        if (k == lightSamples) return;
        if (k < 1 && !lighting.areaLights.empty())
            throw std::invalid_argument("SnapshotSettings::areaLightSamples must be at least 1, got " +
                                        std::to_string(k));
        std::vector<PointLight> lights = lighting.pointLights;
        for (const AreaLight& area : lighting.areaLights) {
            const std::vector<PointLight> samples = approximateAreaLight(lighting, area, k);
            lights.insert(lights.end(), samples.begin(), samples.end());
        }
        gbuffer.setLights(lights);
        lightSamples = k;
    }
};

SnapshotRenderer::SnapshotRenderer(VulkanContext& context, const Scene& scene)
    : impl_(std::make_unique<Impl>(context, scene)) {}
SnapshotRenderer::~SnapshotRenderer() = default;

SnapshotResult SnapshotRenderer::render(const View& view, int width, int height, const SnapshotSettings& settings) {
    const auto start = Clock::now();
    if (width <= 0 || height <= 0)
        throw std::invalid_argument("SnapshotRenderer::render: non-positive size " + std::to_string(width) + "x" +
                                    std::to_string(height));
    if (!(settings.scale > 0.0f) || !std::isfinite(settings.scale))
        throw std::invalid_argument("SnapshotSettings::scale must be positive");
    Impl& s = *impl_;
    s.updateLights(settings.areaLightSamples);

    auto scaled = [&](int v) {
        return static_cast<std::uint32_t>(std::max(1L, std::lround(settings.scale * static_cast<float>(v))));
    };
    const std::uint32_t snapW = scaled(width), snapH = scaled(height);
    const PinholeCamera camera = PinholeCamera::fromView(view);
    float nearPlane = 0.0f, farPlane = 0.0f;
    clipPlanes(s.bounds, camera.origin, s.emptyMesh, nearPlane, farPlane);

    s.executor.clear();
    graph::RenderGraph graph;
    graph::ResourceDesc colour;
    colour.name = kSnapshot;
    colour.format = passes::GBufferPass::kColourFormat;
    colour.size = graph::Size::absolute(snapW, snapH);
    graph.addResource(colour);
    graph::ResourceDesc depth;
    depth.name = kDepth;
    depth.format = passes::GBufferPass::kDepthFormat;
    depth.size = graph::Size::relative(kSnapshot);
    graph.addResource(depth);
    s.gbuffer.add(graph, s.executor, kSnapshot, kDepth, camera, nearPlane, farPlane);
    s.chain.add(graph, s.executor, kSnapshot, width, height, settings.filter);

    std::vector<std::string> outputs{passes::kAamap};
    if (settings.keepDebugImages) {
        outputs.push_back(kSnapshot);
        outputs.push_back(passes::kLaplacian);
    }
    const graph::CompiledGraph compiled = graph.compile(outputs);
    if (spdlog::should_log(spdlog::level::debug)) spdlog::debug("Snapshot {}", compiled.explain());
    const vk::ExecutionResult run = s.executor.execute(compiled);

    SnapshotResult result;
    const auto convert = Clock::now();
    result.aamap = passes::toImageGrey(run.outputs.at(passes::kAamap));
    if (settings.keepDebugImages) {
        result.snapshot = passes::toImageRGB(run.outputs.at(kSnapshot));
        result.laplacian = passes::toImageGrey(run.outputs.at(passes::kLaplacian));
    }
    result.readbackSeconds = run.readbackSeconds + secondsSince(convert);
    for (const vk::PassTime& t : run.passTimes) result.passTimes.push_back({t.pass, t.milliseconds});
    result.deviceName = s.context.deviceName();
    result.explain = compiled.explain();
    result.totalSeconds = secondsSince(start);
    return result;
}

}  // namespace aamap
