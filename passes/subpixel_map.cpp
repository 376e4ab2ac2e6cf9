#include "passes/subpixel_map.h"

#include <cstring>
#include <stdexcept>

#include <aamap/spirv.h>

#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"
#include "glsl/shared/subpixel_map.h"
#include "passes/gpu_aamap.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {
namespace {

graph::Size sizeOf(int width, int height) {
    return graph::Size::absolute(static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height));
}

std::vector<std::byte> toRGBA32(const Image<glm::vec4>& image) {
    std::vector<std::byte> bytes(image.size() * sizeof(glm::vec4));
    std::memcpy(bytes.data(), image.data(), bytes.size());
    return bytes;
}

}  // namespace

SubpixelMapPass::SubpixelMapPass(VulkanContext& context) : context_(&context) {}

graph::PassId SubpixelMapPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                                   const std::string& normalDepth, const std::string& ids, const std::string& output,
                                   const SubpixelSettings& settings) const {
    if (settings.k < SUBPIXEL_MIN_K || settings.k > SUBPIXEL_MAX_K)
        throw std::invalid_argument("SubpixelSettings::k must be in [2, 4], got " + std::to_string(settings.k));
    const int k = settings.k;
    const int shared = settings.shared ? 1 : 0;
    const auto push = [settings](const vk::Image& out) {
        gpu::SubpixelPush p{};
        p.outSize = {static_cast<int>(out.info().width), static_cast<int>(out.info().height)};
        p.k = settings.k;
        p.exposure = settings.exposure;
        p.tolerance = settings.tolerance;
        return p;
    };
    const auto build = [this](vk::Pipeline& pipeline, std::span<const std::uint32_t> code, int bindings,
                              std::vector<std::uint32_t> constants) {
        if (pipeline.handle()) return;
        pipeline = vk::Pipeline(*context_, code,
                                vk::LayoutDesc{std::vector<VkDescriptorType>(static_cast<std::size_t>(bindings),
                                                                             VK_DESCRIPTOR_TYPE_STORAGE_IMAGE),
                                               static_cast<std::uint32_t>(sizeof(gpu::SubpixelPush)),
                                               VK_SHADER_STAGE_COMPUTE_BIT},
                                constants);
    };
    // The render-resolution flags image is sized like the map.
    graph.addResource(graph::imageResource(kSubpixelGeometry, graph::Format::R32Float, graph::Size::relative(output)));

    vk::PassDeclaration geometry;
    geometry.desc = {kSubpixelGeometryPass, graph::QueueKind::Compute,
                     {graph::reads(normalDepth, graph::Usage::StorageRead), graph::reads(ids, graph::Usage::StorageRead),
                      graph::writes(kSubpixelGeometry, graph::Usage::StorageWrite)},
                     "aamap: which pixels' k x k geometry samples differ, inside and across each border"};
    geometry.prepare = [this, k, build] {
        std::vector<std::uint32_t> constants(SUBPIXEL_SPEC_K + 1, 0u);
        constants[SUBPIXEL_SPEC_K] = static_cast<std::uint32_t>(k);
        build(geometry_[k], spirv::subpixel_geometry_comp, 3, constants);
    };
    // Both passes bind two images read and the one written, at bindings 0, 1 and 2, and run one
    // invocation per render pixel.
    static_assert(SUBPIXEL_GEOMETRY_BINDING_NORMAL_DEPTH == 0 && SUBPIXEL_GEOMETRY_BINDING_IDS == 1 &&
                  SUBPIXEL_GEOMETRY_BINDING_OUTPUT == 2 && SUBPIXEL_BINDING_COLOUR == 0 &&
                  SUBPIXEL_BINDING_GEOMETRY == 1 && SUBPIXEL_BINDING_OUTPUT == 2);
    const auto dispatch = [this, push](vk::PassContext& pc, const vk::Pipeline& pipeline, const std::string& a,
                                       const std::string& b, const std::string& output) {
        const vk::Image& out = pc.image(output);
        pipeline.bind(pc.cmd());
        vk::DescriptorPush descriptors;
        descriptors.storageImage(0, pc.image(a).view()).storageImage(1, pc.image(b).view()).storageImage(2, out.view());
        descriptors.push(*context_, pc.cmd(), pipeline);
        pipeline.pushConstants(pc.cmd(), push(out));
        vk::dispatch2D(pc.cmd(), out.info().width, out.info().height, SUBPIXEL_GROUP_X, SUBPIXEL_GROUP_Y);
    };
    geometry.record = [this, normalDepth, ids, dispatch, k](vk::PassContext& pc) {
        dispatch(pc, geometry_[k], normalDepth, ids, kSubpixelGeometry);
    };
    vk::declarePass(graph, executor, std::move(geometry));

    vk::PassDeclaration pass;
    pass.desc = {kSubpixelMapPass, graph::QueueKind::Compute,
                 {graph::reads(colour, graph::Usage::StorageRead),
                  graph::reads(kSubpixelGeometry, graph::Usage::StorageRead),
                  graph::writes(output, graph::Usage::StorageWrite)},
                 shared ? "aamap: each pixel's predicted one-ray display error from its k x k geometry samples and "
                          "the shades of it and its neighbours"
                        : "aamap: each pixel's predicted one-ray display error from its k x k samples"};
    pass.prepare = [this, k, shared, build] {
        std::vector<std::uint32_t> constants(SUBPIXEL_SPEC_SHARED + 1, 0u);
        constants[SUBPIXEL_SPEC_K] = static_cast<std::uint32_t>(k);
        constants[SUBPIXEL_SPEC_SHARED] = static_cast<std::uint32_t>(shared);
        build(pipelines_[k][shared], spirv::subpixel_map_comp, 3, constants);
    };
    pass.record = [this, colour, output, dispatch, k, shared](vk::PassContext& pc) {
        dispatch(pc, pipelines_[k][shared], colour, kSubpixelGeometry, output);
    };
    return vk::declarePass(graph, executor, std::move(pass));
}

