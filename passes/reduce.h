#pragma once
// The aamap reduction: conservative max over overlapping footprints, snapshot -> render size.
#include <string>

#include "passes/filter_pass.h"

namespace aamap::passes {

class ReducePass {
public:
    explicit ReducePass(VulkanContext& context);
    // Declares the pass "reduce" and registers its recording (this object must outlive execution).
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                      const std::string& map, const std::string& aamap) const;

private:
    FilterPass pass_;
};

}  // namespace aamap::passes
