#pragma once
// A compute pass of the aamap filter chain: one storage image in, one r32f storage image out,
// FilterPush constants and, for shaders that declare them, specialisation constants. The concrete
// passes (luminance, laplacian, blur, reduce) only choose the shader and the constants.
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "glsl/shared/snapshot_interface.h"

namespace aamap::passes {

class FilterPass {
public:
    // rowsPerInvocation: output rows each invocation computes (the dispatch covers the output
    // height divided by it), as the shader was written for.
    FilterPass(VulkanContext& context, std::span<const std::uint32_t> spirv, std::string kind,
               std::uint32_t rowsPerInvocation = 1);

    // Declares pass `name` (reads `input` as StorageRead, writes `output` as StorageWrite) and
    // registers its recording. inSize/outSize of `push` are filled from the live images;
    // `constants` are the shader's specialisation constants (a pipeline is built per distinct
    // list, on first use). The FilterPass must outlive the graph's execution.
    graph::PassId add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& name,
                      const std::string& input, const std::string& output, const gpu::FilterPush& push,
                      std::string purpose, const std::vector<std::uint32_t>& constants = {}) const;

    const std::string& kind() const { return kind_; }

private:
    VulkanContext* context_;
    std::span<const std::uint32_t> spirv_;
    // Per specialisation: a cache behind the const interface; std::map keeps the references that
    // recordings hold valid.
    mutable std::map<std::vector<std::uint32_t>, vk::Pipeline> pipelines_;
    std::string kind_;
    std::uint32_t rowsPerInvocation_;
};

}  // namespace aamap::passes
