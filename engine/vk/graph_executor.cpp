#include "engine/vk/graph_executor.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/vk/check.h"
#include "engine/vk/context.h"

namespace aamap::vk {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

bool isDepth(const LiveResource& r) {
    return r.resolved.desc.kind == graph::ResourceKind::Image && graph::isDepthFormat(r.resolved.desc.format);
}

std::size_t hostBytes(const graph::ResolvedResource& r) {
    if (r.desc.kind == graph::ResourceKind::Buffer) return r.desc.bytes;
    return static_cast<std::size_t>(r.width) * r.height * graph::bytesPerTexel(r.desc.format);
}

// Collects the barriers of one batch and records them as one vkCmdPipelineBarrier2.
class BarrierBatch {
public:
    void add(const LiveResource& r, graph::Usage from, graph::Usage to) {
        UsageState src = usageState(from, isDepth(r));
        const UsageState dst = usageState(to, isDepth(r));
        if (from == graph::Usage::Undefined) {
            // Contents are discarded, but the resource may still be in use by the previous run
            // (resources are kept between runs): wait for all earlier work.
            src.stages = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
            src.access = VK_ACCESS_2_MEMORY_WRITE_BIT;
        }
        if (r.resolved.desc.kind == graph::ResourceKind::Buffer) {
            VkBufferMemoryBarrier2 b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
            b.srcStageMask = src.stages;
            b.srcAccessMask = src.access;
            b.dstStageMask = dst.stages;
            b.dstAccessMask = dst.access;
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.buffer = r.buffer.handle();
            b.size = VK_WHOLE_SIZE;
            buffers_.push_back(b);
            return;
        }
        images_.push_back(imageBarrier(r.image.handle(), r.image.range(),
                                       {src.layout, dst.layout, src.stages, src.access, dst.stages, dst.access}));
    }
    void record(VkCommandBuffer cmd) {
        if (images_.empty() && buffers_.empty()) return;
        VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
        dep.imageMemoryBarrierCount = static_cast<std::uint32_t>(images_.size());
        dep.pImageMemoryBarriers = images_.data();
        dep.bufferMemoryBarrierCount = static_cast<std::uint32_t>(buffers_.size());
        dep.pBufferMemoryBarriers = buffers_.data();
        vkCmdPipelineBarrier2(cmd, &dep);
        images_.clear();
        buffers_.clear();
    }

private:
    std::vector<VkImageMemoryBarrier2> images_;
    std::vector<VkBufferMemoryBarrier2> buffers_;
};

// A primary command buffer with its fence, reused across runs.
struct Submission {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;

    void begin(VulkanContext& context) {
        VkDevice device = context.device();
        if (!cmd) {
            VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
            ai.commandPool = context.commandPool();
            ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
            ai.commandBufferCount = 1;
            VK_CHECK(vkAllocateCommandBuffers(device, &ai, &cmd));
            VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
            VK_CHECK(vkCreateFence(device, &fi, nullptr, &fence));
        }
        VK_CHECK(vkResetCommandBuffer(cmd, 0));
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    }
    void submitAndWait(VulkanContext& context) {
        VK_CHECK(vkEndCommandBuffer(cmd));
        VK_CHECK(vkResetFences(context.device(), 1, &fence));
        VkCommandBufferSubmitInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        info.commandBuffer = cmd;
        VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        submit.commandBufferInfoCount = 1;
        submit.pCommandBufferInfos = &info;
        VK_CHECK(vkQueueSubmit2(context.queue(), 1, &submit, fence));
        VK_CHECK(withTestFault(vkWaitForFences(context.device(), 1, &fence, VK_TRUE, UINT64_MAX)));
    }
    void destroy(VulkanContext& context) {
        if (fence) vkDestroyFence(context.device(), fence, nullptr);
        if (cmd) vkFreeCommandBuffers(context.device(), context.commandPool(), 1, &cmd);
        fence = VK_NULL_HANDLE;
        cmd = VK_NULL_HANDLE;
    }
};

}  // namespace

const LiveResource& PassContext::find(const std::string& name) const {
    bool declared = false;
    for (const graph::Access& a : pass_.accesses) declared |= a.resource == name;
    auto it = live_.find(name);
    if (!declared || it == live_.end())
        throw std::logic_error(fmt::format("pass '{}' uses resource '{}' it did not declare", pass_.name, name));
    return it->second;
}
const Image& PassContext::image(const std::string& name) const { return find(name).image; }
const Buffer& PassContext::buffer(const std::string& name) const { return find(name).buffer; }

struct GraphExecutor::Impl {
    VulkanContext& context;
    std::map<std::string, RecordFn> records;
    std::map<std::string, PrepareFn> prepares;
    std::map<std::string, std::vector<std::byte>> uploads;
    std::map<std::string, LiveResource> live;
    std::map<std::string, Buffer> staging;  // host-visible, per resource name (uploads and readbacks)
    VkQueryPool queries = VK_NULL_HANDLE;
    std::uint32_t queryCapacity = 0;
    Submission main, readback;

