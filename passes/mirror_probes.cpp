#include "passes/mirror_probes.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

#include <aamap/spirv.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"

namespace aamap::passes {
namespace {

// (sc, tc, ma) of r on face f as rows of coefficients: glsl/shadow_cube.glsl cubeFaceCoords.
struct FaceAxes {
    glm::vec3 sc, tc, ma;
};
constexpr FaceAxes kFaces[6] = {
    {{0, 0, -1}, {0, -1, 0}, {1, 0, 0}},  {{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}},
    {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}},    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},
    {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}},   {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}},
};

}  // namespace

glm::mat4 cubeFaceViewProjection(glm::vec3 centre, int face, float nearPlane) {
    const FaceAxes& a = kFaces[std::clamp(face, 0, 5)];
    glm::mat4 m(0.0f);  // m[column][row]
    const glm::vec3 rows[3] = {a.sc, a.tc, a.ma};
    const int rowIndex[3] = {0, 1, 3};
    for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) m[c][rowIndex[k]] = rows[k][c];
        m[3][rowIndex[k]] = -glm::dot(rows[k], centre);
    }
    m[3][2] = nearPlane;  // z = near, w = ma: depth near / ma, reversed, infinite far plane
    return m;
}

MirrorProbes::MirrorProbes(VulkanContext& context, const Scene& scene, const MirrorGroups& groups)
    : context_(&context) {
    const TriangleMesh& mesh = scene.mesh;
    const bool hasNormals = mesh.normals.size() == mesh.positions.size();
    for (const CurvedMirror& curved : groups.curved) {
        // The group's own corners, three per triangle: all that coverage and the draw need.
        Probe probe;
        probe.name = curved.group;
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const std::uint32_t t : curved.triangles) {
            const glm::uvec3 tri = mesh.triangles[t];
            const glm::vec3 face =
                glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x], mesh.positions[tri.z] - mesh.positions[tri.x]);
            const auto first = static_cast<std::uint32_t>(probe.corners.size());
            probe.cornerTriangles.push_back({first, first + 1, first + 2});
            probe.allTriangles.push_back(static_cast<std::uint32_t>(probe.allTriangles.size()));
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 p = mesh.positions[tri[k]];
                glm::vec3 n = hasNormals ? mesh.normals[tri[k]] : face;
                if (!(glm::dot(n, n) > 0.0f)) n = face;
                probe.corners.push_back(p);
                probe.vertices.push_back({p, n, curved.reflectance, 0.0f});
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
            }
        }
        probe.centre = 0.5f * (lo + hi);
        for (const glm::vec3& p : probe.corners) probe.radius = std::max(probe.radius, glm::length(p - probe.centre));
        if (!(probe.radius > 0.0f) || !std::isfinite(probe.radius)) continue;  // nothing to see from
        probes_.push_back(std::move(probe));
    }
    if (!probes_.empty()) unsupported_ = reflectedViewsUnsupported(context, kMirrorProbesPass);
}

std::vector<MirrorProbes::Selected> MirrorProbes::select(const SnapshotView& view, glm::uvec2 snapshotPixels) const {
    const glm::mat4 viewProj = view.reversedViewProjection();  // x, y and w as the plain projection's
    std::vector<Selected> selected;
    for (const Probe& p : probes_) {
        const double pixels =
            projectedPixels(p.corners, p.cornerTriangles, p.allTriangles, viewProj, view.nearPlane, snapshotPixels);
        if (pixels >= MirrorPass::kMinReflectedPixels) selected.push_back({&p, pixels});
    }
    std::stable_sort(selected.begin(), selected.end(),
                     [](const Selected& a, const Selected& b) { return a.pixels > b.pixels; });
    if (selected.size() > kMaxProbes) selected.resize(kMaxProbes);
    return selected;
}

bool MirrorProbes::anyInView(const SnapshotView& view, glm::uvec2 snapshotPixels) const {
    return any() && !select(view, snapshotPixels).empty();
}

