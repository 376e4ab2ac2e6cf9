#include "passes/geometric_aamap.h"

#include <cstring>
#include <stdexcept>

#include <aamap/spirv.h>

#include "engine/vk/context.h"
#include "glsl/shared/aamap_filter.h"
#include "glsl/shared/snapshot_interface.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {
namespace {

vk::Pipeline edgePipeline(VulkanContext& context, bool combined) {
    std::vector<VkDescriptorType> bindings(combined ? 4 : 3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
    static_assert(GEOMETRIC_BINDING_NORMAL_DEPTH == 0 && GEOMETRIC_BINDING_IDS == 1 &&
                  GEOMETRIC_BINDING_OUTPUT == 2 && GEOMETRIC_BINDING_LAPLACIAN == 3);
    return vk::Pipeline(context, combined ? spirv::geometric_edges_combined_comp : spirv::geometric_edges_comp,
                        vk::LayoutDesc{bindings, static_cast<std::uint32_t>(sizeof(gpu::FilterPush)),
                                       VK_SHADER_STAGE_COMPUTE_BIT});
}

std::vector<std::byte> toRGBA32(const Image<glm::vec4>& image) {
    std::vector<std::byte> bytes(image.size() * sizeof(glm::vec4));
    std::memcpy(bytes.data(), image.data(), bytes.size());
    return bytes;
}

graph::Size sizeOf(int width, int height) {
    return graph::Size::absolute(static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height));
}

}  // namespace

GeometricEdgePass::GeometricEdgePass(VulkanContext& context)
    : context_(&context) {}

graph::PassId GeometricEdgePass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                                     const std::string& normalDepth, const std::string& ids,
                                     const std::string& laplacian, const std::string& output) const {
    const bool combined = !laplacian.empty();
    std::vector<graph::Access> accesses{graph::reads(normalDepth, graph::Usage::StorageRead),
                                        graph::reads(ids, graph::Usage::StorageRead),
                                        graph::writes(output, graph::Usage::StorageWrite)};
    if (combined) accesses.push_back(graph::reads(laplacian, graph::Usage::StorageRead));
    vk::PassDeclaration pass;
    pass.desc = {kGeometricEdgesPass, graph::QueueKind::Compute, accesses,
                 combined ? "edges: max of G-buffer discontinuities and the luminance |L|"
                          : "edges: G-buffer discontinuities (depth, normal, object and material id, shadow mask)"};
    pass.prepare = [this, combined] {
        vk::Pipeline& pipeline = combined ? combined_ : geometric_;
        if (!pipeline.handle()) pipeline = edgePipeline(*context_, combined);
    };
    pass.record = [this, normalDepth, ids, laplacian, output, combined](vk::PassContext& pc) {
        const vk::Image& out = pc.image(output);
        gpu::FilterPush push{};
        push.inSize = {static_cast<int>(out.info().width), static_cast<int>(out.info().height)};
        push.outSize = push.inSize;
        const vk::Pipeline& pipeline = combined ? combined_ : geometric_;
        pipeline.bind(pc.cmd());
        vk::DescriptorPush descriptors;
        descriptors.storageImage(GEOMETRIC_BINDING_NORMAL_DEPTH, pc.image(normalDepth).view())
            .storageImage(GEOMETRIC_BINDING_IDS, pc.image(ids).view())
            .storageImage(GEOMETRIC_BINDING_OUTPUT, out.view());
        if (combined) descriptors.storageImage(GEOMETRIC_BINDING_LAPLACIAN, pc.image(laplacian).view());
        descriptors.push(*context_, pc.cmd(), pipeline);
        pipeline.pushConstants(pc.cmd(), push);
        vk::dispatch2D(pc.cmd(), out.info().width, out.info().height, AAMAP_FILTER_GROUP_X, AAMAP_FILTER_GROUP_Y);
    };
    const graph::PassId id = vk::declarePass(graph, executor, std::move(pass));
    return id;
}

