#include "passes/mirror.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <unordered_map>
#include <utility>

#include <aamap/spirv.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {
namespace {


struct MaskVertex {
    glm::vec3 position;
    glm::vec3 reflectance;
    float layer;
};

// The pixels of an image of `pixels` that NDC bounds (min x, min y, max x, max y) touch, one pixel
// of slack for the raster's rounding; the whole image if the bounds are empty or not finite.
VkRect2D scissorOf(glm::vec4 ndc, glm::uvec2 pixels) {
    const auto toPixel = [](float v, std::uint32_t size) {
        const float p = (v + 1.0f) * 0.5f * static_cast<float>(size);
        return std::isfinite(p) ? static_cast<int>(std::clamp(p, 0.0f, static_cast<float>(size))) : 0;
    };
    if (!(ndc.x <= ndc.z && ndc.y <= ndc.w)) return {{0, 0}, {pixels.x, pixels.y}};
    const int x0 = std::max(toPixel(ndc.x, pixels.x) - 1, 0), y0 = std::max(toPixel(ndc.y, pixels.y) - 1, 0);
    const int x1 = std::min(toPixel(ndc.z, pixels.x) + 2, static_cast<int>(pixels.x));
    const int y1 = std::min(toPixel(ndc.w, pixels.y) + 2, static_cast<int>(pixels.y));
    return {{x0, y0}, {static_cast<std::uint32_t>(std::max(x1 - x0, 1)), static_cast<std::uint32_t>(std::max(y1 - y0, 1))}};
}

}  // namespace

std::string reflectedViewsUnsupported(VulkanContext& context, const std::string& pass) {
    // The reflected views go to their layers through gl_Layer from the vertex shader.
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    vkGetPhysicalDeviceFeatures2(context.physicalDevice(), &f2);
    if (f12.shaderOutputLayer) return {};
    return fmt::format("'{}' lacks shaderOutputLayer (Vulkan 1.2), which the {} pass needs", context.deviceName(), pass);
}

MirrorPass::MirrorPass(VulkanContext& context, const Scene& scene)
    : context_(&context), mirrors_(findPlanarMirrors(scene)) {
    if (mirrors_.planar.empty()) return;  // nothing to test or draw for scenes without one
    unsupported_ = reflectedViewsUnsupported(context, kMirrorPass);
    if (!unsupported_.empty()) return;
    positions_ = scene.mesh.positions;
    triangles_ = scene.mesh.triangles;
}

