// SnapshotRenderer: raster + aamap filter chain as one render graph, run on the GPU.
#include "passes/snapshot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "engine/vk/context.h"
#include "engine/vk/graph_executor.h"
#include "passes/environment_lighting.h"
#include "passes/gbuffer.h"
#include "passes/mirror.h"
#include "passes/mirror_probes.h"
#include "passes/gpu_aamap.h"
#include "passes/scene_gpu.h"
#include "passes/shadow_cube.h"
#include "passes/subpixel_map.h"
#include "passes/view_budget.h"
#include "glsl/shared/subpixel_map.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "passes/snapshot_graph.h"

namespace aamap {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

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
    s.directionalLights = scene.directionalLights;
    s.environment = scene.environment;
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

void validate(const ShadowSettings& s) {
    if (!s.enabled) return;
    if (s.resolution < 1 || s.resolution > 8192)
        throw std::invalid_argument("ShadowSettings::resolution must be in [1, 8192], got " +
                                    std::to_string(s.resolution));
    if (s.pcf < 1 || s.pcf > 16)
        throw std::invalid_argument("ShadowSettings::pcf must be in [1, 16], got " + std::to_string(s.pcf));
    if (!(s.depthBias >= 0.0f) || !(s.slopeBias >= 0.0f) || !std::isfinite(s.depthBias) ||
        !std::isfinite(s.slopeBias))
        throw std::invalid_argument("ShadowSettings::depthBias and slopeBias must be finite and non-negative");
    if (!(s.texelPixels >= 0.0f) || !std::isfinite(s.texelPixels))
        throw std::invalid_argument("ShadowSettings::texelPixels must be finite and non-negative");
}

// The compiled graph plus why the scene needs each kept pass (the shadow passes name their lights).
std::string explainWithPurposes(const graph::RenderGraph& graph, const graph::CompiledGraph& compiled) {
    std::string text = compiled.explain() + "pass purposes:\n";
    for (const graph::CompiledPass& p : compiled.passes)
        text += "  '" + p.name + "': " + graph.passes()[p.id].purpose + "\n";
    return text;
}

// The subpixel map's samples a side and the luminance maps' scale, as far as the device's images
// allow: the largest that fit, each change with a warning; a render no image holds is refused.
struct RasterScale {
    int k;
    float scale;
};

RasterScale fitToImages(const SnapshotSettings& settings, int width, int height, std::uint32_t limit,
                        const std::string& device, std::vector<std::string>& warnings) {
    const auto longest = static_cast<std::uint32_t>(std::max(width, height));
    if (longest > limit)
        throw std::invalid_argument(fmt::format("a {}x{} render is larger than Vulkan device '{}' allows for an image "
                                                "({} texels a side)",
                                                width, height, device, limit));
    RasterScale fit{settings.subpixel, settings.scale};
    if (settings.map == passes::AamapSource::Subpixel) {
        if (static_cast<std::uint64_t>(fit.k) * longest <= limit) return fit;
        const auto fits = static_cast<int>(limit / longest);
        if (fits < SUBPIXEL_MIN_K)
            throw std::invalid_argument(fmt::format("snapshot.subpixel: even {} samples a side need {}-texel images; "
                                                    "Vulkan device '{}' allows {}",
                                                    SUBPIXEL_MIN_K, SUBPIXEL_MIN_K * longest, device, limit));
        warnings.push_back(fmt::format("snapshot.subpixel: {} samples a side need {}-texel images; Vulkan device '{}' "
                                       "allows {}: using {}",
                                       fit.k, static_cast<std::uint64_t>(fit.k) * longest, device, limit, fits));
        fit.k = fits;
    } else if (std::lround(fit.scale * static_cast<float>(longest)) > static_cast<long>(limit)) {
        fit.scale = static_cast<float>(limit) / static_cast<float>(longest);
        warnings.push_back(fmt::format("snapshot.scale: {} needs {}-texel images; Vulkan device '{}' allows {}: using "
                                       "{:.3f}",
                                       settings.scale, std::lround(settings.scale * static_cast<float>(longest)),
                                       device, limit, fit.scale));
    }
    return fit;
}

}  // namespace