void addAamapChain(graph::RenderGraph& graph, vk::GraphExecutor& executor, const FilterChain& chain,
                   GeometryBufferPass& geometry, const GeometricEdgePass& edges, const SubpixelMapPass& subpixel,
                   AamapSource source, const MapChainInputs& in) {
    if (source == AamapSource::Subpixel) {
        // k x the render resolution, whatever the colour's (one shade per pixel, or per sample).
        const auto k = static_cast<std::uint32_t>(in.subpixel.k);
        geometry.add(graph, executor,
                     graph::Size::absolute(k * static_cast<std::uint32_t>(in.width),
                                           k * static_cast<std::uint32_t>(in.height)),
                     in.view);
        graph.addResource(graph::imageResource(kAamap, graph::Format::R32Float, sizeOf(in.width, in.height)));
        subpixel.add(graph, executor, in.colour, kGeometryNormalDepth, kGeometryIds, kAamap, in.subpixel);
        return;
    }
    geometry.add(graph, executor, graph::Size::relative(in.colour), in.view, in.shadows);
    graph.addResource(graph::imageResource(kEdges, graph::Format::R32Float, graph::Size::relative(in.colour)));
    if (source == AamapSource::Luminance) {
        chain.add(graph, executor, in.colour, in.width, in.height, in.params, in.greyFromGBuffer);
        // Declared for the explanation only: nothing reads kEdges, so the graph culls both.
        edges.add(graph, executor, kGeometryNormalDepth, kGeometryIds, "", kEdges);
        return;
    }
    // The Laplacian stays declared for the geometric map: a debug output only (the combined map reads it).
    const bool combined = source == AamapSource::Combined;
    chain.add(graph, executor, in.colour, in.width, in.height, in.params, in.greyFromGBuffer,
              [&executor, &edges, combined](graph::RenderGraph& g) {
                  edges.add(g, executor, kGeometryNormalDepth, kGeometryIds, combined ? kLaplacian : "", kEdges);
                  return std::string(kEdges);
              });
}

GpuGeometricEdges::GpuGeometricEdges(VulkanContext& context)
    : pass_(context), executor_(std::make_unique<vk::GraphExecutor>(context)) {}
GpuGeometricEdges::~GpuGeometricEdges() = default;

ImageGrey GpuGeometricEdges::edges(const cpu::GeometryImages& g, const ImageGrey* laplacian) {
    const int W = g.normalDepth.width(), H = g.normalDepth.height();
    if (W <= 0 || H <= 0 || g.ids.width() != W || g.ids.height() != H ||
        (laplacian != nullptr && (laplacian->width() != W || laplacian->height() != H)))
        throw std::invalid_argument("GpuGeometricEdges: empty or mismatched images");
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(graph::imageResource(kGeometryNormalDepth, graph::Format::RGBA32Float, sizeOf(W, H), true));
    graph.addResource(graph::imageResource(kGeometryIds, graph::Format::RGBA32Float, sizeOf(W, H), true));
    graph.addResource(graph::imageResource(kEdges, graph::Format::R32Float, sizeOf(W, H)));
    executor_->setUpload(kGeometryNormalDepth, toRGBA32(g.normalDepth));
    executor_->setUpload(kGeometryIds, toRGBA32(g.ids));
    if (laplacian != nullptr) {
        graph.addResource(graph::imageResource(kLaplacian, graph::Format::R32Float, sizeOf(W, H), true));
        executor_->setUpload(kLaplacian, toR32(*laplacian));
    }
    pass_.add(graph, *executor_, kGeometryNormalDepth, kGeometryIds, laplacian != nullptr ? kLaplacian : "", kEdges);
    const std::vector<std::string> outputs{kEdges};
    const vk::ExecutionResult r = executor_->execute(graph.compile(outputs));
    executor_->clear();
    return toImageGrey(r.outputs.at(kEdges));
}

}  // namespace aamap::passes
