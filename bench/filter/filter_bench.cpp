#include "filter_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include "engine/vk/context.h"
#include "gpu_copy.h"
#include "passes/cpu_aamap.h"
#include "passes/gpu_aamap.h"

namespace aamap::bench {
namespace {

constexpr double kBytesPerPixel = 2.0 * sizeof(float);  // one float read + one float written

// Deterministic noise in [0,1) from a hash of (index, seed): the timing does not depend on the
// data (no data-dependent branches), and noise exercises every tap with non-trivial values.
ImageGrey noiseImage(int w, int h, std::uint32_t seed) {
    ImageGrey image(w, h);
    float* p = image.data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, image.size(), 1 << 16), [&](const auto& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            std::uint32_t x = static_cast<std::uint32_t>(i) * 0x9E3779B9u ^ seed;
            x ^= x >> 16;
            x *= 0x7feb352du;
            x ^= x >> 15;
            x *= 0x846ca68bu;
            x ^= x >> 16;
            p[i] = static_cast<float>(x >> 8) * (1.0f / 16777216.0f);
        }
    });
    return image;
}

double maxAbsDiff(const ImageGrey& a, const ImageGrey& b) {
    if (a.width() != b.width() || a.height() != b.height()) return std::numeric_limits<double>::infinity();
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double d = std::fabs(static_cast<double>(a.data()[i]) - b.data()[i]);
        if (!(d <= worst)) worst = std::isnan(d) ? std::numeric_limits<double>::infinity() : d;
    }
    return worst;
}

// The CPU side of the limit: a TBB-parallel memcpy of the image into a buffer that already exists.
double cpuCopyMs(const ImageGrey& src, std::vector<float>& dst) {
    const std::size_t n = src.size();
    const std::size_t grain = std::max<std::size_t>(n / 64, 1 << 14);  // >= 64 KiB per task
    const auto t0 = Clock::now();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const auto& r) {
        std::memcpy(dst.data() + r.begin(), src.data() + r.begin(), (r.end() - r.begin()) * sizeof(float));
    });
    return msSince(t0);
}

class SizeRunner {
public:
    SizeRunner(VulkanContext* context, passes::GpuAamap* gpu, GpuCopyTimer* copy, const FilterBenchOptions& options,
               const Progress& progress, FilterBenchResult& result)
        : context_(context), gpu_(gpu), copy_(copy), options_(options), progress_(progress), result_(result) {}

    void run(int size) {
        w_ = h_ = size;
        bytes_ = kBytesPerPixel * w_ * h_;
        const ImageGrey grey = noiseImage(w_, h_, 0x1234u);
        runCopies(grey);
        for (const std::string& stage : options_.stages) {
            if (stage == "laplacian") {
                runStage(
                    stage, grey,
                    [](const ImageGrey& in, ImageGrey& out, cpu::Mode m) { cpu::laplacianMagnitudeInto(in, out, m); },
                    [](const ImageGrey& in, cpu::Mode m) { return cpu::laplacianMagnitude(in, m); },
                    [this](const ImageGrey& in) { return gpu_->laplacianMagnitude(in); });
            } else if (stage == "blur") {
                // Inputs in [0,1]: the GPU pass fuses the dead zone, and noiseFloor 0 / gain 1 is then
                // the identity, so both sides compute the plain box blur.
                const ImageGrey edges = noiseImage(w_, h_, 0xBEEFu);
                const int r = options_.blurRadius;
                runStage(
                    stage, edges,
                    [r](const ImageGrey& in, ImageGrey& out, cpu::Mode m) { cpu::boxBlurInto(in, r, out, m); },
                    [r](const ImageGrey& in, cpu::Mode m) { return cpu::boxBlur(in, r, m); },
                    [this, r](const ImageGrey& in) { return gpu_->blurDeadZone(in, r, 0.0f, 1.0f); });
            } else {
                throw std::invalid_argument("unknown stage '" + stage + "'");
            }
        }
    }

private:
    FilterBenchRow& add(const std::string& stage, const std::string& impl, Stats ms) {
        FilterBenchRow row;
        row.stage = stage;
        row.impl = impl;
        row.width = w_;
        row.height = h_;
        row.ms = ms;
        row.bytesMoved = bytes_;
        row.maxAbsDiff = std::numeric_limits<double>::quiet_NaN();
        const bool gpuSide = impl.rfind("gpu", 0) == 0;
        const double copyMs = gpuSide ? gpuCopyMs_ : cpuCopyMs_;
        row.fractionOfCopy = copyMs > 0 && ms.median > 0 ? copyMs / ms.median : 0.0;
        if (impl == "cpu_alloc") {  // writes the image once, reads nothing; not held to the copy
            row.bytesMoved = bytes_ / 2;
            row.fractionOfCopy = std::numeric_limits<double>::quiet_NaN();
        }
        result_.rows.push_back(row);
        progress_(fmt::format("{:>9} {:>4}x{:<4} {:<16} median {:10.3f} ms  [{:.3f}, {:.3f}]", stage, w_, h_, impl,
                              ms.median, ms.min, ms.max));
        return result_.rows.back();
    }