struct SnapshotRenderer::Impl {
    VulkanContext& context;
    Scene lighting;
    Bounds bounds;
    bool emptyMesh;
    passes::SceneGpu sceneGpu;  // meshes, lights and atlas, read by every raster pass
    passes::GBufferPass gbuffer;
    passes::MirrorPass mirrors;  // planar mirrors: passes only when one is in view
    passes::MirrorProbes probes;  // curved mirrors: likewise
    passes::FilterChain chain;
    passes::BlockSumPass blockSums;
    passes::GeometryBufferPass geometry;  // uploads its ids on first use
    passes::GeometricEdgePass geometricEdges;
    passes::SubpixelMapPass subpixel;
    vk::GraphExecutor executor;
    std::vector<int> areaSamples{-1};  // samples per area light the light buffer was built for
    std::vector<float> cullRadii;      // per light of the buffer: how far its patch reaches
    int environmentLights = -1;  // and the environment's extracted lights
    bool softShadows = false;    // and whether area-light samples had patches
    std::vector<std::string> lightNames;     // of the light buffer, in order
    std::vector<PointLight> pointLights;     // the buffer's point lights and area-light samples, first
    double infiniteIrradiance = 0.0;         // luminance of what its directional lights add
    std::optional<passes::ShadowCubePass> shadows;  // built on first use (needs a light)

    Impl(VulkanContext& c, const Scene& scene)
        : context(c),
          lighting(lightingCopy(scene)),
          bounds(sceneBounds(scene)),
          emptyMesh(scene.mesh.triangles.empty()),
          sceneGpu(c, scene),
          gbuffer(c, sceneGpu),
          mirrors(c, scene),
          probes(c, scene, mirrors.groups()),
          chain(c),
          blockSums(c),
          geometry(c, scene, sceneGpu),
          geometricEdges(c),
          subpixel(c),
          executor(c) {}

    // Point samples per area light for the view's region (passes/view_budget.h).
    std::vector<int> samplesFor(const Bounds& region, int maxSamples, float solidAnglePerSample) const {
        std::vector<int> counts;
        for (const AreaLight& area : lighting.areaLights) {
            double total = 0.0;
            glm::dvec3 centre(0.0), normal(0.0);
            for (std::uint32_t t : area.triangles) {
                const double a = triangleArea(lighting.mesh, t);
                const glm::uvec3 v = lighting.mesh.triangles[t];
                centre += a * (glm::dvec3(lighting.mesh.positions[v.x]) + glm::dvec3(lighting.mesh.positions[v.y]) +
                               glm::dvec3(lighting.mesh.positions[v.z])) / 3.0;
                normal += a * glm::dvec3(triangleNormal(lighting.mesh, t));
                total += a;
            }
            if (!(total > 0.0)) {
                counts.push_back(std::max(maxSamples, 1));
                continue;
            }
            centre /= total;
            // A curved or two-faced light (mean normal well short of unit length) counts from every side.
            const glm::dvec3 n = glm::length(normal) > 0.9 * total ? glm::normalize(normal) : glm::dvec3(0.0);
            const double omega = passes::meanSolidAngle(total, glm::vec3(centre), glm::vec3(n), region);
            counts.push_back(passes::areaLightSamplesFor(omega, solidAnglePerSample, maxSamples));
        }
        return counts;
    }

