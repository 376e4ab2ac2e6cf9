#include "snapshot_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>

namespace aamap::bench {
namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

SnapshotBenchResult runSnapshotBench(VulkanContext& context, const Scene& scene, const View& view,
                                     const SnapshotBenchOptions& options) {
    if (options.iterations < 1) throw std::invalid_argument("runSnapshotBench: iterations must be >= 1");
    SnapshotRenderer renderer(context, scene);
    for (int i = 0; i < options.warmup; ++i) renderer.render(view, options.width, options.height, options.settings);

    std::vector<std::vector<double>> perPass;
    std::vector<std::string> names;
    std::vector<double> gpu, total, readback;
    SnapshotBenchResult result;
    for (int i = 0; i < options.iterations; ++i) {
        const SnapshotResult r = renderer.render(view, options.width, options.height, options.settings);
        if (names.empty()) {
            for (const std::string& w : r.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
            for (const PassTiming& t : r.passTimes) names.push_back(t.pass);
            perPass.resize(names.size());
        }
        double sum = 0.0;
        for (std::size_t p = 0; p < r.passTimes.size() && p < perPass.size(); ++p) {
            perPass[p].push_back(r.passTimes[p].gpuMilliseconds);
            sum += r.passTimes[p].gpuMilliseconds;
        }
        gpu.push_back(sum);
        total.push_back(r.totalSeconds * 1e3);
        readback.push_back(r.readbackSeconds * 1e3);
        result.deviceName = r.deviceName;
        result.explain = r.explain;
    }
    for (std::size_t p = 0; p < names.size(); ++p) result.medianPassTimes.push_back({names[p], median(perPass[p])});
    result.medianGpuMilliseconds = median(gpu);
    result.medianTotalMilliseconds = median(total);
    result.medianReadbackMilliseconds = median(readback);
    return result;
}

std::string formatSnapshotBench(const SnapshotBenchResult& result, const SnapshotBenchOptions& options) {
    // The colour raster's size: the subpixel map shades at k x the render or once per pixel.
    const SnapshotSettings& s = options.settings;
    const bool subpixel = s.map == passes::AamapSource::Subpixel;
    const float scale = !subpixel ? s.scale
                        : s.subpixelShading == passes::SubpixelShading::Pixel ? 1.0f
                                                                              : static_cast<float>(s.subpixel);
    const long sw = std::lround(scale * static_cast<float>(options.width));
    const long sh = std::lround(scale * static_cast<float>(options.height));
    const std::string map = subpixel ? fmt::format("subpixel (k = {}, {} shading)", s.subpixel,
                                                   passes::toString(s.subpixelShading))
                                     : std::string(passes::toString(s.map));
    std::string out = fmt::format("device: {}\nshading {}x{} for a {}x{} render, map {}, up to {} area-light samples, "
                                  "{}, median of {} runs after {} warm-up\n",
                                  result.deviceName, sw, sh, options.width, options.height, map,
                                  options.settings.areaLightSamples,
                                  options.settings.shadows.enabled
                                      ? fmt::format("shadows at most {}^2 per face (by need, {} px per texel), pcf {}",
                                                    options.settings.shadows.resolution,
                                                    options.settings.shadows.texelPixels, options.settings.shadows.pcf)
                                      : std::string("no shadows"),
                                  options.iterations, options.warmup);
    out += fmt::format("{:<12} {:>10}\n", "pass", "GPU ms");
    for (const PassTiming& t : result.medianPassTimes) out += fmt::format("{:<12} {:>10.3f}\n", t.pass, t.gpuMilliseconds);
    out += fmt::format("{:<12} {:>10.3f}\n", "sum", result.medianGpuMilliseconds);
    out += fmt::format("total (CPU wall, incl. upload + readback): {:.3f} ms\n", result.medianTotalMilliseconds);
    out += fmt::format("readback (CPU wall):                       {:.3f} ms\n", result.medianReadbackMilliseconds);
    return out;
}

}  // namespace aamap::bench
