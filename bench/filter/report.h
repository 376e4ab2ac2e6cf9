#pragma once
// Outputs of the filter benchmark: the CSV the plot script reads, and the readable tables.
#include <string>

#include "filter_bench.h"

namespace aamap::bench {

// One row per (stage, size, implementation); device and CPU names on every row.
std::string filterBenchCsv(const FilterBenchResult& result);

// Median / min / max per implementation, GB/s and fraction of copy, then the speedups.
std::string filterBenchTable(const FilterBenchResult& result, const FilterBenchOptions& options);

}  // namespace aamap::bench
