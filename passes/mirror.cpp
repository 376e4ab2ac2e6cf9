#include "passes/mirror.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
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

bool positive(glm::vec3 c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }

}  // namespace

void mirrorAlbedos(const Material& m, glm::vec3& kd, glm::vec3& reflectance) {
    kd = m.kd;
    reflectance = glm::max(m.ks, glm::vec3(0.0f));
    if (!positive(reflectance)) reflectance = glm::vec3(1.0f);
    const glm::vec3 sum = kd + reflectance;
    const float most = std::max({sum.x, sum.y, sum.z});
    if (most > 1.0f) {
        kd /= most;
        reflectance /= most;
    }
}

glm::mat4 reflectionMatrix(glm::vec3 n, float d) {
    glm::mat4 r(1.0f);
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) r[c][k] -= 2.0f * n[k] * n[c];
    r[3] = glm::vec4(2.0f * d * n, 1.0f);
    return r;
}

MirrorGroups findPlanarMirrors(const Scene& scene) {
    const TriangleMesh& mesh = scene.mesh;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> groups;  // (object, material)
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const std::uint32_t material = t < mesh.materialIds.size() ? mesh.materialIds[t] : 0u;
        if (material >= scene.materials.size() || scene.materials[material].kind != MaterialKind::Mirror) continue;
        const std::uint32_t object = t < mesh.objectIds.size() ? mesh.objectIds[t] : 0u;
        groups[{object, material}].push_back(static_cast<std::uint32_t>(t));
    }
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& p : mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const float tolerance = 1e-4f * std::max(glm::length(hi - lo), 1e-6f);

    MirrorGroups out;
    for (const auto& [key, tris] : groups) {
        const Material& material = scene.materials[key.second];
        const std::string name = fmt::format("object {}/{}", key.first, material.name);
        // The plane through the area-weighted normal and the centroid of the first vertices.
        glm::vec3 weighted(0.0f), anchor(0.0f);
        for (std::uint32_t t : tris) {
            const glm::uvec3 i = mesh.triangles[t];
            weighted += glm::cross(mesh.positions[i.y] - mesh.positions[i.x], mesh.positions[i.z] - mesh.positions[i.x]);
            anchor += mesh.positions[i.x];
        }
        const float length = glm::length(weighted);
        if (!(length > 0.0f)) continue;  // degenerate: nothing to reflect in
        PlanarMirror mirror;
        mirror.name = name;
        mirror.normal = weighted / length;
        mirror.offset = glm::dot(mirror.normal, anchor / static_cast<float>(tris.size()));
        bool planar = true;
        for (std::uint32_t t : tris)
            for (int k = 0; k < 3 && planar; ++k)
                planar = std::fabs(glm::dot(mirror.normal, mesh.positions[mesh.triangles[t][k]]) - mirror.offset) <= tolerance;
        if (!planar) {
            out.curved.push_back(name);
            continue;
        }
        mirror.triangles = tris;
        glm::vec3 kd;
        mirrorAlbedos(material, kd, mirror.reflectance);
        out.planar.push_back(std::move(mirror));
    }
    return out;
}

MirrorPass::MirrorPass(VulkanContext& context, const Scene& scene)
    : context_(&context), mirrors_(findPlanarMirrors(scene)) {
    if (mirrors_.planar.empty()) return;  // nothing to test or draw for scenes without one
    // The reflected views go to their layers through gl_Layer from the vertex shader.
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    vkGetPhysicalDeviceFeatures2(context.physicalDevice(), &f2);
    if (!f12.shaderOutputLayer) {
        unsupported_ = fmt::format("'{}' lacks shaderOutputLayer (Vulkan 1.2), which the mirror pass needs",
                                   context.deviceName());
        return;
    }
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

bool MirrorPass::anyInView(const SnapshotView& view) const {
    return unsupported_.empty() && !visibleMirrors(view).empty();
}

// Visible mirrors, nearest first: the eye off the plane and some part of a triangle inside the
// frustum (conservative: no vertex set entirely beyond one side plane of the frustum).
std::vector<MirrorPass::VisibleMirror> MirrorPass::visibleMirrors(const SnapshotView& view) const {
    const PinholeCamera& camera = view.camera;
    const float sceneSize = view.sceneSize;
    const glm::mat4 viewProj = view.reversedViewProjection();
    std::vector<VisibleMirror> visible;
    for (const PlanarMirror& m : mirrors_.planar) {
        const float side = glm::dot(m.normal, camera.origin) - m.offset;
        if (std::fabs(side) <= 1e-6f * sceneSize) continue;
        bool inView = false;
        float nearest = INFINITY;
        for (std::uint32_t t : m.triangles) {
            int outside[5] = {0, 0, 0, 0, 0};
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 p = positions_[triangles_[t][k]];
                const glm::vec4 c = viewProj * glm::vec4(p, 1.0f);
                outside[0] += c.w <= 0.0f;
                outside[1] += c.x > c.w;
                outside[2] += c.x < -c.w;
                outside[3] += c.y > c.w;
                outside[4] += c.y < -c.w;
                nearest = std::min(nearest, glm::length(p - camera.origin));
            }
            inView |= std::none_of(std::begin(outside), std::end(outside), [](int n) { return n == 3; });
        }
        if (inView) visible.push_back({&m, side > 0.0f ? 1.0f : -1.0f, nearest});
    }
    std::sort(visible.begin(), visible.end(),
              [](const VisibleMirror& a, const VisibleMirror& b) { return a.distance < b.distance; });
    return visible;
}

void MirrorPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, GBufferPass& gbuffer,
                     const std::string& snapshot, const std::string& depth, const SnapshotView& snapshotView,
                     const GBufferShadows& shadows, std::string* why) {
    const PinholeCamera& camera = snapshotView.camera;
    const float nearPlane = snapshotView.nearPlane, farPlane = snapshotView.farPlane;
    const float sceneSize = snapshotView.sceneSize;
    const auto explain = [&](std::string text) {
        if (why) *why = std::move(text);
    };
    if (!unsupported_.empty()) {
        explain("no mirror pass: " + unsupported_);
        return;
    }
    if (mirrors_.planar.empty()) {
        explain(mirrors_.curved.empty() ? "no mirror pass: the scene has no mirror"
                                        : fmt::format("no mirror pass: {} mirror group(s) are curved (not coplanar), "
                                                      "and the Snapshot reflects planar mirrors only",
                                                      mirrors_.curved.size()));
        return;
    }
    std::vector<VisibleMirror> visible = visibleMirrors(snapshotView);
    if (visible.empty()) {
        explain(fmt::format("no mirror pass: none of the {} planar mirror(s) is in view", mirrors_.planar.size()));
        return;
    }
    if (visible.size() > kMaxMirrors) visible.resize(kMaxMirrors);
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
        views.push_back(v);
        for (std::uint32_t t : m.triangles)
            for (int k = 0; k < 3; ++k)
                maskVertices.push_back({positions_[triangles_[t][k]], m.reflectance, static_cast<float>(i)});
        if (i < 4) names += fmt::format("{}'{}'", i ? ", " : "", m.name);
    }
    if (visible.size() > 4) names += fmt::format(", ... ({} more)", visible.size() - 4);
    maskVertexCount_ = static_cast<std::uint32_t>(maskVertices.size());
    maskVertices_ = vk::uploadBuffer(*context_, std::as_bytes(std::span<const MaskVertex>(maskVertices)),
                                     VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    explain(fmt::format("{} planar mirror(s) in view: {}", visible.size(), names));

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

    graph.addPass({kMirrorMaskPass,
                   graph::QueueKind::Graphics,
                   {graph::reads(depth, graph::Usage::Sampled), graph::writes(kMirrorMask, graph::Usage::ColorAttachment)},
                   "mark the pixels where a planar mirror is the visible surface, with its reflectance"});
    gpu::MirrorMaskPush maskPush{};
    maskPush.viewProj = viewProj;
    executor.setPrepare(kMirrorMaskPass, [this] { buildMaskPipeline(); });
    executor.setRecord(kMirrorMaskPass, [this, depth, maskPush](vk::PassContext& pc) {
        const vk::Image& target = pc.image(kMirrorMask);
        const VkExtent2D extent{target.info().width, target.info().height};
        const VkRenderingAttachmentInfo colourInfo = vk::clearedColourAttachment(target.view());  // layer + 1 = 0: no mirror
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 1;
        rendering.pColorAttachments = &colourInfo;
        VkCommandBuffer cmd = pc.cmd();
        vkCmdBeginRendering(cmd, &rendering);
        vk::setFullViewport(cmd, extent);
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
    });

    graph.addPass({kMirrorCompositePass,
                   graph::QueueKind::Compute,
                   {graph::updates(snapshot, graph::Usage::StorageWrite), graph::reads(kMirrorMask, graph::Usage::StorageRead),
                    graph::reads(kMirrorColour, graph::Usage::Sampled)},
                   "add each visible mirror's reflection, times its reflectance, into the snapshot"});
    executor.setPrepare(kMirrorCompositePass, [this] { buildCompositePipeline(); });
    executor.setRecord(kMirrorCompositePass, [this, snapshot](vk::PassContext& pc) {
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
    });
}

}  // namespace aamap::passes
