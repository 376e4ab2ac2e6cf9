#pragma once
// Speedups divide one render's time by another's; when the two were traced on different machines
// (an experiment spread over a cluster), the ratio measures the machines as much as the strategies.
#include <string>
#include <vector>

#include "eval/results.h"

namespace aamap {

// One warning per experiment whose speedup pairs (the baseline uniform series against every other
// series at the same rpp, as in the report's speedup table) mix machines; empty when none do.
std::vector<std::string> mixedMachineWarnings(const Results& results);

}  // namespace aamap
