#pragma once
// Runs a compiled render graph on Vulkan: creates (and keeps, for the next run) the live
// resources, uploads imported ones, derives every vkCmdPipelineBarrier2 from the compiled
// barriers, records each pass through its callback between two timestamps, submits, waits and
// reads the requested outputs back. Passes never write barriers.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/graph/render_graph.h"
#include "engine/vk/resources.h"

namespace aamap {
class VulkanContext;
}

namespace aamap::vk {

// Layout, stages and access of one graph usage (the state a resource is in while used so).
struct UsageState {
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
    VkAccessFlags2 access = VK_ACCESS_2_NONE;
};
UsageState usageState(graph::Usage usage, bool depth);
VkImageUsageFlags imageUsageFlags(graph::Usage usage);

// A resource of the graph as it lives on the device.
struct LiveResource {
    graph::ResolvedResource resolved;
    VkImageUsageFlags imageUsage = 0;
    Image image;    // kind Image
    Buffer buffer;  // kind Buffer
};

// What a pass's record callback sees.
class PassContext {
public:
    PassContext(VulkanContext& context, VkCommandBuffer cmd, const graph::CompiledPass& pass,
                const std::map<std::string, LiveResource>& live)
        : context_(context), cmd_(cmd), pass_(pass), live_(live) {}

    VulkanContext& context() const { return context_; }
    VkCommandBuffer cmd() const { return cmd_; }
    const graph::CompiledPass& pass() const { return pass_; }
    const Image& image(const std::string& name) const;    // throws if the pass does not access it
    const Buffer& buffer(const std::string& name) const;  // likewise

private:
    const LiveResource& find(const std::string& name) const;
    VulkanContext& context_;
    VkCommandBuffer cmd_;
    const graph::CompiledPass& pass_;
    const std::map<std::string, LiveResource>& live_;
};

using RecordFn = std::function<void(PassContext&)>;
// Work a pass needs once it is known to run (pipelines, static buffers): called by execute()
// for kept passes only, before recording, so a culled pass builds nothing.
using PrepareFn = std::function<void()>;

// An output brought back to the host: tightly packed texels (images) or the raw bytes (buffers).
struct HostData {
    graph::ResourceKind kind = graph::ResourceKind::Image;
    graph::Format format = graph::Format::R32Float;
    std::uint32_t width = 0, height = 0;
    std::vector<std::byte> bytes;

    std::uint32_t channels() const;
    std::vector<float> floats() const;  // every channel of every texel as float (images only)
};

struct PassTime {
    std::string pass;
    double milliseconds = 0.0;  // GPU time between the pass's two timestamps
};

struct ExecutionResult {
    std::vector<PassTime> passTimes;  // execution order
    std::map<std::string, HostData> outputs;
    double gpuMilliseconds = 0.0;    // sum of passTimes
    double submitSeconds = 0.0;      // CPU wall time: record, submit and wait for the passes
    double readbackSeconds = 0.0;    // CPU wall time: copy the outputs to the host
};

class GraphExecutor {
public:
    explicit GraphExecutor(VulkanContext& context);
    ~GraphExecutor();
    GraphExecutor(const GraphExecutor&) = delete;
    GraphExecutor& operator=(const GraphExecutor&) = delete;

    // The callback recording pass `pass` (by name). A kept pass without one is an error.
    void setRecord(const std::string& pass, RecordFn record);
    // Optional: what pass `pass` builds before it can be recorded (see PrepareFn).
    void setPrepare(const std::string& pass, PrepareFn prepare);
    // Host contents of an imported resource: tightly packed texels of layer 0, or buffer bytes.
    void setUpload(const std::string& resource, std::vector<std::byte> bytes);
    void clear();  // forgets callbacks (record and prepare) and uploads (live resources stay for reuse)

    // Throws std::logic_error when the compiled barriers disagree with the executor's own state
    // tracking, a kept pass has no callback or an imported resource has no upload.
    ExecutionResult execute(const graph::CompiledGraph& graph);

    // Live resources of the last execute (valid until the next).
    const Image& image(const std::string& name) const;
    const Buffer& buffer(const std::string& name) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A pass as it is registered: its description for the graph (name, queue, accesses, purpose) and
// how the executor records it (and, optionally, what it builds first), under the one name.
struct PassDeclaration {
    graph::PassDesc desc;
    RecordFn record;
    PrepareFn prepare;  // may be empty
};
// Registers `pass` once: in `graph` (which decides whether it runs) and in `executor` (which
// records it if it does). Every Snapshot pass registers through here.
graph::PassId declarePass(graph::RenderGraph& graph, GraphExecutor& executor, PassDeclaration pass);

}  // namespace aamap::vk
