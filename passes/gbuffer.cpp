#include "passes/gbuffer.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include <aamap/spirv.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"

namespace aamap::passes {
namespace {

// The mesh is drawn unindexed so that each vertex carries its triangle's material (flat
// attributes: no per-fragment buffer lookups, and no gl_PrimitiveID, which fragment shaders may
// only read with the geometry-shader feature).
struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec3 kd;
    glm::vec3 ke;
};
static_assert(sizeof(Vertex) == GBufferPass::kVertexStride);

std::vector<Vertex> flatten(const TriangleMesh& mesh, const std::vector<Material>& materials) {
    const Material fallback;  // for ids past the material list
    std::vector<Vertex> out;
    out.reserve(mesh.triangles.size() * 3);
    const bool hasNormals = mesh.normals.size() == mesh.positions.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 tri = mesh.triangles[t];
        const glm::vec3 p[3] = {mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z]};
        const glm::vec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float len = glm::length(cross);
        const glm::vec3 face = len > 0.0f ? cross / len : glm::vec3(0, 0, 1);
        const std::uint32_t id = t < mesh.materialIds.size() ? mesh.materialIds[t] : 0u;
        const Material& m = id < materials.size() ? materials[id] : fallback;
        for (int k = 0; k < 3; ++k) {
            glm::vec3 n = hasNormals ? mesh.normals[tri[k]] : face;
            if (!(glm::dot(n, n) > 0.0f)) n = face;  // zero or NaN normals in the file
            out.push_back({p[k], n, m.kd, m.ke});
        }
    }
    return out;
}

template <class T>
std::span<const std::byte> bytesOf(const std::vector<T>& v) {
    return std::as_bytes(std::span<const T>(v));
}