    void updateLights(const std::vector<int>& counts, int fromEnvironment, bool soft) {
        if (counts == areaSamples && fromEnvironment == environmentLights && soft == softShadows) return;
        for (const int k : counts)
            if (k < 1)
                throw std::invalid_argument("SnapshotSettings::areaLightSamples must be at least 1, got " +
                                            std::to_string(k));
        if (fromEnvironment < 0 || fromEnvironment > 16)
            throw std::invalid_argument("SnapshotSettings::environmentLights must be in [0, 16], got " +
                                        std::to_string(fromEnvironment));
        std::vector<PointLight> lights = lighting.pointLights;
        std::vector<float> patchHalfSides(lights.size(), 0.0f);  // true point lights: hard shadows
        cullRadii.assign(lights.size(), 0.0f);
        for (std::size_t a = 0; a < lighting.areaLights.size(); ++a) {
            const AreaLight& area = lighting.areaLights[a];
            const int k = counts[a];
            const std::vector<PointLight> samples = approximateAreaLight(lighting, area, k);
            double total = 0.0;
            for (std::uint32_t t : area.triangles) total += triangleArea(lighting.mesh, t);
            // Each sample stands for 1/k of the light: a square of that area, whose penumbra its
            // shadow lookup spreads (glsl/shadow_visibility.glsl softShadowVisibility).
            const float halfSide = soft ? static_cast<float>(0.5 * std::sqrt(total / k)) : 0.0f;
            patchHalfSides.insert(patchHalfSides.end(), samples.size(), halfSide);
            for (const PointLight& sample : samples) {
                // How far the light reaches from the sample: the view cull of its shadow faces keeps
                // every triangle between any point of the light and the view (soft shadows filter
                // over the whole patch; hard ones need only the sample, but the margin is cheap).
                float reach = 0.0f;
                for (std::uint32_t t : area.triangles) {
                    const glm::uvec3 v = lighting.mesh.triangles[t];
                    for (const std::uint32_t i : {v.x, v.y, v.z})
                        reach = std::max(reach, glm::length(lighting.mesh.positions[i] - sample.position));
                }
                cullRadii.push_back(reach);
            }
            lights.insert(lights.end(), samples.begin(), samples.end());
        }
        std::vector<DirectionalLight> directionals = lighting.directionalLights;
        std::optional<passes::EnvironmentLighting> env;
        if (lighting.environment) {
            env = passes::prepareEnvironmentLighting(*lighting.environment, fromEnvironment);
            directionals.insert(directionals.end(), env->lights.begin(), env->lights.end());
        }
        sceneGpu.setLights(lights, directionals, env ? &env->irradianceSH : nullptr, patchHalfSides);
        sceneGpu.setBackground(env ? env->background : glm::vec3(0.0f));
        lightNames.clear();
        for (const PointLight& l : lights) lightNames.push_back(l.name);
        pointLights = lights;
        infiniteIrradiance = 0.0;
        for (const DirectionalLight& d : directionals)
            if (glm::length(d.direction) > 0.0f)
                infiniteIrradiance += 0.2126 * d.irradiance.x + 0.7152 * d.irradiance.y + 0.0722 * d.irradiance.z;
        for (const DirectionalLight& d : directionals)
            if (glm::length(d.direction) > 0.0f) {
                lightNames.push_back(d.name);
                cullRadii.push_back(0.0f);
            }
        areaSamples = counts;
        environmentLights = fromEnvironment;
        softShadows = soft;
    }
};