void MirrorProbes::buildCompositePipeline() {
    if (compositePipeline_.handle()) return;
    vk::GraphicsDesc desc;
    desc.vertexSpirv = spirv::mirror_probe_vert;
    desc.fragmentSpirv = spirv::mirror_probe_frag;
    desc.vertexInput.stride = sizeof(Vertex);
    desc.vertexInput.attributes = {
        {MIRROR_PROBE_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
        {MIRROR_PROBE_LOCATION_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
        {MIRROR_PROBE_LOCATION_REFLECTANCE, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, reflectance)},
        {MIRROR_PROBE_LOCATION_LAYER, 0, VK_FORMAT_R32_SFLOAT, offsetof(Vertex, firstLayer)},
    };
    desc.colorFormats = {vk::toVkFormat(GBufferPass::kColourFormat)};
    desc.premultipliedBlend = true;  // alpha 0: added to what the G-buffer shaded
    static_assert(MIRROR_PROBE_BINDING_DEPTH == 0 && MIRROR_PROBE_BINDING_COLOUR == 1);
    compositePipeline_ = vk::Pipeline(
        *context_, desc,
        vk::LayoutDesc{{VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
                       static_cast<std::uint32_t>(sizeof(gpu::MirrorProbePush)),
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

void MirrorProbes::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, GBufferPass& gbuffer,
                       const std::string& snapshot, const std::string& depth, const SnapshotView& view,
                       glm::uvec2 snapshotPixels, const GBufferShadows& shadows, std::string* why) {
    const auto explain = [why](std::string text) {
        if (why) *why = std::move(text);
    };
    if (probes_.empty()) return explain("no probe pass: the scene has no curved mirror");
    if (!unsupported_.empty()) return explain("no probe pass: " + unsupported_);
    const std::vector<Selected> selected = select(view, snapshotPixels);
    if (selected.empty())
        return explain(fmt::format("no probe pass: none of the {} curved mirror group(s) covers {} snapshot pixels",
                                   probes_.size(), MirrorPass::kMinReflectedPixels));

    std::vector<ReflectedView> views;
    std::vector<Vertex> vertices;
    std::string names;
    for (std::size_t i = 0; i < selected.size(); ++i) {
        const Probe& p = *selected[i].probe;
        for (int face = 0; face < 6; ++face) {
            ReflectedView v;
            v.viewProj = cubeFaceViewProjection(p.centre, face, p.radius);
            v.eye = p.centre;
            v.clipPlane = glm::vec4(0.0f, 0.0f, 0.0f, -1.0f);  // 0 >= -1 everywhere: nothing clipped
            views.push_back(v);
        }
        for (Vertex v : p.vertices) {
            v.firstLayer = static_cast<float>(6 * i);
            vertices.push_back(v);
        }
        if (i < 4) names += fmt::format("{}'{}' ({:.0f} px)", i ? ", " : "", p.name, selected[i].pixels);
    }
    vertexCount_ = static_cast<std::uint32_t>(vertices.size());
    vertices_ = vk::uploadBuffer(*context_, std::as_bytes(std::span<const Vertex>(vertices)),
                                 VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    explain(fmt::format("{} curved mirror group(s) reflected through {}x{} cube probes: {}", selected.size(), kFaceSize,
                        kFaceSize, names));

    graph::ResourceDesc colour;
    colour.name = kMirrorProbeColour;
    colour.format = GBufferPass::kColourFormat;
    colour.size = graph::Size::absolute(kFaceSize, kFaceSize);
    colour.layers = static_cast<std::uint32_t>(views.size());
    graph.addResource(colour);
    graph::ResourceDesc probeDepth = colour;
    probeDepth.name = kMirrorProbeDepth;
    probeDepth.format = GBufferPass::kDepthFormat;
    graph.addResource(probeDepth);
    gbuffer.addReflected(graph, executor, kMirrorProbesPass, kMirrorProbeColour, kMirrorProbeDepth, views, shadows,
                         fmt::format("the scene seen from the centre of {} curved mirror group(s), 6 cube faces each: {}",
                                     selected.size(), names));

    gpu::MirrorProbePush push{};
    push.viewProj = view.reversedViewProjection();
    push.cameraPos = glm::vec4(view.camera.origin, static_cast<float>(kFaceSize));
    vk::PassDeclaration pass;
    pass.desc = {kMirrorProbeCompositePass,
                 graph::QueueKind::Graphics,
                 {graph::updates(snapshot, graph::Usage::ColorAttachment), graph::reads(depth, graph::Usage::Sampled),
                  graph::reads(kMirrorProbeColour, graph::Usage::Sampled)},
                 "add what each curved mirror's probe sees in the reflected direction, times its reflectance"};
    pass.prepare = [this] { buildCompositePipeline(); };
    pass.record = [this, snapshot, depth, push](vk::PassContext& pc) {
        const vk::Image& target = pc.image(snapshot);
        const VkExtent2D extent{target.info().width, target.info().height};
        VkCommandBuffer cmd = pc.cmd();
        vk::beginColourRendering(cmd, vk::loadedColourAttachment(target.view()), extent);  // add to the shading
        compositePipeline_.bind(cmd);
        vk::DescriptorPush()
            .sampledImage(MIRROR_PROBE_BINDING_DEPTH, pc.image(depth).view(), VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL)
            .sampledImage(MIRROR_PROBE_BINDING_COLOUR, pc.image(kMirrorProbeColour).view(),
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
            .push(*context_, cmd, compositePipeline_);
        compositePipeline_.pushConstants(cmd, push);
        const VkBuffer vb = vertices_.handle();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdDraw(cmd, vertexCount_, 1, 0, 0);
        vkCmdEndRendering(cmd);
    };
    vk::declarePass(graph, executor, std::move(pass));
}

}  // namespace aamap::passes
