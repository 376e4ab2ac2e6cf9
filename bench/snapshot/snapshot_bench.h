#pragma once
// The Snapshot benchmark as a function, so other tools can run it on any scene and view.
#include <string>
#include <vector>

#include "passes/snapshot.h"

namespace aamap::bench {

struct SnapshotBenchOptions {
    int width = 512, height = 512;  // render resolution; the snapshot is scale times larger
    SnapshotSettings settings;      // scale 1.5: the paper's 768x768 snapshot for a 512x512 render
    int warmup = 3;
    int iterations = 20;
};

struct SnapshotBenchResult {
    std::string deviceName;
    std::vector<PassTiming> medianPassTimes;  // per pass, median GPU ms over the iterations
    double medianGpuMilliseconds = 0.0;       // median of the per-run sum over passes
    double medianTotalMilliseconds = 0.0;     // median CPU wall time of render() (upload + run + readback)
    double medianReadbackMilliseconds = 0.0;
    std::string explain;  // the compiled graph of the last run
};

SnapshotBenchResult runSnapshotBench(VulkanContext& context, const Scene& scene, const View& view,
                                     const SnapshotBenchOptions& options);

// A human-readable table of the result.
std::string formatSnapshotBench(const SnapshotBenchResult& result, const SnapshotBenchOptions& options);

}  // namespace aamap::bench
