#pragma once
// The GPU-vs-CPU filter benchmark (the paper's Figure 4): the 5x5 Laplacian and the box blur at
// several resolutions, on the CPU (scalar reference, TBB-parallel) and through the Vulkan compute
// passes (kernel time from timestamps, and wall time with upload and readback), against a copy of
// the same image on each side as the bandwidth limit.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "timing.h"

namespace aamap {
class VulkanContext;
}

namespace aamap::bench {

struct FilterBenchOptions {
    std::vector<int> sizes{256, 512, 768, 1024, 2048, 4096};  // square images
    std::vector<std::string> stages{"laplacian", "blur"};
    int repeats = 7;
    int warmup = 2;
    int blurRadius = 1;
};

// One implementation of one stage (or a copy) at one size. Implementations:
//   cpu_scalar, cpu_parallel (into a kept image), cpu_parallel_new (returns a new image),
//   gpu_kernel, gpu_total (stages); cpu_copy, cpu_alloc, gpu_copy (stage "copy").
struct FilterBenchRow {
    std::string stage, impl;
    int width = 0, height = 0;
    Stats ms;
    double bytesMoved = 0.0;        // model: read the image once + write it once (2 * 4 bytes/pixel)
    double fractionOfCopy = 0.0;    // copy median / this median, against the same side's copy
    double maxAbsDiff = 0.0;        // against cpu_scalar; NaN for the copies

    double gigabytesPerSecond() const { return ms.median > 0 ? bytesMoved / (ms.median * 1e6) : 0.0; }
};

struct FilterBenchResult {
    std::string device;  // Vulkan device, or "" when none was usable
    std::string cpu;     // CPU model and thread count
    int threads = 0;
    std::vector<FilterBenchRow> rows;
};

using Progress = std::function<void(const std::string&)>;

// `context` may be null: the CPU rows only.
FilterBenchResult runFilterBench(VulkanContext* context, const FilterBenchOptions& options, const Progress& progress);

// Largest |difference| of the GPU and parallel results from the scalar reference over all rows
// (NaN counts as infinite).
double worstDisagreement(const FilterBenchResult& result);

std::string cpuName();

}  // namespace aamap::bench
