#pragma once
// Step 2 of the aamap: e = |5x5 Laplacian| of the grey image (R32F -> R32F).
#include <string>

#include "passes/filter_pass.h"

namespace aamap::passes {

class LaplacianPass {
public:
    explicit LaplacianPass(VulkanContext& context);
    // Declares the pass "laplacian" and registers its recording (this object must outlive execution).
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                      const std::string& grey, const std::string& edges) const;

private:
    FilterPass pass_;
};

}  // namespace aamap::passes
