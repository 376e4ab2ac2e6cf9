#pragma once
// Step 2 of the aamap: e = |5x5 Laplacian| of the grey image, 0 where the grey is flat
// (aamap_filter.h; R32F -> R32F).
#include <string>

#include "passes/filter_pass.h"

namespace aamap::passes {

class LaplacianPass {
public:
    explicit LaplacianPass(VulkanContext& context);
    // Declares the pass "laplacian" and registers its recording (this object must outlive execution).
    // flatRange 0: no flat gate.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& grey,
                      const std::string& edges, float flatRange) const;

private:
    FilterPass pass_;
};

}  // namespace aamap::passes
