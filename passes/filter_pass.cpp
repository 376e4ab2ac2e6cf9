#include "passes/filter_pass.h"

#include <utility>

#include "engine/vk/context.h"
#include "glsl/shared/aamap_filter.h"

namespace aamap::passes {

FilterPass::FilterPass(VulkanContext& context, std::span<const std::uint32_t> spirv, std::string kind,
                       std::uint32_t rowsPerInvocation)
    : context_(&context), spirv_(spirv), kind_(std::move(kind)), rowsPerInvocation_(rowsPerInvocation) {}

graph::PassId FilterPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& name,
                              const std::string& input, const std::string& output, const gpu::FilterPush& push,
                              std::string purpose, const std::vector<std::uint32_t>& constants) const {
    vk::Pipeline& pipeline = pipelines_[constants];  // built only if the graph keeps the pass
    vk::PassDeclaration pass;
    pass.desc = {name,
                 graph::QueueKind::Compute,
                 {graph::reads(input, graph::Usage::StorageRead),
                  graph::writes(output, graph::Usage::StorageWrite)},
                 std::move(purpose)};
    pass.prepare = [this, &pipeline, constants] {
        if (!pipeline.handle())
            pipeline = vk::Pipeline(*context_, spirv_,
                                    vk::LayoutDesc{{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                                   static_cast<std::uint32_t>(sizeof(gpu::FilterPush)),
                                                   VK_SHADER_STAGE_COMPUTE_BIT},
                                    constants);
    };
    pass.record = [this, input, output, push, &pipeline](vk::PassContext& pc) {
        const vk::Image& in = pc.image(input);
        const vk::Image& out = pc.image(output);
        gpu::FilterPush values = push;
        values.inSize = {static_cast<int>(in.info().width), static_cast<int>(in.info().height)};
        values.outSize = {static_cast<int>(out.info().width), static_cast<int>(out.info().height)};
        pipeline.bind(pc.cmd());
        vk::DescriptorPush()
            .storageImage(FILTER_BINDING_INPUT, in.view())
            .storageImage(FILTER_BINDING_OUTPUT, out.view())
            .push(*context_, pc.cmd(), pipeline);
        pipeline.pushConstants(pc.cmd(), values);
        const std::uint32_t strips = (out.info().height + rowsPerInvocation_ - 1) / rowsPerInvocation_;
        vk::dispatch2D(pc.cmd(), out.info().width, strips, AAMAP_FILTER_GROUP_X, AAMAP_FILTER_GROUP_Y);
    };
    const graph::PassId id = vk::declarePass(graph, executor, std::move(pass));
    return id;
}

}  // namespace aamap::passes