GpuSubpixelMap::GpuSubpixelMap(VulkanContext& context)
    : pass_(context), executor_(std::make_unique<vk::GraphExecutor>(context)) {}
GpuSubpixelMap::~GpuSubpixelMap() = default;

ImageGrey GpuSubpixelMap::map(const ImageRGB& colour, const cpu::GeometryImages& g, const SubpixelSettings& settings) {
    const int Ws = g.normalDepth.width(), Hs = g.normalDepth.height(), k = settings.k;
    const int colourScale = settings.shared ? 1 : k;
    if (Ws <= 0 || Hs <= 0 || k <= 0 || Ws % k != 0 || Hs % k != 0 || colour.width() * k != Ws * colourScale ||
        colour.height() * k != Hs * colourScale || g.ids.width() != Ws || g.ids.height() != Hs)
        throw std::invalid_argument("GpuSubpixelMap: empty or mismatched images, or a size not a multiple of k");
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(
        graph::imageResource("colour", graph::Format::RGBA32Float, sizeOf(colour.width(), colour.height()), true));
    graph.addResource(graph::imageResource(kGeometryNormalDepth, graph::Format::RGBA32Float, sizeOf(Ws, Hs), true));
    graph.addResource(graph::imageResource(kGeometryIds, graph::Format::RGBA32Float, sizeOf(Ws, Hs), true));
    graph.addResource(graph::imageResource(kAamap, graph::Format::R32Float, sizeOf(Ws / k, Hs / k)));
    executor_->setUpload("colour", passes::toRGBA32(colour));
    executor_->setUpload(kGeometryNormalDepth, toRGBA32(g.normalDepth));
    executor_->setUpload(kGeometryIds, toRGBA32(g.ids));
    pass_.add(graph, *executor_, "colour", kGeometryNormalDepth, kGeometryIds, kAamap, settings);
    const std::vector<std::string> outputs{kAamap};
    const vk::ExecutionResult r = executor_->execute(graph.compile(outputs));
    executor_->clear();
    return toImageGrey(r.outputs.at(kAamap));
}

}  // namespace aamap::passes
