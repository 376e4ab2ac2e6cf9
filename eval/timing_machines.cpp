#include "eval/timing_machines.h"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "tracer/strategy.h"

namespace aamap {

namespace {

std::string describe(const MachineInfo& m) { return fmt::format("{} ({})", m.hostname, m.cpuModel); }

bool sameMachine(const MachineInfo& a, const MachineInfo& b) {
    return a.hostname == b.hostname && a.cpuModel == b.cpuModel;
}

}  // namespace

std::vector<std::string> mixedMachineWarnings(const Results& results) {
    const std::vector<RenderRecord>& renders = results.renders;
    // The report's baseline: the first uniform series.
    const auto base = std::find_if(renders.begin(), renders.end(), [](const RenderRecord& r) { return r.strategy == baselineStrategyName(); });
    if (base == renders.end()) return {};
    std::set<int> rpps;
    std::set<std::string> machines;
    for (const RenderRecord& b : renders) {
        if (b.series != base->series) continue;
        for (const RenderRecord& r : renders) {
            if (r.series == base->series || r.maxRaysPerPixel != b.maxRaysPerPixel || sameMachine(r.machine, b.machine))
                continue;
            rpps.insert(b.maxRaysPerPixel);
            machines.insert(describe(b.machine));
            machines.insert(describe(r.machine));
        }
    }
    if (rpps.empty()) return {};
    return {fmt::format("the speedups at rpp {} divide times traced on different machines ({}): they compare the "
                        "machines as well as the strategies; timing.same_machine: true traces each rpp's renders on one",
                        fmt::join(rpps, ", "), fmt::join(machines, "; "))};
}

}  // namespace aamap
