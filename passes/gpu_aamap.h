#pragma once
// The aamap filter chain on the GPU: the graph fragment the Snapshot appends after its raster,
// and a stand-alone runner on host images (the GPU counterpart of passes/cpu_aamap.h, used by
// the GPU-vs-CPU tests and benchmarks). The images go up as imported graph resources.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "engine/vk/graph_executor.h"
#include "passes/blur.h"
#include "passes/cpu_aamap.h"
#include "passes/filter_params.h"
#include "passes/laplacian.h"
#include "passes/luminance.h"
#include "passes/reduce.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

struct FilterChain {
    explicit FilterChain(VulkanContext& context)
        : luminance(context), laplacian(context), blur(context), reduce(context) {}
    LuminancePass luminance;
    LaplacianPass laplacian;
    BlurPass blur;
    ReducePass reduce;

    // Declares grey, laplacian, map (sized like `colour`) and aamap (width x height), and the
    // four passes from the RGBA32F image `colour` to the aamap. greyFromGBuffer: grey is already
    // declared and written (passes/gbuffer.h, GBufferGrey), so there is no luminance pass.
    // blurInput (the geometric and combined maps): declares, after the Laplacian, the pass that
    // writes what the blur reads instead of the Laplacian, and returns that resource's name.
    using BlurInput = std::function<std::string(graph::RenderGraph&)>;
    void add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour, int width, int height,
             const FilterParams& params, bool greyFromGBuffer = false, const BlurInput& blurInput = {}) const;
};

// Runs the chain, or one stage of it, on host images.
class GpuAamap {
public:
    explicit GpuAamap(VulkanContext& context);
    ~GpuAamap();

    cpu::AamapImages build(const ImageRGB& snapshot, int width, int height, const FilterParams& params);
    ImageGrey greyscale(const ImageRGB& rgb, float exposure);
    ImageGrey laplacianMagnitude(const ImageGrey& grey, float flatRange = 0.0f);  // 0: no flat gate
    // Box blur followed by the dead zone: noiseFloor 0 and gain 1 give the plain blur of inputs in [0,1].
    ImageGrey blurDeadZone(const ImageGrey& edges, int radius, float noiseFloor, float gain);
    ImageGrey reduceMax(const ImageGrey& map, int width, int height);

    // Timings of the last call, and its compiled graph.
    const std::vector<vk::PassTime>& passTimes() const { return last_.passTimes; }
    const vk::ExecutionResult& lastResult() const { return last_; }

private:
    vk::ExecutionResult run(graph::RenderGraph& graph, const std::vector<std::string>& outputs);

    FilterChain chain_;
    std::unique_ptr<vk::GraphExecutor> executor_;
    vk::ExecutionResult last_;
};

// Host <-> graph image conversions.
std::vector<std::byte> toRGBA32(const ImageRGB& image);
std::vector<std::byte> toR32(const ImageGrey& image);
ImageRGB toImageRGB(const vk::HostData& data);
ImageGrey toImageGrey(const vk::HostData& data);  // first channel

}  // namespace aamap::passes