    void runCopies(const ImageGrey& grey) {
        std::vector<float> dst(grey.size(), 1.0f);  // touched: the copy measures bandwidth, not page faults
        const Stats cpu = timeRepeated(options_.warmup, options_.repeats, [&] { return cpuCopyMs(grey, dst); });
        cpuCopyMs_ = cpu.median;
        add("copy", "cpu_copy", cpu);
        // What a CPU filter call that returns a new image pays before computing: allocating and
        // value-initialising the ImageGrey (core/image.h fills it serially). Informative, not a limit.
        add("copy", "cpu_alloc", timeRepeated(options_.warmup, options_.repeats, [&] {
                const auto t0 = Clock::now();
                ImageGrey out(w_, h_);
                const double ms = msSince(t0);
                if (out.data()[out.size() - 1] != 0.0f) throw std::logic_error("ImageGrey not zeroed");
                return ms;
            }));
        if (copy_) {
            const std::size_t bytes = grey.size() * sizeof(float);
            const Stats gpu = timeRepeated(options_.warmup, options_.repeats, [&] { return copy_->copyMilliseconds(bytes); });
            gpuCopyMs_ = gpu.median;
            add("copy", "gpu_copy", gpu);
        }
    }

    // cpu_scalar and cpu_parallel write into an image kept between runs (as the copy and the GPU
    // kernel do); cpu_parallel_new is the call that returns a new image (+ allocation, zero-fill).
    template <class CpuIntoFn, class CpuNewFn, class GpuFn>
    void runStage(const std::string& stage, const ImageGrey& input, CpuIntoFn&& cpuInto, CpuNewFn&& cpuNew,
                  GpuFn&& gpuFn) {
        ImageGrey reference, out;
        auto timeInto = [&](cpu::Mode mode, ImageGrey& keep) {
            cpuInto(input, keep, mode);  // sized outside the timed region
            return timeRepeated(options_.warmup, options_.repeats, [&] {
                const auto t0 = Clock::now();
                cpuInto(input, keep, mode);
                return msSince(t0);
            });
        };
        add(stage, "cpu_scalar", timeInto(cpu::Mode::Scalar, reference)).maxAbsDiff = 0.0;
        const Stats parallel = timeInto(cpu::Mode::Parallel, out);
        add(stage, "cpu_parallel", parallel).maxAbsDiff = maxAbsDiff(out, reference);
        const Stats fresh = timeRepeated(options_.warmup, options_.repeats, [&] {
            const auto t0 = Clock::now();
            ImageGrey r = cpuNew(input, cpu::Mode::Parallel);
            const double ms = msSince(t0);
            out = std::move(r);  // the old image is freed outside the timed region
            return ms;
        });
        add(stage, "cpu_parallel_new", fresh).maxAbsDiff = maxAbsDiff(out, reference);
        if (!gpu_) return;

        std::vector<double> kernel, total;
        for (int i = 0; i < options_.warmup + options_.repeats; ++i) {
            const auto t0 = Clock::now();
            ImageGrey r = gpuFn(input);
            const double ms = msSince(t0);
            out = std::move(r);
            if (i < options_.warmup) continue;
            total.push_back(ms);
            kernel.push_back(gpu_->lastResult().gpuMilliseconds);
        }
        const double diff = maxAbsDiff(out, reference);
        add(stage, "gpu_kernel", summarise(kernel)).maxAbsDiff = diff;
        add(stage, "gpu_total", summarise(total)).maxAbsDiff = diff;
    }

    VulkanContext* context_;
    passes::GpuAamap* gpu_;
    GpuCopyTimer* copy_;
    const FilterBenchOptions& options_;
    const Progress& progress_;
    FilterBenchResult& result_;
    int w_ = 0, h_ = 0;
    double bytes_ = 0.0, cpuCopyMs_ = 0.0, gpuCopyMs_ = 0.0;
};

}  // namespace

std::string cpuName() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) != 0) continue;
        const auto colon = line.find(':');
        if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
    return "unknown CPU";
}

FilterBenchResult runFilterBench(VulkanContext* context, const FilterBenchOptions& options, const Progress& progress) {
    if (options.repeats < 1) throw std::invalid_argument("--repeats must be >= 1");
    if (options.warmup < 0) throw std::invalid_argument("--warmup must be >= 0");
    if (options.blurRadius < 0) throw std::invalid_argument("--blur-radius must be >= 0");
    for (int s : options.sizes)
        if (s < 1 || s > 16384) throw std::invalid_argument(fmt::format("size {} is outside [1, 16384]", s));

    FilterBenchResult result;
    result.threads = tbb::info::default_concurrency();
    result.cpu = fmt::format("{} ({} threads)", cpuName(), result.threads);
    std::unique_ptr<passes::GpuAamap> gpu;
    std::unique_ptr<GpuCopyTimer> copy;
    if (context) {
        result.device = context->deviceName();
        gpu = std::make_unique<passes::GpuAamap>(*context);
        copy = std::make_unique<GpuCopyTimer>(*context);
    }
    SizeRunner runner(context, gpu.get(), copy.get(), options, progress, result);
    for (int size : options.sizes) runner.run(size);
    return result;
}

double worstDisagreement(const FilterBenchResult& result) {
    double worst = 0.0;
    for (const FilterBenchRow& row : result.rows) {
        if (row.stage == "copy") continue;
        if (!(row.maxAbsDiff <= worst)) worst = std::isnan(row.maxAbsDiff) ? INFINITY : row.maxAbsDiff;
    }
    return worst;
}

}  // namespace aamap::bench
