#include "passes/gpu_aamap.h"

#include <cstring>
#include <stdexcept>

namespace aamap::passes {
namespace {

graph::Size absoluteSize(int width, int height) {
    return graph::Size::absolute(static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height));
}

graph::Size sizeOf(const auto& image) {
    if (image.empty()) throw std::invalid_argument("GpuAamap: empty input image");
    return graph::Size::absolute(static_cast<std::uint32_t>(image.width()), static_cast<std::uint32_t>(image.height()));
}

}  // namespace

void FilterChain::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour, int width,
                      int height, const FilterParams& params, bool greyFromGBuffer, const BlurInput& blurInput) const {
    if (!greyFromGBuffer)
        graph.addResource(graph::imageResource(kGrey, graph::Format::R32Float, graph::Size::relative(colour)));
    graph.addResource(graph::imageResource(kLaplacian, graph::Format::R32Float, graph::Size::relative(colour)));
    graph.addResource(graph::imageResource(kMap, graph::Format::R32Float, graph::Size::relative(colour)));
    graph.addResource(graph::imageResource(kAamap, graph::Format::R32Float,
                            absoluteSize(width, height)));
    if (!greyFromGBuffer) luminance.add(graph, executor, colour, kGrey, params.exposure);
    laplacian.add(graph, executor, kGrey, kLaplacian, params.flatRange);
    const std::string blurred = blurInput ? blurInput(graph) : std::string(kLaplacian);
    blur.add(graph, executor, blurred, kMap, params.blurRadius, params.noiseFloor, params.gain);
    reduce.add(graph, executor, kMap, kAamap);
}

GpuAamap::GpuAamap(VulkanContext& context)
    : chain_(context), executor_(std::make_unique<vk::GraphExecutor>(context)) {}
GpuAamap::~GpuAamap() = default;

vk::ExecutionResult GpuAamap::run(graph::RenderGraph& graph, const std::vector<std::string>& outputs) {
    const graph::CompiledGraph compiled = graph.compile(outputs);
    last_ = executor_->execute(compiled);
    executor_->clear();
    return last_;
}

cpu::AamapImages GpuAamap::build(const ImageRGB& snapshot, int width, int height, const FilterParams& params) {
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(graph::imageResource("colour", graph::Format::RGBA32Float, sizeOf(snapshot), true));
    executor_->setUpload("colour", toRGBA32(snapshot));
    chain_.add(graph, *executor_, "colour", width, height, params);
    const vk::ExecutionResult r = run(graph, {kGrey, kLaplacian, kAamap});
    return {toImageGrey(r.outputs.at(kGrey)), toImageGrey(r.outputs.at(kLaplacian)), toImageGrey(r.outputs.at(kAamap))};
}

ImageGrey GpuAamap::greyscale(const ImageRGB& rgb, float exposure) {
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(graph::imageResource("colour", graph::Format::RGBA32Float, sizeOf(rgb), true));
    graph.addResource(graph::imageResource(kGrey, graph::Format::R32Float, sizeOf(rgb)));
    executor_->setUpload("colour", toRGBA32(rgb));
    chain_.luminance.add(graph, *executor_, "colour", kGrey, exposure);
    return toImageGrey(run(graph, {kGrey}).outputs.at(kGrey));
}

ImageGrey GpuAamap::laplacianMagnitude(const ImageGrey& grey, float flatRange) {
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(graph::imageResource(kGrey, graph::Format::R32Float, sizeOf(grey), true));
    graph.addResource(graph::imageResource(kLaplacian, graph::Format::R32Float, sizeOf(grey)));
    executor_->setUpload(kGrey, toR32(grey));
    chain_.laplacian.add(graph, *executor_, kGrey, kLaplacian, flatRange);
    return toImageGrey(run(graph, {kLaplacian}).outputs.at(kLaplacian));
}

ImageGrey GpuAamap::blurDeadZone(const ImageGrey& edges, int radius, float noiseFloor, float gain) {
    if (radius < 0) throw std::invalid_argument("GpuAamap::blurDeadZone: negative radius");
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(graph::imageResource(kLaplacian, graph::Format::R32Float, sizeOf(edges), true));
    graph.addResource(graph::imageResource(kMap, graph::Format::R32Float, sizeOf(edges)));
    executor_->setUpload(kLaplacian, toR32(edges));
    chain_.blur.add(graph, *executor_, kLaplacian, kMap, radius, noiseFloor, gain);
    return toImageGrey(run(graph, {kMap}).outputs.at(kMap));
}

ImageGrey GpuAamap::reduceMax(const ImageGrey& map, int width, int height) {
    if (width <= 0 || height <= 0) throw std::invalid_argument("GpuAamap::reduceMax: non-positive output size");
    executor_->clear();
    graph::RenderGraph graph;
    graph.addResource(graph::imageResource(kMap, graph::Format::R32Float, sizeOf(map), true));
    graph.addResource(graph::imageResource(kAamap, graph::Format::R32Float,
                            absoluteSize(width, height)));
    executor_->setUpload(kMap, toR32(map));
    chain_.reduce.add(graph, *executor_, kMap, kAamap);
    return toImageGrey(run(graph, {kAamap}).outputs.at(kAamap));
}

std::vector<std::byte> toRGBA32(const ImageRGB& image) {
    std::vector<float> texels(image.size() * 4);
    for (std::size_t i = 0; i < image.size(); ++i) {
        const glm::vec3 c = image.data()[i];
        texels[4 * i + 0] = c.r;
        texels[4 * i + 1] = c.g;
        texels[4 * i + 2] = c.b;
        texels[4 * i + 3] = 1.0f;
    }
    std::vector<std::byte> bytes(texels.size() * 4);
    std::memcpy(bytes.data(), texels.data(), bytes.size());
    return bytes;
}

std::vector<std::byte> toR32(const ImageGrey& image) {
    std::vector<std::byte> bytes(image.size() * 4);
    std::memcpy(bytes.data(), image.data(), bytes.size());
    return bytes;
}

ImageRGB toImageRGB(const vk::HostData& data) {
    const std::vector<float> f = data.floats();
    const std::uint32_t c = data.channels();
    ImageRGB out(static_cast<int>(data.width), static_cast<int>(data.height));
    for (std::size_t i = 0; i < out.size(); ++i)
        out.data()[i] = glm::vec3(f[c * i], f[c * i + (c > 1 ? 1 : 0)], f[c * i + (c > 2 ? 2 : 0)]);
    return out;
}

ImageGrey toImageGrey(const vk::HostData& data) {
    ImageGrey out(static_cast<int>(data.width), static_cast<int>(data.height));
    if (data.format == graph::Format::R32Float && data.bytes.size() == out.size() * sizeof(float)) {
        std::memcpy(out.data(), data.bytes.data(), data.bytes.size());  // the per-frame aamap: one copy
        return out;
    }
    const std::vector<float> f = data.floats();
    const std::uint32_t c = data.channels();
    for (std::size_t i = 0; i < out.size(); ++i) out.data()[i] = f[c * i];
    return out;
}

}  // namespace aamap::passes
