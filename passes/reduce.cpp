#include "passes/reduce.h"

#include <aamap/spirv.h>

#include "passes/snapshot_graph.h"

namespace aamap::passes {

ReducePass::ReducePass(VulkanContext& context) : pass_(context, spirv::reduce_comp, kReducePass) {}

graph::PassId ReducePass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                              const std::string& map, const std::string& aamap) const {
    return pass_.add(graph, executor, kReducePass, map, aamap, gpu::FilterPush{},
                     "reduce to the render resolution");
}

}  // namespace aamap::passes
