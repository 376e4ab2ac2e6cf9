#pragma once
// Steps 3 and 4 of the aamap, fused: box blur of the edges, then the dead zone (R32F -> R32F).
#include <string>

#include "passes/filter_pass.h"

namespace aamap::passes {

class BlurPass {
public:
    explicit BlurPass(VulkanContext& context);
    // Declares the pass "blur" and registers its recording (this object must outlive execution).
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                      const std::string& edges, const std::string& map, int radius, float noiseFloor,
                      float gain) const;

private:
    FilterPass pass_;
};

}  // namespace aamap::passes