// Built by the executor's prepare step, so a scene whose mirrors are never in view builds neither.
void MirrorPass::buildMaskPipeline() {
    if (maskPipeline_.handle()) return;
    vk::GraphicsDesc mask;
    mask.vertexSpirv = spirv::mirror_mask_vert;
    mask.fragmentSpirv = spirv::mirror_mask_frag;
    mask.vertexInput.stride = sizeof(MaskVertex);
    mask.vertexInput.attributes = {
        {MIRROR_MASK_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MaskVertex, position)},
        {MIRROR_MASK_LOCATION_REFLECTANCE, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MaskVertex, reflectance)},
        {MIRROR_MASK_LOCATION_LAYER, 0, VK_FORMAT_R32_SFLOAT, offsetof(MaskVertex, layer)},
    };
    mask.colorFormats = {vk::toVkFormat(graph::Format::RGBA32Float)};
    static_assert(MIRROR_MASK_BINDING_DEPTH == 0);
    maskPipeline_ = vk::Pipeline(*context_, mask,
                                 vk::LayoutDesc{{VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
                                                static_cast<std::uint32_t>(sizeof(gpu::MirrorMaskPush)),
                                                VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

void MirrorPass::buildCompositePipeline() {
    if (compositePipeline_.handle()) return;
    static_assert(MIRROR_COMPOSITE_BINDING_SNAPSHOT == 0 && MIRROR_COMPOSITE_BINDING_MASK == 1 &&
                  MIRROR_COMPOSITE_BINDING_COLOUR == 2);
    compositePipeline_ = vk::Pipeline(
        *context_, spirv::mirror_composite_comp,
        vk::LayoutDesc{{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
                       static_cast<std::uint32_t>(sizeof(gpu::MirrorCompositePush)), VK_SHADER_STAGE_COMPUTE_BIT});
}

bool MirrorPass::anyInView(const SnapshotView& view, glm::uvec2 snapshotPixels) const {
    return unsupported_.empty() && !selectMirrors(view, snapshotPixels).reflected.empty();
}

// The planes this view reflects: the eye off the plane, then by projected coverage within the
// budget (kMinReflectedPixels, kMaxMirrors), largest first.
MirrorPass::MirrorSelection MirrorPass::selectMirrors(const SnapshotView& view, glm::uvec2 snapshotPixels) const {
    const glm::mat4 viewProj = view.reversedViewProjection();  // x, y and w as the plain projection's
    MirrorSelection selection;
    for (const PlanarMirror& m : mirrors_.planar) {
        const float side = glm::dot(m.normal, view.camera.origin) - m.offset;
        if (!(std::fabs(side) > 1e-6f * view.sceneSize)) continue;  // seen edge-on
        const double pixels =
            projectedPixels(positions_, triangles_, m.triangles, viewProj, view.nearPlane, snapshotPixels);
        if (!(pixels > 0.0)) continue;
        ++selection.inView;
        if (pixels < kMinReflectedPixels) {
            ++selection.tooSmall;
            continue;
        }
        selection.reflected.push_back({&m, side > 0.0f ? 1.0f : -1.0f, pixels});
    }
    std::stable_sort(selection.reflected.begin(), selection.reflected.end(),
                     [](const VisibleMirror& a, const VisibleMirror& b) { return a.pixels > b.pixels; });
    if (selection.reflected.size() > kMaxMirrors) {
        selection.overLimit = selection.reflected.size() - kMaxMirrors;
        selection.reflected.resize(kMaxMirrors);
    }
    return selection;
}

void MirrorPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, GBufferPass& gbuffer,
                     const std::string& snapshot, const std::string& depth, const SnapshotView& snapshotView,
                     glm::uvec2 snapshotPixels, const GBufferShadows& shadows, std::string* why) {
    const PinholeCamera& camera = snapshotView.camera;
    const float nearPlane = snapshotView.nearPlane, farPlane = snapshotView.farPlane;
    const float sceneSize = snapshotView.sceneSize;
    std::string curved;  // what gets no reflection in any view
    for (std::size_t i = 0; i < mirrors_.curved.size() && i < 3; ++i)
        curved += fmt::format("{}{}", i ? "; " : "", mirrors_.curved[i].describe());
    if (mirrors_.curved.size() > 3) curved += fmt::format("; ... ({} more groups)", mirrors_.curved.size() - 3);
    const auto explain = [&](std::string text) {
        if (!curved.empty()) text += "; curved (reflected through environment probes): " + curved;
        if (why) *why = std::move(text);
    };
    if (!unsupported_.empty()) {
        explain("no mirror pass: " + unsupported_);
        return;
    }
    if (mirrors_.planar.empty()) {
        explain(mirrors_.curved.empty() ? "no mirror pass: the scene has no mirror"
                                        : fmt::format("no mirror pass: {} mirror group(s) are curved (no plane holds "
                                                      "enough of them): environment probes reflect them",
                                                      mirrors_.curved.size()));
        return;
    }
    const MirrorSelection selection = selectMirrors(snapshotView, snapshotPixels);
    const std::vector<VisibleMirror>& visible = selection.reflected;
    std::string skipped;  // the budget's part
    if (selection.tooSmall > 0)
        skipped += fmt::format("; {} plane(s) skipped for the budget: under {} snapshot pixels each",
                               selection.tooSmall, kMinReflectedPixels);
    if (selection.overLimit > 0)
        skipped += fmt::format("; {} plane(s) skipped for the budget: beyond the {} largest", selection.overLimit,
                               kMaxMirrors);
    if (visible.empty()) {
        explain(selection.inView == 0
                    ? fmt::format("no mirror pass: none of the {} planar mirror(s) is in view", mirrors_.planar.size())
                    : fmt::format("no mirror pass: 0 of the {} planar mirror(s) in view reflected{}", selection.inView,
                                  skipped));
        return;
    }
    const glm::mat4 view = camera.viewMatrix();
    const glm::mat4 viewProj = snapshotView.reversedViewProjection();

    // One reflected view per mirror; the clip plane keeps the eye's side, a hair off the mirror
    // itself so that the mirror does not reflect its own surface.
    std::vector<ReflectedView> views;
    std::vector<MaskVertex> maskVertices;
    std::string names;
    for (std::size_t i = 0; i < visible.size(); ++i) {
        const PlanarMirror& m = *visible[i].mirror;
        const glm::mat4 reflect = reflectionMatrix(m.normal, m.offset);
        // Clip planes for the reflected eye; x and y of the projection do not depend on them,
        // so pixel (x, y) still matches the camera's.
        ReflectedView v;
        // Every scene point is within farPlane + |eye - reflected eye| of the reflected eye.
        const float reflectedFar = farPlane + 2.0f * std::fabs(glm::dot(m.normal, camera.origin) - m.offset);
        v.viewProj = GBufferPass::reversedViewProjection(
            camera.projectionMatrix(std::min(nearPlane, reflectedFar * 1e-5f), reflectedFar), view * reflect);
        v.eye = glm::vec3(reflect * glm::vec4(camera.origin, 1.0f));
        const glm::vec3 n = visible[i].sign * m.normal;
        v.clipPlane = glm::vec4(n, visible[i].sign * m.offset + 1e-5f * sceneSize);
        // Only the mirror's own pixels are composited: the view shades its screen rectangle.
        glm::vec4 ndc;
        projectedPixels(positions_, triangles_, m.triangles, viewProj, nearPlane, snapshotPixels, &ndc);
        v.scissor = scissorOf(ndc, snapshotPixels);
        views.push_back(v);
        for (std::uint32_t t : m.triangles)
            for (int k = 0; k < 3; ++k)
                maskVertices.push_back({positions_[triangles_[t][k]], m.reflectance, static_cast<float>(i)});
        if (i < 4) names += fmt::format("{}'{}' ({:.0f} px)", i ? ", " : "", m.name, visible[i].pixels);
    }
    if (visible.size() > 4) names += fmt::format(", ... ({} more)", visible.size() - 4);
    maskVertexCount_ = static_cast<std::uint32_t>(maskVertices.size());
    maskVertices_ = vk::uploadBuffer(*context_, std::as_bytes(std::span<const MaskVertex>(maskVertices)),
                                     VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    explain(fmt::format("{} planar mirror(s) in view reflected: {}{}", visible.size(), names, skipped));

    // The array view needs two layers at least (a one-layer image gets a 2D view).
    const auto layers = static_cast<std::uint32_t>(std::max<std::size_t>(visible.size(), 2));
    graph::ResourceDesc colour;
    colour.name = kMirrorColour;
    colour.format = GBufferPass::kColourFormat;
    colour.size = graph::Size::relative(snapshot);
    colour.layers = layers;
    graph.addResource(colour);
    graph::ResourceDesc mirrorDepth = colour;
    mirrorDepth.name = kMirrorDepth;
    mirrorDepth.format = GBufferPass::kDepthFormat;
    graph.addResource(mirrorDepth);
    graph::ResourceDesc mask;
    mask.name = kMirrorMask;
    mask.format = graph::Format::RGBA32Float;
    mask.size = graph::Size::relative(snapshot);
    graph.addResource(mask);

    gbuffer.addReflected(graph, executor, kMirrorPass, kMirrorColour, kMirrorDepth, views, shadows,
                          fmt::format("the scene seen in {} planar mirror{} (camera reflected in each mirror plane, "
                                      "clipped to it): {}",
                                      visible.size(), visible.size() == 1 ? "" : "s", names));

    gpu::MirrorMaskPush maskPush{};
    maskPush.viewProj = viewProj;
    vk::PassDeclaration maskPass;
    maskPass.desc = {kMirrorMaskPass,
                     graph::QueueKind::Graphics,
                     {graph::reads(depth, graph::Usage::Sampled), graph::writes(kMirrorMask, graph::Usage::ColorAttachment)},
                     "mark the pixels where a planar mirror is the visible surface, with its reflectance"};
    maskPass.prepare = [this] { buildMaskPipeline(); };
    maskPass.record = [this, depth, maskPush](vk::PassContext& pc) {
        const vk::Image& target = pc.image(kMirrorMask);
        const VkExtent2D extent{target.info().width, target.info().height};
        VkCommandBuffer cmd = pc.cmd();
        vk::beginColourRendering(cmd, vk::clearedColourAttachment(target.view()), extent);  // layer + 1 = 0: no mirror
        maskPipeline_.bind(cmd);
        vk::DescriptorPush()
            .sampledImage(MIRROR_MASK_BINDING_DEPTH, pc.image(depth).view(), VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL)
            .push(*context_, cmd, maskPipeline_);
        maskPipeline_.pushConstants(cmd, maskPush);
        const VkBuffer vb = maskVertices_.handle();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdDraw(cmd, maskVertexCount_, 1, 0, 0);
        vkCmdEndRendering(cmd);
    };
    vk::declarePass(graph, executor, std::move(maskPass));

    vk::PassDeclaration compositePass;
    compositePass.desc = {kMirrorCompositePass,
                          graph::QueueKind::Compute,
                          {graph::updates(snapshot, graph::Usage::StorageWrite), graph::reads(kMirrorMask, graph::Usage::StorageRead),
                           graph::reads(kMirrorColour, graph::Usage::Sampled)},
                          "add each visible mirror's reflection, times its reflectance, into the snapshot"};
    compositePass.prepare = [this] { buildCompositePipeline(); };
    compositePass.record = [this, snapshot](vk::PassContext& pc) {
        const vk::Image& target = pc.image(snapshot);
        gpu::MirrorCompositePush push{};
        push.size = {static_cast<int>(target.info().width), static_cast<int>(target.info().height)};
        compositePipeline_.bind(pc.cmd());
        vk::DescriptorPush()
            .storageImage(MIRROR_COMPOSITE_BINDING_SNAPSHOT, target.view())
            .storageImage(MIRROR_COMPOSITE_BINDING_MASK, pc.image(kMirrorMask).view())
            .sampledImage(MIRROR_COMPOSITE_BINDING_COLOUR, pc.image(kMirrorColour).view(),
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
            .push(*context_, pc.cmd(), compositePipeline_);
        compositePipeline_.pushConstants(pc.cmd(), push);
        vk::dispatch2D(pc.cmd(), target.info().width, target.info().height, MIRROR_COMPOSITE_GROUP,
                       MIRROR_COMPOSITE_GROUP);
    };
    vk::declarePass(graph, executor, std::move(compositePass));
}

}  // namespace aamap::passes
