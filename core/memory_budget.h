#pragma once
// Fail early, before the big allocations, when a job cannot fit in memory: the estimate and the
// limit in the message, instead of an OOM kill halfway through.
#include <cstdint>
#include <string>

namespace aamap {

// The memory a job may use: AAMAP_MEMORY_LIMIT (bytes; for tests and shared machines) if set, else
// MemAvailable from /proc/meminfo, else physical memory. 0 if none can be found (no check).
std::uint64_t memoryLimitBytes();

// Throws EnvironmentError "<what> needs about X GiB (<detail>), more than the Y GiB available" (MiB below 1 GiB)
// when estimateBytes exceeds memoryLimitBytes().
void checkMemoryBudget(std::uint64_t estimateBytes, const std::string& what, const std::string& detail);

}  // namespace aamap
