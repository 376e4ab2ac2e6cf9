#include "passes/blur.h"

#include <cstdint>
#include <vector>

#include <aamap/spirv.h>

#include "glsl/shared/aamap_filter.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

BlurPass::BlurPass(VulkanContext& context) : pass_(context, spirv::blur_comp, kBlurPass, AAMAP_FILTER_ROWS) {}

graph::PassId BlurPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                            const std::string& edges, const std::string& map, int radius, float noiseFloor,
                            float gain) const {
    gpu::FilterPush push{};
    push.noiseFloor = noiseFloor;
    push.gain = gain;
    std::vector<std::uint32_t> constants(1);
    constants[FILTER_SPEC_BLUR_RADIUS] = static_cast<std::uint32_t>(radius);
    return pass_.add(graph, executor, kBlurPass, edges, map, push,
                     "blur (the edges of the edge map alias too) and dead zone", constants);
}

}  // namespace aamap::passes
