// The graph executor: culled passes do not run, barriers come from the compiled graph, imported
// resources are uploaded, outputs read back, timestamps per pass.
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "engine/vk/graph_executor.h"
#include "gpu_fixture.h"
#include "passes/gpu_aamap.h"

namespace aamap::test {
namespace {

using graph::Usage;

graph::ResourceDesc r32(const std::string& name, std::uint32_t w, std::uint32_t h, bool imported = false) {
    graph::ResourceDesc d;
    d.name = name;
    d.format = graph::Format::R32Float;
    d.size = graph::Size::absolute(w, h);
    d.imported = imported;
    return d;
}

// Fills an image that the pass declared as TransferDst with one value.
vk::RecordFn clearTo(const std::string& name, float value, int* calls) {
    return [name, value, calls](vk::PassContext& pc) {
        ++*calls;
        const VkClearColorValue colour{{value, value, value, value}};
        const VkImageSubresourceRange range = pc.image(name).range();
        vkCmdClearColorImage(pc.cmd(), pc.image(name).handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &colour, 1, &range);
    };
}

// Copies `from` (TransferSrc) to `to` (TransferDst).
vk::RecordFn copy(const std::string& from, const std::string& to, int* calls) {
    return [from, to, calls](vk::PassContext& pc) {
        ++*calls;
        const vk::Image& src = pc.image(from);
        VkImageCopy region{};
        region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.dstSubresource = region.srcSubresource;
        region.extent = {src.info().width, src.info().height, 1};
        vkCmdCopyImage(pc.cmd(), src.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pc.image(to).handle(),
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    };
}

class ExecutorTest : public GpuTest {};

TEST_F(ExecutorTest, CulledPassDoesNotRun) {
    graph::RenderGraph g;
    g.addResource(r32("a", 16, 8));
    g.addResource(r32("out", 16, 8));
    g.addResource(r32("debug", 16, 8));
    g.addPass({"fill", graph::QueueKind::Graphics, {graph::writes("a", Usage::TransferDst)}, "fills a"});
    g.addPass({"copy", graph::QueueKind::Graphics,
               {graph::reads("a", Usage::TransferSrc), graph::writes("out", Usage::TransferDst)}, "copies"});
    g.addPass({"debugFill", graph::QueueKind::Graphics, {graph::writes("debug", Usage::TransferDst)}, "unused"});
    const std::vector<std::string> outputs{"out"};
    const graph::CompiledGraph compiled = g.compile(outputs);
    ASSERT_EQ(compiled.passes.size(), 2u);
    ASSERT_EQ(compiled.culled.size(), 1u);
    EXPECT_EQ(compiled.culled[0].name, "debugFill");

    vk::GraphExecutor executor(context());
    int fillCalls = 0, copyCalls = 0, debugCalls = 0;
    executor.setRecord("fill", clearTo("a", 3.5f, &fillCalls));
    executor.setRecord("copy", copy("a", "out", &copyCalls));
    executor.setRecord("debugFill", clearTo("debug", 1.0f, &debugCalls));
    // Preparation (pipeline builds) runs for kept passes only, before any pass is recorded.
    int copyPrepares = 0, debugPrepares = 0;
    executor.setPrepare("copy", [&] {
        EXPECT_EQ(fillCalls, copyCalls) << "prepared after recording began";
        ++copyPrepares;
    });
    executor.setPrepare("debugFill", [&] { ++debugPrepares; });
    for (int run = 0; run < 2; ++run) {  // the second run reuses the live resources
        const vk::ExecutionResult result = executor.execute(compiled);
        ASSERT_EQ(result.passTimes.size(), 2u);
        EXPECT_EQ(result.passTimes[0].pass, "fill");
        EXPECT_EQ(result.passTimes[1].pass, "copy");
        for (const vk::PassTime& t : result.passTimes) EXPECT_GE(t.milliseconds, 0.0);
        ASSERT_EQ(result.outputs.count("out"), 1u);
        ASSERT_EQ(result.outputs.count("debug"), 0u);
        const std::vector<float> values = result.outputs.at("out").floats();
        ASSERT_EQ(values.size(), 16u * 8u);
        for (float v : values) ASSERT_EQ(v, 3.5f);
    }
    EXPECT_EQ(fillCalls, 2);
    EXPECT_EQ(copyCalls, 2);
    EXPECT_EQ(debugCalls, 0);
    EXPECT_EQ(copyPrepares, 2);
    EXPECT_EQ(debugPrepares, 0);
}

TEST_F(ExecutorTest, ImportedResourceIsUploadedAndReadBack) {
    graph::RenderGraph g;
    g.addResource(r32("in", 5, 3, true));
    g.addResource(r32("out", 5, 3));
    g.addPass({"copy", graph::QueueKind::Graphics,
               {graph::reads("in", Usage::TransferSrc), graph::writes("out", Usage::TransferDst)}, "copies"});
    const std::vector<std::string> outputs{"out", "in"};
    const graph::CompiledGraph compiled = g.compile(outputs);

    std::vector<float> texels(15);
    for (int i = 0; i < 15; ++i) texels[i] = static_cast<float>(i) * 0.25f - 1.0f;
    std::vector<std::byte> bytes(texels.size() * 4);
    std::memcpy(bytes.data(), texels.data(), bytes.size());

    vk::GraphExecutor executor(context());
    int calls = 0;
    executor.setRecord("copy", copy("in", "out", &calls));
    executor.setUpload("in", bytes);
    const vk::ExecutionResult result = executor.execute(compiled);
    EXPECT_EQ(result.outputs.at("out").floats(), texels);
    EXPECT_EQ(result.outputs.at("in").floats(), texels);
}

TEST_F(ExecutorTest, MissingCallbackOrUploadIsAnError) {
    graph::RenderGraph g;
    g.addResource(r32("in", 4, 4, true));
    g.addResource(r32("out", 4, 4));
    g.addPass({"copy", graph::QueueKind::Graphics,
               {graph::reads("in", Usage::TransferSrc), graph::writes("out", Usage::TransferDst)}, "copies"});
    const std::vector<std::string> outputs{"out"};
    const graph::CompiledGraph compiled = g.compile(outputs);
    vk::GraphExecutor executor(context());
    EXPECT_THROW(executor.execute(compiled), std::logic_error);  // no callback
    int calls = 0;
    executor.setRecord("copy", copy("in", "out", &calls));
    EXPECT_THROW(executor.execute(compiled), std::logic_error);  // no upload
    executor.setUpload("in", std::vector<std::byte>(4 * 4 * 4));
    EXPECT_NO_THROW(executor.execute(compiled));
    EXPECT_EQ(calls, 1);
}

TEST_F(ExecutorTest, UndeclaredResourceInCallbackIsAnError) {
    graph::RenderGraph g;
    g.addResource(r32("a", 4, 4));
    g.addResource(r32("b", 4, 4));
    g.addPass({"fillA", graph::QueueKind::Graphics, {graph::writes("a", Usage::TransferDst)}, ""});
    g.addPass({"fillB", graph::QueueKind::Graphics, {graph::writes("b", Usage::TransferDst)}, ""});
    const std::vector<std::string> outputs{"a", "b"};
    const graph::CompiledGraph compiled = g.compile(outputs);
    vk::GraphExecutor executor(context());
    int calls = 0;
    executor.setRecord("fillA", clearTo("b", 1.0f, &calls));  // touches b without declaring it
    executor.setRecord("fillB", clearTo("b", 1.0f, &calls));
    EXPECT_THROW(executor.execute(compiled), std::logic_error);
    // The aborted recording must not poison the next run.
    executor.setRecord("fillA", clearTo("a", 2.0f, &calls));
    const vk::ExecutionResult result = executor.execute(compiled);
    EXPECT_EQ(result.outputs.at("a").floats(), std::vector<float>(16, 2.0f));
}

TEST_F(ExecutorTest, ContextReportsDevice) {
    EXPECT_FALSE(context().deviceName().empty());
    EXPECT_TRUE(context().validationEnabled());
    EXPECT_GT(context().timestampPeriodNs(), 0.0);
    const std::vector<std::string> devices = VulkanContext::listDevices();
    EXPECT_FALSE(devices.empty());
}

TEST(ContextTest, UnknownDeviceNameIsAnEnvironmentError) {
    ContextOptions options;
    options.device = "no-such-device-xyz";
    EXPECT_THROW(VulkanContext{options}, EnvironmentError);
}

}  // namespace
}  // namespace aamap::test
