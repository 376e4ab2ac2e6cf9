#pragma once
// The block-sum reduction of the aamap for adaptive subsampling: two compute passes that build
// the summed-area tables of tracer/block_sums.h (float-float sums, exact uint non-zero counts)
// from the aamap image, read back and handed to BlockSums::fromTables(). The Snapshot appends it
// after the filter chain; the graph culls it when no strategy asks for block sums.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

// Graph resources (buffers) of the block-sum tables.

// The tables as read back: sums widened to double (hi + lo).
struct BlockSumTables {
    int width = 0, height = 0;  // of the aamap
    std::vector<double> sums;
    std::vector<std::uint32_t> counts;
    bool empty() const { return sums.empty(); }
};

class BlockSumPass {
public:
    explicit BlockSumPass(VulkanContext& context);

    // Declares the row-prefix buffers and kBlockSums/kBlockCounts for a width x height `map`, and
    // the passes "block_sum_rows" and "block_sum_columns". Must outlive the graph's execution.
    void add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& map, int width,
             int height, std::string purpose) const;

private:
    VulkanContext* context_;
    vk::Pipeline rows_, columns_;
};

// kBlockSums and kBlockCounts outputs -> tables (throws std::invalid_argument on a size mismatch).
BlockSumTables toBlockSumTables(const vk::HostData& sums, const vk::HostData& counts, int width, int height);

// Runs the two passes on a host image (the GPU-vs-CPU tests).
class GpuBlockSums {
public:
    explicit GpuBlockSums(VulkanContext& context);
    ~GpuBlockSums();
    BlockSumTables compute(const ImageGrey& map);

private:
    BlockSumPass pass_;
    std::unique_ptr<vk::GraphExecutor> executor_;
};

}  // namespace aamap::passes
