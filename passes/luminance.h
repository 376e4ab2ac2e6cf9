#pragma once
// Step 1 of the aamap: display-encoded luma of the snapshot colour (RGBA32F -> R32F).
#include <string>

#include "passes/filter_pass.h"

namespace aamap::passes {

class LuminancePass {
public:
    explicit LuminancePass(VulkanContext& context);
    // Declares the pass "luminance" and registers its recording (this object must outlive execution).
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                      const std::string& colour, const std::string& grey, float exposure) const;

private:
    FilterPass pass_;
};

}  // namespace aamap::passes
