#include "passes/geometry_buffer.h"

#include <cstddef>
#include <cstring>
#include <stdexcept>

#include <aamap/spirv.h>
#include <glm/geometric.hpp>

#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"

namespace aamap::passes {

namespace {

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    std::uint32_t objectId, materialId;
};

// Unindexed, so that ids travel as flat vertex attributes (as the G-buffer does with materials).
std::vector<Vertex> flatten(const TriangleMesh& mesh) {
    std::vector<Vertex> out;
    out.reserve(mesh.triangles.size() * 3);
    const bool hasNormals = mesh.normals.size() == mesh.positions.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 tri = mesh.triangles[t];
        const glm::vec3 p[3] = {mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z]};
        const glm::vec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float len = glm::length(cross);
        const glm::vec3 face = len > 0.0f ? cross / len : glm::vec3(0, 0, 1);
        const std::uint32_t object = t < mesh.objectIds.size() ? mesh.objectIds[t] : 0u;
        const std::uint32_t material = t < mesh.materialIds.size() ? mesh.materialIds[t] : 0u;
        for (int k = 0; k < 3; ++k) {
            glm::vec3 n = hasNormals ? mesh.normals[tri[k]] : face;
            if (!(glm::dot(n, n) > 0.0f)) n = face;
            out.push_back({p[k], n, object, material});
        }
    }
    return out;
}

vk::Pipeline makePipeline(VulkanContext& context) {
    vk::GraphicsDesc desc;
    desc.vertexSpirv = spirv::geometry_buffer_vert;
    desc.fragmentSpirv = spirv::geometry_buffer_frag;
    desc.vertexInput.stride = sizeof(Vertex);
    desc.vertexInput.attributes = {
        {GEOMETRY_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
        {GEOMETRY_LOCATION_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
        {GEOMETRY_LOCATION_IDS, 0, VK_FORMAT_R32G32_UINT, offsetof(Vertex, objectId)},
    };
    const VkFormat f = vk::toVkFormat(GeometryBufferPass::kFormat);
    desc.colorFormats = {f, f};
    desc.depthFormat = vk::toVkFormat(graph::Format::D32Float);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed depth, as the G-buffer
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{{}, static_cast<std::uint32_t>(sizeof(gpu::GeometryPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

graph::ResourceDesc image(const std::string& name, graph::Format format, const std::string& like) {
    graph::ResourceDesc d;
    d.name = name;
    d.format = format;
    d.size = graph::Size::relative(like);
    return d;
}

VkRenderingAttachmentInfo colourAttachment(const vk::Image& image) {
    VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    info.imageView = image.view();
    info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    info.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};  // depth 0: uncovered
    return info;
}

}  // namespace

GeometryBufferPass::GeometryBufferPass(VulkanContext& context, const Scene& scene) : context_(&context) {
    const std::vector<Vertex> vertices = flatten(scene.mesh);
    vertexCount_ = static_cast<std::uint32_t>(vertices.size());
    pending_.resize(vertices.size() * sizeof(Vertex));
    if (!pending_.empty()) std::memcpy(pending_.data(), vertices.data(), pending_.size());
}

GeometryBufferPass::~GeometryBufferPass() = default;

void GeometryBufferPass::prepare() {
    if (!pipeline_.handle()) pipeline_ = makePipeline(*context_);
    if (vertexCount_ == 0 || vertices_) return;
    vertices_ = vk::uploadBuffer(*context_, pending_, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    pending_ = {};
}

void GeometryBufferPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& like,
                             const PinholeCamera& camera, float nearPlane, float farPlane) {
    graph.addResource(image(kGeometryNormalDepth, kFormat, like));
    graph.addResource(image(kGeometryIds, kFormat, like));
    graph.addResource(image(kGeometryDepth, graph::Format::D32Float, like));
    graph.addPass({"geometry_buffer",
                   graph::QueueKind::Graphics,
                   {graph::writes(kGeometryNormalDepth, graph::Usage::ColorAttachment),
                    graph::writes(kGeometryIds, graph::Usage::ColorAttachment),
                    graph::writes(kGeometryDepth, graph::Usage::DepthAttachment)},
                   "rasterise normals, view depth and object/material ids for the geometric aamap"});
    gpu::GeometryPush push{};
    glm::mat4 reverse(1.0f);  // reversed depth, as GBufferPass
    reverse[2][2] = -1.0f;
    reverse[3][2] = 1.0f;
    push.viewProj = reverse * camera.projectionMatrix(nearPlane, farPlane) * camera.viewMatrix();
    push.cameraPos = glm::vec4(camera.origin, 1.0f);
    push.cameraForward = glm::vec4(camera.forward, 0.0f);
    executor.setRecord("geometry_buffer", [this, push](vk::PassContext& pc) {
        if (!prepared() || !pipeline_.handle())
            throw std::logic_error("GeometryBufferPass::prepare() was not called before execution");
        const vk::Image& normalDepth = pc.image(kGeometryNormalDepth);
        const vk::Image& z = pc.image(kGeometryDepth);
        const VkExtent2D extent{normalDepth.info().width, normalDepth.info().height};
        const VkRenderingAttachmentInfo colours[2] = {colourAttachment(normalDepth),
                                                      colourAttachment(pc.image(kGeometryIds))};
        VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthInfo.imageView = z.view();
        depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        depthInfo.clearValue.depthStencil = {0.0f, 0};
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 2;
        rendering.pColorAttachments = colours;
        rendering.pDepthAttachment = &depthInfo;
        VkCommandBuffer cmd = pc.cmd();
        vkCmdBeginRendering(cmd, &rendering);
        vk::setFullViewport(cmd, extent);
        if (vertexCount_ > 0) {
            pipeline_.bind(cmd);
            pipeline_.pushConstants(cmd, push);
            const VkBuffer vb = vertices_.handle();
            const VkDeviceSize offset = 0;
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
            vkCmdDraw(cmd, vertexCount_, 1, 0, 0);
        }
        vkCmdEndRendering(cmd);
    });
}

}  // namespace aamap::passes
