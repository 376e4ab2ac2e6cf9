#include "passes/laplacian.h"

#include <aamap/spirv.h>

#include "glsl/shared/aamap_filter.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

LaplacianPass::LaplacianPass(VulkanContext& context)
    : pass_(context, spirv::laplacian_comp, kLaplacianPass, AAMAP_FILTER_ROWS) {}

graph::PassId LaplacianPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& grey,
                                 const std::string& edges, float flatRange) const {
    gpu::FilterPush push{};
    push.flatRange = flatRange;
    return pass_.add(graph, executor, kLaplacianPass, grey, edges, push,
                     "5x5 Laplacian: the edges to antialias, where the grey is not flat");
}

}  // namespace aamap::passes