vk::Pipeline makePipeline(VulkanContext& context, bool shadowed) {
    vk::GraphicsDesc desc;
    desc.vertexSpirv = spirv::gbuffer_vert;
    desc.fragmentSpirv = shadowed ? spirv::gbuffer_shadowed_frag : spirv::gbuffer_frag;
    desc.vertexInput.stride = sizeof(Vertex);
    desc.vertexInput.attributes = {
        {GBUFFER_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
        {GBUFFER_LOCATION_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
        {GBUFFER_LOCATION_KD, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, kd)},
        {GBUFFER_LOCATION_KE, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, ke)},
    };
    desc.colorFormats = {vk::toVkFormat(GBufferPass::kColourFormat)};
    desc.depthFormat = vk::toVkFormat(GBufferPass::kDepthFormat);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed depth
    std::vector<VkDescriptorType> bindings{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER};  // GBUFFER_BINDING_LIGHTS
    static_assert(GBUFFER_BINDING_LIGHTS == 0 && GBUFFER_BINDING_SHADOW == 1);
    if (shadowed) bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);  // texelFetch only: no sampler
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{bindings, static_cast<std::uint32_t>(sizeof(gpu::GBufferPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

}  // namespace

GBufferPass::GBufferPass(VulkanContext& context, const Scene& scene) : context_(&context) {
    pipeline_ = makePipeline(context, false);
    const std::vector<Vertex> vertices = flatten(scene.mesh, scene.materials);
    vertexCount_ = static_cast<std::uint32_t>(vertices.size());
    vertices_ = vk::uploadBuffer(context, bytesOf(vertices), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);

    setLights({});
}

void GBufferPass::setLights(std::span<const PointLight> lights) {
    std::vector<gpu::GpuLight> gpuLights;
    for (const PointLight& l : lights)
        gpuLights.push_back({glm::vec4(l.position, 1.0f), glm::vec4(l.intensity, 0.0f), glm::vec4(l.normal, 0.0f)});
    if (gpuLights.size() > GBUFFER_MAX_LIGHTS)
        throw std::invalid_argument(fmt::format("the Snapshot raster takes at most {} point lights, the scene gives {} "
                                                "(point lights plus areaLightSamples per area light)",
                                                GBUFFER_MAX_LIGHTS, gpuLights.size()));
    lightCount_ = static_cast<std::uint32_t>(gpuLights.size());
    gpuLights.resize(GBUFFER_MAX_LIGHTS);  // the shader declares the whole array
    lights_ = vk::uploadBuffer(*context_, bytesOf(gpuLights), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
}

graph::PassId GBufferPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                               const std::string& depth, const PinholeCamera& camera, float nearPlane,
                               float farPlane, const GBufferShadows& shadows) {
    const bool shadowed = !shadows.resource.empty();
    std::vector<graph::Access> accesses{graph::writes(colour, graph::Usage::ColorAttachment),
                                        graph::writes(depth, graph::Usage::DepthAttachment)};
    if (shadowed) accesses.push_back(graph::reads(shadows.resource, graph::Usage::Sampled));
    const graph::PassId id = graph.addPass(
        {"gbuffer", graph::QueueKind::Graphics, accesses,
         shadowed ? "rasterise the scene with local illumination and shadow-map visibility per light"
                  : "rasterise the scene with local illumination"});
    if (shadowed && !shadowedPipeline_.handle()) shadowedPipeline_ = makePipeline(*context_, true);
    gpu::GBufferPush push{};
    // Reversed depth (z' = w - z, cleared to 0, GREATER wins): float depth then has about uniform
    // relative precision, so a small near plane does not cost z-fighting far away.
    glm::mat4 reverse(1.0f);
    reverse[2][2] = -1.0f;
    reverse[3][2] = 1.0f;
    push.viewProj = reverse * camera.projectionMatrix(nearPlane, farPlane) * camera.viewMatrix();
    push.cameraPos = glm::vec4(camera.origin, 1.0f);
    push.lightCount = lightCount_;
    push.shadowPcf = std::max(shadows.pcf, 1u);
    push.shadow = glm::vec4(shadows.nearPlane, shadows.depthBias, shadows.slopeBias,
                            static_cast<float>(shadows.faceSize));
    const vk::Pipeline& pipeline = shadowed ? shadowedPipeline_ : pipeline_;
    executor.setRecord("gbuffer", [this, colour, depth, push, &pipeline, shadow = shadows.resource](
                                      vk::PassContext& pc) {
        const vk::Image& target = pc.image(colour);
        const vk::Image& z = pc.image(depth);
        const VkExtent2D extent{target.info().width, target.info().height};
        VkRenderingAttachmentInfo colourInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        colourInfo.imageView = target.view();
        colourInfo.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        colourInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        colourInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        colourInfo.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};  // background: black, as rays that miss
        VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthInfo.imageView = z.view();
        depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        depthInfo.clearValue.depthStencil = {0.0f, 0};  // reversed depth: 0 is the far plane
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 1;
        rendering.pColorAttachments = &colourInfo;
        rendering.pDepthAttachment = &depthInfo;

        VkCommandBuffer cmd = pc.cmd();
        vkCmdBeginRendering(cmd, &rendering);
        vk::setFullViewport(cmd, extent);
        if (vertexCount_ > 0) {
            pipeline.bind(cmd);
            vk::DescriptorPush descriptors;
            descriptors.uniformBuffer(GBUFFER_BINDING_LIGHTS, lights_.handle());
            if (!shadow.empty())
                descriptors.sampledImage(GBUFFER_BINDING_SHADOW, pc.image(shadow).view(),
                                         VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
            descriptors.push(*context_, cmd, pipeline);
            pipeline.pushConstants(cmd, push);
            const VkBuffer vb = vertices_.handle();
            const VkDeviceSize offset = 0;
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
            vkCmdDraw(cmd, vertexCount_, 1, 0, 0);
        }
        vkCmdEndRendering(cmd);
    });
    return id;
}

}  // namespace aamap::passes

