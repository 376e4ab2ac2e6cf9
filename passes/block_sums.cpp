#include "passes/block_sums.h"

#include <cstring>
#include <stdexcept>

#include <aamap/spirv.h>

#include "engine/vk/context.h"
#include "glsl/shared/snapshot_interface.h"
#include "passes/gpu_aamap.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {
namespace {


vk::LayoutDesc storageLayout(std::vector<VkDescriptorType> bindings) {
    return {std::move(bindings), static_cast<std::uint32_t>(sizeof(gpu::BlockSumPush)), VK_SHADER_STAGE_COMPUTE_BIT};
}

std::size_t tableSize(int width, int height) {
    return static_cast<std::size_t>(width + 1) * static_cast<std::size_t>(height + 1);
}

}  // namespace

BlockSumPass::BlockSumPass(VulkanContext& context)
    : context_(&context),
      rows_(context, spirv::block_sum_rows_comp,
            storageLayout({VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           VK_DESCRIPTOR_TYPE_STORAGE_BUFFER})),
      columns_(context, spirv::block_sum_columns_comp,
               storageLayout({VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                              VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER})) {}

void BlockSumPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& map, int width,
                       int height, std::string purpose) const {
    if (width <= 0 || height <= 0) throw std::invalid_argument("BlockSumPass: non-positive map size");
    const std::uint64_t prefixes = static_cast<std::uint64_t>(width + 1) * static_cast<std::uint64_t>(height);
    const std::uint64_t table = tableSize(width, height);
    graph.addResource(graph::bufferResource(kBlockSumRowPrefixes, prefixes * 2 * sizeof(float)));
    graph.addResource(graph::bufferResource(kBlockCountRowPrefixes, prefixes * sizeof(std::uint32_t)));
    graph.addResource(graph::bufferResource(kBlockSums, table * 2 * sizeof(float)));
    graph.addResource(graph::bufferResource(kBlockCounts, table * sizeof(std::uint32_t)));
    const gpu::BlockSumPush push{{width, height}, {0, 0}};

    vk::PassDeclaration rows;
    rows.desc = {kBlockSumRowsPass,
                 graph::QueueKind::Compute,
                 {graph::reads(map, graph::Usage::StorageRead), graph::writes(kBlockSumRowPrefixes, graph::Usage::StorageWrite),
                  graph::writes(kBlockCountRowPrefixes, graph::Usage::StorageWrite)},
                 purpose + " (row prefixes)"};
    rows.record = [this, map, push](vk::PassContext& pc) {
        rows_.bind(pc.cmd());
        vk::DescriptorPush()
            .storageImage(BLOCKSUM_ROWS_BINDING_MAP, pc.image(map).view())
            .storageBuffer(BLOCKSUM_ROWS_BINDING_SUMS, pc.buffer(kBlockSumRowPrefixes).handle())
            .storageBuffer(BLOCKSUM_ROWS_BINDING_COUNTS, pc.buffer(kBlockCountRowPrefixes).handle())
            .push(*context_, pc.cmd(), rows_);
        rows_.pushConstants(pc.cmd(), push);
        vk::dispatch2D(pc.cmd(), static_cast<std::uint32_t>(push.size.y), 1, BLOCKSUM_GROUP, 1);
    };
    vk::declarePass(graph, executor, std::move(rows));

    vk::PassDeclaration columns;
    columns.desc = {kBlockSumColumnsPass,
                    graph::QueueKind::Compute,
                    {graph::reads(kBlockSumRowPrefixes, graph::Usage::StorageRead),
                     graph::reads(kBlockCountRowPrefixes, graph::Usage::StorageRead),
                     graph::writes(kBlockSums, graph::Usage::StorageWrite),
                     graph::writes(kBlockCounts, graph::Usage::StorageWrite)},
                    std::move(purpose)};
    columns.record = [this, push](vk::PassContext& pc) {
        columns_.bind(pc.cmd());
        vk::DescriptorPush()
            .storageBuffer(BLOCKSUM_COLUMNS_BINDING_ROW_SUMS, pc.buffer(kBlockSumRowPrefixes).handle())
            .storageBuffer(BLOCKSUM_COLUMNS_BINDING_ROW_COUNTS, pc.buffer(kBlockCountRowPrefixes).handle())
            .storageBuffer(BLOCKSUM_COLUMNS_BINDING_SUMS, pc.buffer(kBlockSums).handle())
            .storageBuffer(BLOCKSUM_COLUMNS_BINDING_COUNTS, pc.buffer(kBlockCounts).handle())
            .push(*context_, pc.cmd(), columns_);
        columns_.pushConstants(pc.cmd(), push);
        vk::dispatch2D(pc.cmd(), static_cast<std::uint32_t>(push.size.x + 1), 1, BLOCKSUM_GROUP, 1);
    };
    vk::declarePass(graph, executor, std::move(columns));
}

BlockSumTables toBlockSumTables(const vk::HostData& sums, const vk::HostData& counts, int width, int height) {
    const std::size_t n = tableSize(width, height);
    if (sums.bytes.size() != n * 2 * sizeof(float) || counts.bytes.size() != n * sizeof(std::uint32_t))
        throw std::invalid_argument("block-sum buffers do not match the map size");
    BlockSumTables t;
    t.width = width;
    t.height = height;
    std::vector<float> pairs(2 * n);
    std::memcpy(pairs.data(), sums.bytes.data(), sums.bytes.size());
    t.sums.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        t.sums[i] = static_cast<double>(pairs[2 * i]) + static_cast<double>(pairs[2 * i + 1]);
    t.counts.resize(n);
    std::memcpy(t.counts.data(), counts.bytes.data(), counts.bytes.size());
    return t;
}

GpuBlockSums::GpuBlockSums(VulkanContext& context)
    : pass_(context), executor_(std::make_unique<vk::GraphExecutor>(context)) {}
GpuBlockSums::~GpuBlockSums() = default;

BlockSumTables GpuBlockSums::compute(const ImageGrey& map) {
    if (map.empty()) throw std::invalid_argument("GpuBlockSums: empty map");
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(graph::imageResource(
        "map", graph::Format::R32Float,
        graph::Size::absolute(static_cast<std::uint32_t>(map.width()), static_cast<std::uint32_t>(map.height())), true));
    executor_->setUpload("map", toR32(map));
    pass_.add(graph, *executor_, "map", map.width(), map.height(), "block sums of a host map");
    const std::vector<std::string> outputs{kBlockSums, kBlockCounts};
    const vk::ExecutionResult r = executor_->execute(graph.compile(outputs));
    executor_->clear();
    return toBlockSumTables(r.outputs.at(kBlockSums), r.outputs.at(kBlockCounts), map.width(), map.height());
}

}  // namespace aamap::passes
