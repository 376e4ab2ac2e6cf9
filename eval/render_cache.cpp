#include "eval/render_cache.h"

#include <atomic>
#include <cstdio>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace aamap {
namespace fs = std::filesystem;

namespace {

bool isTemporary(const fs::path& p) { return p.filename().string().find(".tmp-") != std::string::npos; }

int removeTemporaries(const fs::path& dir) {
    int removed = 0;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return 0;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        if (!isTemporary(e.path())) continue;
        std::error_code rm;
        fs::remove_all(e.path(), rm);
        if (!rm) ++removed;
    }
    return removed;
}

}  // namespace

RenderCache::RenderCache(fs::path dir, const fs::path& cleanAlso) : dir_(std::move(dir)) {
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec) throw EnvironmentError(fmt::format("{}: cannot create the render cache: {}", dir_.string(), ec.message()));
    removed_ = removeTemporaries(dir_);
    if (!cleanAlso.empty()) removed_ += removeTemporaries(cleanAlso);
    if (removed_ > 0) spdlog::info("removed {} temporary file(s) left by an interrupted run", removed_);
}

bool RenderCache::has(const std::string& key) const {
    std::error_code ec;
    return fs::is_regular_file(record(key), ec);
}

void RenderCache::commit(const std::string& key, const std::function<void(const fs::path&)>& write) {
    static std::atomic<int> counter{0};
    const fs::path tmp = dir_ / fmt::format("{}.tmp-{}-{}", key, ::getpid(), counter++);
    std::error_code ec;
    fs::remove_all(tmp, ec);
    fs::create_directories(tmp, ec);
    if (ec) throw EnvironmentError(fmt::format("{}: cannot create: {}", tmp.string(), ec.message()));
    try {
        write(tmp);
        if (!fs::is_regular_file(tmp / "record.json"))
            throw EnvironmentError(fmt::format("{}: cache entry without record.json", tmp.string()));
        const fs::path final = entry(key);
        fs::remove_all(final, ec);  // a stale, incomplete entry (no record.json)
        if (std::rename(tmp.c_str(), final.c_str()) != 0)
            throw EnvironmentError(fmt::format("{}: cannot rename into place", final.string()));
    } catch (...) {
        fs::remove_all(tmp, ec);
        throw;
    }
}

void copyFileAtomically(const fs::path& from, const fs::path& to) {
    writeFileAtomically(to, [&](const fs::path& tmp) {
        std::error_code ec;
        fs::copy_file(from, tmp, fs::copy_options::overwrite_existing, ec);
        if (ec) throw EnvironmentError(fmt::format("cannot copy {} to {}: {}", from.string(), to.string(), ec.message()));
    });
}

}  // namespace aamap
