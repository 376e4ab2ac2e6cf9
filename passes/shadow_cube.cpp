#include "passes/shadow_cube.h"

#include <algorithm>
#include <stdexcept>

#include <aamap/spirv.h>
#include <fmt/format.h>

#include "core/error.h"
#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"

namespace aamap::passes {

ShadowCubePass::ShadowCubePass(VulkanContext& context) : context_(&context) {
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    vkGetPhysicalDeviceFeatures2(context.physicalDevice(), &f2);
    if (!f12.shaderOutputLayer)
        throw EnvironmentError(fmt::format("'{}' lacks shaderOutputLayer (Vulkan 1.2), which the shadow cube maps "
                                           "need; turn snapshot shadows off",
                                           context.deviceName()));
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(context.physicalDevice(), &props);
    maxLayers_ = std::min(props.limits.maxFramebufferLayers, props.limits.maxImageArrayLayers);
}

void ShadowCubePass::buildPipeline(const SceneGpu& scene) const {
    const bool masked = scene.alphaMasked();  // else sharedPositions(), or nothing to draw
    vk::Pipeline& pipeline = pipelineSlot(scene);
    if (pipeline.handle()) return;
    vk::GraphicsDesc desc;
    desc.vertexSpirv = masked ? spirv::shadow_cube_masked_vert : spirv::shadow_cube_vert;
    desc.fragmentSpirv = masked ? spirv::shadow_cube_masked_frag : spirv::shadow_cube_frag;
    // Masked: the scene's full vertices, position at 0; else the shared positions.
    desc.vertexInput.stride = masked ? scene.vertexStride() : static_cast<std::uint32_t>(sizeof(glm::vec3));
    desc.vertexInput.attributes = {{SHADOW_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    std::vector<VkDescriptorType> bindings{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER};
    static_assert(SHADOW_BINDING_LIGHTS == 0 && SHADOW_BINDING_ATLAS == 1);
    if (masked) {
        desc.vertexInput.attributes.push_back(
            {SHADOW_LOCATION_UV, 0, VK_FORMAT_R32G32_SFLOAT, SceneGpu::kUvOffset});
        desc.vertexInput.attributes.push_back(
            {SHADOW_LOCATION_TEX_RECT, 0, VK_FORMAT_R16G16B16A16_UINT, SceneGpu::kTexRectOffset});
        desc.vertexInput.attributes.push_back(
            {SHADOW_LOCATION_TEX_PARAMS, 0, VK_FORMAT_R32G32_SFLOAT, SceneGpu::kTexParamsOffset});
        bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);
    }
    desc.depthFormat = vk::toVkFormat(kFormat);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed: near/ma, nearer is larger
    pipeline = vk::Pipeline(*context_, desc,
                            vk::LayoutDesc{bindings, static_cast<std::uint32_t>(sizeof(gpu::ShadowPush)),
                                           static_cast<VkShaderStageFlags>(
                                               masked ? VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT
                                                      : VK_SHADER_STAGE_VERTEX_BIT)});
}

ShadowCubePass::FaceLists ShadowCubePass::cullPerFace(std::span<const glm::vec3> positions,
                                                     std::span<const glm::vec3> lights, float nearPlane,
                                                     std::span<const std::uint8_t> directional) {
    FaceLists lists;
    const std::size_t triangles = positions.size() / 3;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const glm::vec3& light = lights[l];
        std::vector<std::uint32_t> faces[6];
        if (l < directional.size() && directional[l] != 0) {
            // The orthographic map covers the whole mesh: every triangle, on face 0 only.
            for (std::size_t t = 0; t < triangles; ++t) {
                const auto first = static_cast<std::uint32_t>(3 * t);
                faces[0].insert(faces[0].end(), {first, first + 1, first + 2});
            }
        }
        for (std::size_t t = 0; t < triangles && !(l < directional.size() && directional[l] != 0); ++t) {
            glm::vec3 r[3];
            for (int k = 0; k < 3; ++k) r[k] = positions[3 * t + static_cast<std::size_t>(k)] - light;
            for (int f = 0; f < 6; ++f) {
                const int axis = f >> 1, b = (axis + 1) % 3, c = (axis + 2) % 3;
                const float sign = (f & 1) ? -1.0f : 1.0f;
                // The pyramid: major >= |r_b|, major >= |r_c|, major >= near; culled when all three
                // vertices fail one of these five half-spaces.
                int out[5] = {0, 0, 0, 0, 0};
                for (const glm::vec3& v : r) {
                    const float major = sign * v[axis];
                    out[0] += major < v[b];
                    out[1] += major < -v[b];
                    out[2] += major < v[c];
                    out[3] += major < -v[c];
                    out[4] += major < nearPlane;
                }
                if (out[0] == 3 || out[1] == 3 || out[2] == 3 || out[3] == 3 || out[4] == 3) continue;
                const auto first = static_cast<std::uint32_t>(3 * t);
                faces[f].insert(faces[f].end(), {first, first + 1, first + 2});
            }
        }
        for (const auto& face : faces) {
            lists.ranges.emplace_back(static_cast<std::uint32_t>(lists.indices.size()),
                                      static_cast<std::uint32_t>(face.size()));
            lists.indices.insert(lists.indices.end(), face.begin(), face.end());
        }
    }
    return lists;
}

void ShadowCubePass::updateFaceLists(const SceneGpu& scene, float nearPlane, const ViewFrustum* view,
                                     std::span<const float> cullRadii) {
    if (listsScene_ != &scene || listsVersion_ != scene.lightsVersion() || listsNear_ != nearPlane) {
        baseLists_ = cullPerFace(scene.vertexPositions(), scene.lightPositions(), nearPlane, scene.lightDirectional());
        listsScene_ = &scene;
        listsVersion_ = scene.lightsVersion();
        listsNear_ = nearPlane;
        viewListsValid_ = false;
    }
    const bool culled = view != nullptr;
    if (viewListsValid_ && listsCulled_ == culled && (!culled || (listsView_ == *view &&
                                                                  std::equal(cullRadii.begin(), cullRadii.end(),
                                                                             listsRadii_.begin(), listsRadii_.end()))))
        return;
    FaceLists lists;
    if (!culled) {
        lists = baseLists_;
    } else {
        const std::span<const glm::vec3> positions = scene.vertexPositions();
        const std::span<const glm::vec3> lights = scene.lightPositions();
        const std::span<const std::uint8_t> directional = scene.lightDirectional();
        lists.indices.reserve(baseLists_.indices.size());
        for (std::size_t layer = 0; layer < baseLists_.ranges.size(); ++layer) {
            const std::size_t light = layer / 6;
            const auto [first, count] = baseLists_.ranges[layer];
            const auto begin = static_cast<std::uint32_t>(lists.indices.size());
            const std::span<const std::uint32_t> face(baseLists_.indices.data() + first, count);
            if (light < directional.size() && directional[light] != 0) {
                lists.indices.insert(lists.indices.end(), face.begin(), face.end());  // at infinity: all of it
            } else {
                const float radius = light < cullRadii.size() ? cullRadii[light] : 0.0f;
                cullShadowCasters(positions, face, lights[light], radius, *view, lists.indices);
            }
            lists.ranges.emplace_back(begin, static_cast<std::uint32_t>(lists.indices.size()) - begin);
        }
        listsView_ = *view;
        listsRadii_.assign(cullRadii.begin(), cullRadii.end());
    }
    if (scene.sharedPositions()) {
        const std::span<const std::uint32_t> shared = scene.positionIndex();
        for (std::uint32_t& i : lists.indices) i = shared[i];
    }
    faceRanges_ = std::move(lists.ranges);
    if (lists.indices.empty()) lists.indices.push_back(0);  // a buffer needs a size; no range reads it
    faceIndices_ = vk::uploadBuffer(*context_, std::as_bytes(std::span<const std::uint32_t>(lists.indices)),
                                    VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    viewListsValid_ = true;
    listsCulled_ = culled;
}

graph::PassId ShadowCubePass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& resource,
                                  const SceneGpu& scene, std::span<const std::string> lightNames,
                                  std::uint32_t faceSize, float nearPlane, const ViewFrustum* view,
                                  std::span<const float> cullRadii) {
    const auto lights = static_cast<std::uint32_t>(lightNames.size());
    if (lights == 0 || lights != scene.lightCount())
        throw std::logic_error("ShadowCubePass::add: one name per light of the scene, and at least one");
    const std::uint32_t layers = 6 * lights;
    if (layers > maxLayers_)
        throw std::invalid_argument(fmt::format("{} shadow cube maps need {} layers; '{}' allows {}: fewer lights or "
                                                "area-light samples, or shadows off",
                                                lights, layers, context_->deviceName(), maxLayers_));
    // Each light's faces fill the top-left faceSizes[i]^2 of its layers (by need, passes/view_budget.h);
    // the receivers read the same corner (GpuLight::position.w).
    const std::span<const std::uint32_t> faceSizes = scene.shadowFaceSizes();
    std::vector<std::uint32_t> layerSizes;
    for (const std::uint32_t size : faceSizes) {
        if (size < 1 || size > faceSize)
            throw std::logic_error(fmt::format("ShadowCubePass::add: a light's face size {} outside [1, {}] (set "
                                               "SceneGpu::setShadowFaceSizes first)",
                                               size, faceSize));
        layerSizes.insert(layerSizes.end(), 6, size);
    }
    graph::ResourceDesc desc;
    desc.name = resource;
    desc.format = kFormat;
    desc.size = graph::Size::absolute(faceSize, faceSize);
    desc.layers = layers;  // an array, not `cube`: the receiver picks faces itself (texelFetch)
    graph.addResource(desc);

    std::uint64_t kept = 0;
    if (scene.occluderVertexCount() > 0) {
        updateFaceLists(scene, nearPlane, view, cullRadii);
        for (const auto& range : faceRanges_) kept += range.second;
    }
    const std::uint32_t occluders = scene.occluderVertexCount();
    const double keptShare = occluders > 0 ? static_cast<double>(kept) / (6.0 * lights * occluders) : 0.0;
    std::string names;
    for (std::uint32_t i = 0; i < lights && i < 6; ++i)
        names += fmt::format("{}'{}' {}^2", i ? ", " : "", lightNames[i], faceSizes[i]);
    if (lights > 6) names += fmt::format(", ... ({} more)", lights - 6);
    gpu::ShadowPush push{};
    push.nearPlane = nearPlane;
    const vk::Pipeline& pipeline = pipelineSlot(scene);
    vk::PassDeclaration pass;
    pass.desc = {kShadowPass, graph::QueueKind::Graphics, {graph::writes(resource, graph::Usage::DepthAttachment)},
                 fmt::format("shadow cube maps (at most {}^2 per face, each light's by need, 6 layers each; a "
                             "directional light's orthographic map fills the first) for {} light{}: {}; per-face "
                             "culling draws {:.1f}% of triangles x faces{}{}",
                             faceSize, lights, lights == 1 ? "" : "s", names, 100.0 * keptShare,
                             view != nullptr ? " (those that can shadow a point in view)" : "",
                             scene.alphaMasked() ? "; alpha test from the texture atlas (the scene has masks)" : "")};
    pass.prepare = [this, &scene] { buildPipeline(scene); };
    pass.record = [this, &scene, &pipeline, resource, push, layers, layerSizes](vk::PassContext& pc) {
        const vk::Image& target = pc.image(resource);
        const VkExtent2D extent{target.info().width, target.info().height};
        VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthInfo.imageView = target.view();
        depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        depthInfo.clearValue.depthStencil = {0.0f, 0};  // near/ma = 0: nothing in the way
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = layers;
        rendering.pDepthAttachment = &depthInfo;

        VkCommandBuffer cmd = pc.cmd();
        vkCmdBeginRendering(cmd, &rendering);
        vk::setFullViewport(cmd, extent);
        if (scene.occluderVertexCount() > 0) {
            pipeline.bind(cmd);
            vk::DescriptorPush descriptors;
            descriptors.uniformBuffer(SHADOW_BINDING_LIGHTS, scene.lightBuffer().handle());
            if (scene.alphaMasked())
                descriptors.sampledImage(SHADOW_BINDING_ATLAS, scene.atlas().view(),
                                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            descriptors.push(*context_, cmd, pipeline);
            pipeline.pushConstants(cmd, push);
            const VkBuffer vb = scene.sharedPositions() ? scene.positionBuffer().handle() : scene.vertexBuffer().handle();
            const VkDeviceSize offset = 0;
            vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
            vkCmdBindIndexBuffer(cmd, faceIndices_.handle(), 0, VK_INDEX_TYPE_UINT32);
            std::uint32_t viewportSize = extent.width;
            for (std::uint32_t layer = 0; layer < layers; ++layer) {  // gl_InstanceIndex = layer: face f of light i
                const auto [first, count] = faceRanges_[layer];
                if (count == 0) continue;
                const VkExtent2D face{layerSizes[layer], layerSizes[layer]};
                if (face.width != viewportSize) vk::setFullViewport(cmd, face);
                viewportSize = face.width;
                vkCmdDrawIndexed(cmd, count, 1, first, 0, layer);
            }
        }
        vkCmdEndRendering(cmd);
    };
    const graph::PassId id = vk::declarePass(graph, executor, std::move(pass));
    return id;
}

}  // namespace aamap::passes