    explicit Impl(VulkanContext& c) : context(c) {}
    ~Impl() {
        vkDeviceWaitIdle(context.device());
        main.destroy(context);
        readback.destroy(context);
        if (queries) vkDestroyQueryPool(context.device(), queries, nullptr);
    }

    void ensureQueries(std::uint32_t count) {
        if (count <= queryCapacity) return;
        if (queries) vkDestroyQueryPool(context.device(), queries, nullptr);
        VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = count;
        VK_CHECK(vkCreateQueryPool(context.device(), &info, nullptr, &queries));
        queryCapacity = count;
    }

    Buffer& stagingFor(const std::string& name, std::size_t bytes) {
        Buffer& b = staging[name];
        if (!b || b.size() < bytes)
            b = Buffer(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
        return b;
    }

    // Creates or reuses the live resources the graph needs, with the usage flags its accesses ask for.
    void prepareResources(const graph::CompiledGraph& g) {
        std::map<std::string, VkImageUsageFlags> usage;
        for (const graph::CompiledPass& p : g.passes)
            for (const graph::Access& a : p.accesses) usage[a.resource] |= imageUsageFlags(a.usage);
        for (const std::string& out : g.outputs) usage[out] |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        for (const auto& [name, r] : g.resources)
            if (r.desc.imported) usage[name] |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;

        for (const auto& [name, r] : g.resources) {
            auto it = live.find(name);
            if (it != live.end()) {
                const LiveResource& old = it->second;
                const bool same = old.resolved.desc.kind == r.desc.kind && old.resolved.desc.format == r.desc.format &&
                                  old.resolved.width == r.width && old.resolved.height == r.height &&
                                  old.resolved.desc.layers == r.desc.layers && old.resolved.desc.cube == r.desc.cube &&
                                  old.resolved.desc.bytes == r.desc.bytes && old.imageUsage == usage[name];
                if (same) {
                    it->second.resolved = r;  // `imported` may differ
                    continue;
                }
                live.erase(it);
            }
            LiveResource res;
            res.resolved = r;
            res.imageUsage = usage[name];
            if (r.desc.kind == graph::ResourceKind::Buffer) {
                res.buffer = Buffer(context, r.desc.bytes,
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                        VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    false);
            } else {
                ImageInfo info;
                info.format = toVkFormat(r.desc.format);
                info.width = r.width;
                info.height = r.height;
                info.layers = r.desc.layers;
                info.cube = r.desc.cube;
                info.usage = res.imageUsage;
                res.image = Image(context, info);
            }
            live.emplace(name, std::move(res));
        }
    }

    // Undefined -> TransferDst and a copy from the host for every imported resource.
    void recordUploads(VkCommandBuffer cmd, const graph::CompiledGraph& g, std::map<std::string, graph::Usage>& state) {
        BarrierBatch batch;
        std::vector<std::string> names;
        for (const auto& [name, r] : g.resources) {
            if (!r.desc.imported) continue;
            auto up = uploads.find(name);
            if (up == uploads.end())
                throw std::logic_error(
                    fmt::format("imported resource '{}' has no upload (GraphExecutor::setUpload)", name));
            const std::size_t bytes = hostBytes(r);
            if (up->second.size() != bytes)
                throw std::logic_error(fmt::format("upload for '{}' has {} bytes, the resource needs {}", name,
                                                   up->second.size(), bytes));
            std::memcpy(stagingFor(name, bytes).mapped(), up->second.data(), bytes);
            batch.add(live.at(name), graph::Usage::Undefined, graph::Usage::TransferDst);
            names.push_back(name);
        }
        batch.record(cmd);
        for (const std::string& name : names) {
            const LiveResource& r = live.at(name);
            if (r.resolved.desc.kind == graph::ResourceKind::Buffer) {
                const VkBufferCopy copy{0, 0, r.resolved.desc.bytes};
                vkCmdCopyBuffer(cmd, staging.at(name).handle(), r.buffer.handle(), 1, &copy);
            } else {
                recordCopyBufferToImage(cmd, staging.at(name), r.image);
            }
            state[name] = graph::Usage::TransferDst;
        }
    }

    void addBarriers(BarrierBatch& batch, const std::vector<graph::Barrier>& barriers, const std::string& where,
                     std::map<std::string, graph::Usage>& state) {
        for (const graph::Barrier& b : barriers) {
            auto it = live.find(b.resource);
            if (it == live.end())
                throw std::logic_error(fmt::format("{}: barrier on unknown resource '{}'", where, b.resource));
            const graph::Usage tracked = state.count(b.resource) ? state[b.resource] : graph::Usage::Undefined;
            if (tracked != b.from)
                throw std::logic_error(fmt::format("{}: the compiled barrier moves '{}' from {}, but it is in {}",
                                                   where,
                                                   b.resource, graph::toString(b.from), graph::toString(tracked)));
            batch.add(it->second, b.from, b.to);
            state[b.resource] = b.to;
        }
    }
};

GraphExecutor::GraphExecutor(VulkanContext& context) : impl_(std::make_unique<Impl>(context)) {}
GraphExecutor::~GraphExecutor() = default;

void GraphExecutor::setRecord(const std::string& pass, RecordFn record) { impl_->records[pass] = std::move(record); }

graph::PassId declarePass(graph::RenderGraph& graph, GraphExecutor& executor, PassDeclaration pass) {
    const std::string name = pass.desc.name;
    const graph::PassId id = graph.addPass(std::move(pass.desc));
    executor.setRecord(name, std::move(pass.record));
    if (pass.prepare) executor.setPrepare(name, std::move(pass.prepare));
    return id;
}
void GraphExecutor::setPrepare(const std::string& pass, PrepareFn prepare) {
    impl_->prepares[pass] = std::move(prepare);
}
void GraphExecutor::setUpload(const std::string& resource, std::vector<std::byte> bytes) {
    impl_->uploads[resource] = std::move(bytes);
}
void GraphExecutor::clear() {
    impl_->records.clear();
    impl_->prepares.clear();
    impl_->uploads.clear();
}

ExecutionResult GraphExecutor::execute(const graph::CompiledGraph& g) {
    Impl& s = *impl_;
    VulkanContext& ctx = s.context;
    for (const graph::CompiledPass& p : g.passes)
        if (!s.records.count(p.name))
            throw std::logic_error(fmt::format("pass '{}' is kept but has no record callback", p.name));
    for (const graph::CompiledPass& p : g.passes)
        if (const auto it = s.prepares.find(p.name); it != s.prepares.end()) it->second();

    ExecutionResult result;
    auto t0 = Clock::now();
    s.prepareResources(g);
    const auto passCount = static_cast<std::uint32_t>(g.passes.size());
    s.ensureQueries(std::max(2u, 2 * passCount));

    std::map<std::string, graph::Usage> state;
    s.main.begin(ctx);
    VkCommandBuffer cmd = s.main.cmd;
    if (passCount > 0) vkCmdResetQueryPool(cmd, s.queries, 0, 2 * passCount);
    s.recordUploads(cmd, g, state);
    for (std::uint32_t i = 0; i < passCount; ++i) {
        const graph::CompiledPass& pass = g.passes[i];
        BarrierBatch batch;
        s.addBarriers(batch, pass.barriersBefore, fmt::format("pass '{}'", pass.name), state);
        batch.record(cmd);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, s.queries, 2 * i);
        PassContext pc(ctx, cmd, pass, s.live);
        s.records.at(pass.name)(pc);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, s.queries, 2 * i + 1);
    }
    BarrierBatch finish;
    s.addBarriers(finish, g.finalBarriers, "final barriers", state);
    finish.record(cmd);
    s.main.submitAndWait(ctx);
    result.submitSeconds = secondsSince(t0);

    if (passCount > 0) {
        std::vector<std::uint64_t> stamps(2 * passCount);
        VK_CHECK(vkGetQueryPoolResults(ctx.device(), s.queries, 0, 2 * passCount, stamps.size() * 8, stamps.data(), 8,
                                       VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        const std::uint32_t bits = ctx.timestampValidBits();
        const std::uint64_t mask = bits >= 64 ? ~0ull : ((1ull << bits) - 1);
        for (std::uint32_t i = 0; i < passCount; ++i) {
            const std::uint64_t ticks = ((stamps[2 * i + 1] & mask) - (stamps[2 * i] & mask)) & mask;
            const double ms = static_cast<double>(ticks) * ctx.timestampPeriodNs() * 1e-6;
            result.passTimes.push_back({g.passes[i].name, ms});
            result.gpuMilliseconds += ms;
        }
    }

    // Readback in its own submission so that its cost is measured on its own.
    auto t1 = Clock::now();
    if (!g.outputs.empty()) {
        s.readback.begin(ctx);
        for (const std::string& name : g.outputs) {
            const LiveResource& r = s.live.at(name);
            Buffer& dst = s.stagingFor(name, hostBytes(r.resolved));
            if (r.resolved.desc.kind == graph::ResourceKind::Buffer) {
                const VkBufferCopy copy{0, 0, r.resolved.desc.bytes};
                vkCmdCopyBuffer(s.readback.cmd, r.buffer.handle(), dst.handle(), 1, &copy);
            } else {
                recordCopyImageToBuffer(s.readback.cmd, r.image, dst);
            }
        }
        recordMemoryBarrier(s.readback.cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                            VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
        s.readback.submitAndWait(ctx);
        for (const std::string& name : g.outputs) {
            const LiveResource& r = s.live.at(name);
            HostData data;
            data.kind = r.resolved.desc.kind;
            data.format = r.resolved.desc.format;
            data.width = r.resolved.width;
            data.height = r.resolved.height;
            const auto* mapped = static_cast<const std::byte*>(s.staging.at(name).mapped());
            data.bytes.assign(mapped, mapped + hostBytes(r.resolved));  // no zero-fill before the copy
            result.outputs[name] = std::move(data);
        }
    }
    result.readbackSeconds = secondsSince(t1);
    return result;
}

const Image& GraphExecutor::image(const std::string& name) const { return impl_->live.at(name).image; }
const Buffer& GraphExecutor::buffer(const std::string& name) const { return impl_->live.at(name).buffer; }

}  // namespace aamap::vk