// The one step from the config section to the passes' settings (float where the GPU takes float).
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
    validate(settings.shadows);
    Impl& s = *impl_;
    if (settings.areaLightSamples < 1 && !s.lighting.areaLights.empty())
        throw std::invalid_argument("SnapshotSettings::areaLightSamples must be at least 1, got " +
                                    std::to_string(settings.areaLightSamples));
    if (!(settings.areaLightSolidAngle >= 0.0f) || !std::isfinite(settings.areaLightSolidAngle))
        throw std::invalid_argument("SnapshotSettings::areaLightSolidAngle must be finite and non-negative");

    const bool subpixelMap = settings.map == passes::AamapSource::Subpixel;
    if (subpixelMap && (settings.subpixel < SUBPIXEL_MIN_K || settings.subpixel > SUBPIXEL_MAX_K))
        throw std::invalid_argument("SnapshotSettings::subpixel must be in [2, 4], got " +
                                    std::to_string(settings.subpixel));
    // What the device's images allow: a Snapshot larger than that falls back to the nearest
    // resolution it has (fewer samples a side, a smaller scale), with a warning.
    SnapshotResult result;
    const std::uint32_t limit = s.context.maxImageDimension2D();
    const RasterScale fit = fitToImages(settings, width, height, limit, s.context.deviceName(), result.warnings);
    const int k = fit.k;
    const float scale = fit.scale;
    result.subpixel = subpixelMap ? k : 0;
    auto scaled = [&](int v) {
        return std::min(limit, static_cast<std::uint32_t>(std::max(1L, std::lround(scale * static_cast<float>(v)))));
    };
    // The subpixel map reads k x k geometry samples per render pixel, texel (k x + i, k y + j), and
    // one shade per pixel (shared) or per sample.
    const bool sharedShading = settings.subpixelShading == passes::SubpixelShading::Pixel;
    const auto colourScale = static_cast<std::uint32_t>(sharedShading ? 1 : k);
    const std::uint32_t snapW = subpixelMap ? colourScale * static_cast<std::uint32_t>(width) : scaled(width);
    const std::uint32_t snapH = subpixelMap ? colourScale * static_cast<std::uint32_t>(height) : scaled(height);
    passes::SnapshotView snapshotView;
    snapshotView.camera = PinholeCamera::fromView(view);
    clipPlanes(s.bounds, snapshotView.camera.origin, s.emptyMesh, snapshotView.nearPlane, snapshotView.farPlane);
    snapshotView.sceneSize = glm::length(s.bounds.extent());
    // What the view needs (passes/view_budget.h): the area lights' samples for the region it sees.
    const glm::mat4 viewProj = snapshotView.reversedViewProjection();
    const Bounds region = s.emptyMesh ? s.bounds : passes::visibleRegion(viewProj, s.bounds);
    s.updateLights(s.samplesFor(region, settings.areaLightSamples, settings.areaLightSolidAngle),
                   settings.environmentLights, settings.shadows.enabled && settings.shadows.softShadows);

    s.executor.clear();
    graph::RenderGraph graph;
    graph::ResourceDesc colour;
    colour.name = passes::kSnapshot;
    colour.format = passes::GBufferPass::kColourFormat;
    colour.size = graph::Size::absolute(snapW, snapH);
    graph.addResource(colour);
    graph::ResourceDesc depth;
    depth.name = passes::kDepth;
    depth.format = passes::GBufferPass::kDepthFormat;
    depth.size = graph::Size::relative(passes::kSnapshot);
    graph.addResource(depth);
    // Shadow maps only for what is there: no lights (or no geometry to cast), no shadow pass.
    passes::GBufferShadows shadows;
    bool mirrorsForceFullShadows = false;
    const bool shadowed = settings.shadows.enabled && s.sceneGpu.lightCount() > 0 && !s.emptyMesh;
    if (shadowed) {
        if (!s.shadows) s.shadows.emplace(s.context);
        shadows.resource = passes::kShadowCubes;
        // Geometry within this distance of a light (its own emitter, for area-light samples) casts
        // no shadow; the stored near/ma keeps float precision at every distance.
        shadows.nearPlane = std::max(1e-4f * glm::length(s.bounds.extent()), 1e-6f);
        shadows.depthBias = settings.shadows.depthBias;
        shadows.slopeBias = settings.shadows.slopeBias;
        shadows.pcf = static_cast<std::uint32_t>(settings.shadows.pcf);
        // Mirrors show points outside the frustum, which need every caster and the full resolution.
        const bool mirrorsInView =
            s.mirrors.anyInView(snapshotView, {snapW, snapH}) || s.probes.anyInView(snapshotView, {snapW, snapH});
        // Each light's face size by need (passes/view_budget.h); lights at infinity take the whole layer.
        // In pixels of the map (the render's), which is what a shadow edge's position must be right to.
        mirrorsForceFullShadows = mirrorsInView;
        const passes::ShadowNeedView need{viewProj, snapshotView.camera.origin,
                                          {static_cast<unsigned>(width), static_cast<unsigned>(height)}, region};
        const std::vector<int> bySize =
            passes::shadowFaceSizes(s.pointLights, s.infiniteIrradiance, need,
                                    mirrorsInView ? 0.0f : settings.shadows.texelPixels, settings.shadows.resolution);
        std::vector<std::uint32_t> faceSizes(s.sceneGpu.lightCount(),
                                             static_cast<std::uint32_t>(settings.shadows.resolution));
        for (std::size_t i = 0; i < bySize.size() && i < faceSizes.size(); ++i)
            faceSizes[i] = static_cast<std::uint32_t>(bySize[i]);
        s.sceneGpu.setShadowFaceSizes(faceSizes);
        shadows.faceSize = *std::max_element(faceSizes.begin(), faceSizes.end());
        const passes::ViewFrustum frustum = passes::ViewFrustum::fromViewProjection(viewProj);
        s.shadows->add(graph, s.executor, shadows.resource, s.sceneGpu, s.lightNames, shadows.faceSize,
                       shadows.nearPlane, mirrorsInView ? nullptr : &frustum, s.cullRadii);
    }
    // The G-buffer writes the aamap's grey itself unless something changes the snapshot after the
    // opaque draw (a mirror composite, glass blended over it) or the map does not read the grey:
    // one compute pass fewer.
    passes::GBufferGrey grey;
    if (!s.mirrors.anyInView(snapshotView, {snapW, snapH}) && !s.probes.anyInView(snapshotView, {snapW, snapH}) &&
        !s.gbuffer.drawsGlass() &&
        settings.map != passes::AamapSource::Geometric && !subpixelMap) {
        graph.addResource(
            graph::imageResource(passes::kGrey, passes::GBufferPass::kGreyFormat, graph::Size::relative(passes::kSnapshot)));
        grey = {passes::kGrey, settings.filter.exposure};
    }
    s.gbuffer.add(graph, s.executor, passes::kSnapshot, passes::kDepth, snapshotView, shadows, grey, true);
    std::string mirrorWhy;
    s.mirrors.add(graph, s.executor, s.gbuffer, passes::kSnapshot, passes::kDepth, snapshotView, {snapW, snapH},
                  shadows, &mirrorWhy);
    std::string probeWhy;
    s.probes.add(graph, s.executor, s.gbuffer, passes::kSnapshot, passes::kDepth, snapshotView, {snapW, snapH}, shadows,
                 &probeWhy);
    passes::MapChainInputs mapInputs{passes::kSnapshot, snapshotView, width, height, settings.filter};
    mapInputs.shadows = shadows;  // the geometric map's occlusion mask: the same shadow maps
    mapInputs.greyFromGBuffer = !grey.resource.empty();
    mapInputs.subpixel = {k, settings.filter.exposure, subpixelTolerance(settings.flipThreshold), sharedShading};
    passes::addAamapChain(graph, s.executor, s.chain, s.geometry, s.geometricEdges, s.subpixel, settings.map,
                          mapInputs);
    // Always declared: culled (with the reason in `explain`) unless a strategy asked for it.
    s.blockSums.add(graph, s.executor, passes::kAamap, width, height,
                    "O(1) aamap block sums for adaptive subsampling");

    std::vector<std::string> outputs{passes::kAamap};
    if (settings.keepDebugImages) {
        outputs.push_back(passes::kSnapshot);
        if (settings.map != passes::AamapSource::Geometric && !subpixelMap) outputs.push_back(passes::kLaplacian);
        if (settings.map != passes::AamapSource::Luminance && !subpixelMap) outputs.push_back(passes::kEdges);
    }
    if (settings.blockSums) {
        outputs.push_back(passes::kBlockSums);
        outputs.push_back(passes::kBlockCounts);
    }
    const graph::CompiledGraph compiled = graph.compile(outputs);
    if (spdlog::should_log(spdlog::level::debug)) spdlog::debug("Snapshot {}", compiled.explain());
    const vk::ExecutionResult run = s.executor.execute(compiled);

    const auto convert = Clock::now();
    result.aamap = passes::toImageGrey(run.outputs.at(passes::kAamap));
    if (settings.keepDebugImages) {
        result.snapshot = passes::toImageRGB(run.outputs.at(passes::kSnapshot));
        if (settings.map != passes::AamapSource::Geometric && !subpixelMap)
            result.laplacian = passes::toImageGrey(run.outputs.at(passes::kLaplacian));
        if (settings.map != passes::AamapSource::Luminance && !subpixelMap)
            result.edges = passes::toImageGrey(run.outputs.at(passes::kEdges));
    }
    if (settings.blockSums)
        result.blockSums = passes::toBlockSumTables(run.outputs.at(passes::kBlockSums),
                                                    run.outputs.at(passes::kBlockCounts), width, height);
    result.readbackSeconds = run.readbackSeconds + secondsSince(convert);
    for (const vk::PassTime& t : run.passTimes) result.passTimes.push_back({t.pass, t.milliseconds});
    result.deviceName = s.context.deviceName();
    result.explain = explainWithPurposes(graph, compiled) + "mirrors: " + mirrorWhy + "\ncurved mirrors: " + probeWhy + "\n";
    if (!s.lighting.areaLights.empty()) {
        result.explain += fmt::format("area-light samples (one per {} sr of mean solid angle over the visible region, "
                                      "at most {}):",
                                      settings.areaLightSolidAngle, settings.areaLightSamples);
        for (std::size_t a = 0; a < s.lighting.areaLights.size() && a < s.areaSamples.size(); ++a)
            result.explain += fmt::format("{} '{}' {}", a ? "," : "", s.lighting.areaLights[a].name, s.areaSamples[a]);
        result.explain += "\n";
    }
    if (shadowed) {
        result.explain += fmt::format("shadow faces by need (texels per side, one texel at most {} render pixel(s) at "
                                      "full contrast, at most {}{}):",
                                      settings.shadows.texelPixels, settings.shadows.resolution,
                                      mirrorsForceFullShadows ? "; a mirror in view: every light at most" : "");
        const std::span<const std::uint32_t> sizes = s.sceneGpu.shadowFaceSizes();
        for (std::size_t i = 0; i < sizes.size() && i < s.lightNames.size(); ++i)
            result.explain += fmt::format("{} '{}' {}", i ? "," : "", s.lightNames[i], sizes[i]);
        result.explain += "\n";
        result.shadowFaceSizes.assign(sizes.begin(), sizes.end());
    }
    result.dot = compiled.toDot();
    result.shadowCubeMaps = shadowed ? static_cast<int>(s.sceneGpu.lightCount()) : 0;
    result.areaLightSamples = s.areaSamples;
    result.totalSeconds = secondsSince(start);
    return result;
}

std::vector<std::string> snapshotLimitations(const Scene& scene) {
    std::vector<std::string> notes;
    const MirrorGroups mirrors = findPlanarMirrors(scene);
    if (!mirrors.curved.empty())
        notes.push_back(fmt::format("{} mirror group(s) are not planar everywhere ({}{}): the Snapshot reflects their "
                                    "curved triangles through a cube probe from the group's centre, without parallax",
                                    mirrors.curved.size(), mirrors.curved.front().describe(),
                                    mirrors.curved.size() > 1 ? "; ..." : ""));
    std::size_t glass = 0;
    for (const std::uint32_t id : scene.mesh.materialIds)
        if (id < scene.materials.size() && scene.materials[id].kind == MaterialKind::Glass) ++glass;
    if (glass > 0)
        notes.push_back(fmt::format("{} glass triangle(s): the Snapshot draws glass over what lies straight behind "
                                    "it, Fresnel-weighted, so its silhouettes are in the aamap but what it refracts "
                                    "is not",
                                    glass));
    if (scene.environment && !scene.environment->map.empty())
        notes.push_back("an environment map: the Snapshot's background is the sky's mean radiance, not the map, so "
                        "edges against the sky are judged against that flat colour");
    return notes;
}

}  // namespace aamap
