#include "report.h"

#include <cmath>
#include <map>
#include <optional>

#include <fmt/format.h>

namespace aamap::bench {
namespace {

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::string number(double v) { return std::isnan(v) ? std::string() : fmt::format("{:.6g}", v); }

const FilterBenchRow* find(const FilterBenchResult& r, const std::string& stage, const std::string& impl, int w) {
    for (const FilterBenchRow& row : r.rows)
        if (row.stage == stage && row.impl == impl && row.width == w) return &row;
    return nullptr;
}

std::string ratio(const FilterBenchRow* num, const FilterBenchRow* den) {
    if (!num || !den || den->ms.median <= 0) return "-";
    return fmt::format("{:.2f}x", num->ms.median / den->ms.median);
}

}  // namespace

std::string filterBenchCsv(const FilterBenchResult& result) {
    std::string out =
        "stage,impl,width,height,pixels,median_ms,min_ms,max_ms,repeats,bytes_moved,gb_per_s,fraction_of_copy,"
        "max_abs_diff,device,cpu\n";
    const std::string device = quoted(result.device.empty() ? "none" : result.device), cpu = quoted(result.cpu);
    for (const FilterBenchRow& r : result.rows)
        out += fmt::format("{},{},{},{},{},{},{},{},{},{:.0f},{},{},{},{},{}\n", r.stage, r.impl, r.width, r.height,
                           static_cast<long long>(r.width) * r.height, number(r.ms.median), number(r.ms.min),
                           number(r.ms.max), r.ms.repeats, r.bytesMoved, number(r.gigabytesPerSecond()),
                           number(r.fractionOfCopy), number(r.maxAbsDiff), device, cpu);
    return out;
}

std::string filterBenchTable(const FilterBenchResult& result, const FilterBenchOptions& options) {
    std::string out = fmt::format("device: {}\ncpu:    {}\n", result.device.empty() ? "none (CPU rows only)" : result.device,
                                  result.cpu);
    out += fmt::format("median of {} runs after {} warm-up; [min, max]; bytes model: 4 B read + 4 B written per "
                       "pixel; 'of copy' = copy median / median on the same side (CPU or GPU)\n\n",
                       options.repeats, options.warmup);
    out += fmt::format("{:<9} {:>9} {:<16} {:>11} {:>11} {:>11} {:>8} {:>8} {:>9}\n", "stage", "size", "impl",
                       "median ms", "min ms", "max ms", "GB/s", "of copy", "max|diff|");
    for (const FilterBenchRow& r : result.rows)
        out += fmt::format("{:<9} {:>9} {:<16} {:>11.3f} {:>11.3f} {:>11.3f} {:>8.2f} {:>8} {:>9}\n", r.stage,
                           fmt::format("{}x{}", r.width, r.height), r.impl, r.ms.median, r.ms.min, r.ms.max,
                           r.gigabytesPerSecond(),
                           std::isnan(r.fractionOfCopy) ? std::string("-")
                                                        : fmt::format("{:.0f}%", 100.0 * r.fractionOfCopy),
                           std::isnan(r.maxAbsDiff) ? std::string("") : fmt::format("{:.1e}", r.maxAbsDiff));

    out += "\nspeedups (ratio of medians; > 1 means the second-named is faster)\n";
    out += fmt::format("{:<9} {:>9} {:>14} {:>16} {:>16} {:>15}\n", "stage", "size", "1T / MT CPU",
                       "1T CPU / GPU krn", "MT CPU / GPU krn", "MT CPU / GPU tot");
    for (const std::string& stage : options.stages)
        for (int s : options.sizes) {
            const FilterBenchRow* scalar = find(result, stage, "cpu_scalar", s);
            const FilterBenchRow* parallel = find(result, stage, "cpu_parallel", s);
            const FilterBenchRow* kernel = find(result, stage, "gpu_kernel", s);
            const FilterBenchRow* total = find(result, stage, "gpu_total", s);
            out += fmt::format("{:<9} {:>9} {:>14} {:>16} {:>16} {:>15}\n", stage, fmt::format("{}x{}", s, s),
                               ratio(scalar, parallel), ratio(scalar, kernel), ratio(parallel, kernel),
                               ratio(parallel, total));
        }
    return out;
}

}  // namespace aamap::bench
