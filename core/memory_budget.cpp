#include "core/memory_budget.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <unistd.h>

#include "core/error.h"

namespace aamap {

std::uint64_t memoryLimitBytes() {
    if (const char* env = std::getenv("AAMAP_MEMORY_LIMIT"); env && *env) return std::strtoull(env, nullptr, 10);
    std::ifstream meminfo("/proc/meminfo");
    for (std::string line; std::getline(meminfo, line);) {
        std::istringstream in(line);
        std::string key;
        std::uint64_t kib = 0;
        if (in >> key >> kib && key == "MemAvailable:") return kib * 1024;
    }
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && pageSize > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize) : 0;
}

void checkMemoryBudget(std::uint64_t estimateBytes, const std::string& what, const std::string& detail) {
    const std::uint64_t limit = memoryLimitBytes();
    if (limit == 0 || estimateBytes <= limit) return;
    const auto size = [](std::uint64_t bytes) {
        constexpr double kMiB = 1024.0 * 1024.0;
        return bytes >= 1024 * kMiB ? fmt::format("{:.3g} GiB", bytes / (1024 * kMiB)) : fmt::format("{:.3g} MiB", bytes / kMiB);
    };
    throw EnvironmentError(fmt::format("{} needs about {} ({}), more than the {} available{}", what, size(estimateBytes),
                                       detail, size(limit), std::getenv("AAMAP_MEMORY_LIMIT") ? " (AAMAP_MEMORY_LIMIT)" : ""));
}

}  // namespace aamap
