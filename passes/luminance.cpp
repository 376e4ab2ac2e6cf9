#include "passes/luminance.h"

#include <aamap/spirv.h>

#include "passes/snapshot_graph.h"

namespace aamap::passes {

LuminancePass::LuminancePass(VulkanContext& context) : pass_(context, spirv::luminance_comp, kLuminancePass) {}

graph::PassId LuminancePass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                                 const std::string& colour, const std::string& grey, float exposure) const {
    gpu::FilterPush push{};
    push.exposure = exposure;
    return pass_.add(graph, executor, kLuminancePass, colour, grey, push,
                     "greyscale of the snapshot for the edge filter (in a Snapshot only after something "
                     "changes the snapshot past the opaque draw, a mirror composite or glass: otherwise the "
                     "G-buffer writes it)");
}

}  // namespace aamap::passes
