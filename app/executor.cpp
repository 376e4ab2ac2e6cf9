#include "app/executor.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace aamap::app {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string workListJson(const Experiment& experiment, const fs::path& outDir, const RunOptions& options,
                         const WorkerCommand& worker) {
    std::vector<std::string> base{"run", fs::absolute(worker.config).string()};
    for (const std::string& o : worker.overrides) {
        base.push_back("--set");
        base.push_back(o);
    }
    if (worker.threads >= 0) {
        base.push_back("--threads");
        base.push_back(std::to_string(worker.threads));
    }
    if (worker.validation) base.push_back("--validation");
    Json items = Json::array();
    for (const WorkItem& w : listMissingWork(experiment, outDir, options)) {
        std::vector<std::string> args = base;
        args.push_back("--only");
        args.push_back(w.key);
        items.push_back({{"kind", w.kind}, {"key", w.key}, {"name", w.name}, {"threads", w.threads},
                         {"needs_snapshot", w.needsSnapshot}, {"group", w.group}, {"args", args}});
    }
    const Json list = {{"format", "aamap-work-1"},
                       {"cache", fs::absolute(experimentCacheDir(outDir, options)).string()},
                       {"items", items}};
    return list.dump(2) + "\n";
}

void execRayExecutor(int argc, char** argv, const std::string& rayAddress) {
    const char* envPython = std::getenv("AAMAP_PYTHON");
    const fs::path python = envPython && *envPython ? fs::path(envPython) : fs::path(AAMAP_SOURCE_DIR) / ".venv/bin/python";
    const fs::path script = fs::path(AAMAP_SOURCE_DIR) / "tools/ray_executor.py";
    if (::access(python.c_str(), X_OK) != 0)
        throw EnvironmentError(fmt::format("--executor ray: no Python at {} (run tools/python-env.sh, which installs "
                                           "ray, or set AAMAP_PYTHON)", python.string()));
    if (!fs::is_regular_file(script)) throw EnvironmentError(fmt::format("--executor ray: {} not found", script.string()));
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw EnvironmentError(fmt::format("--executor ray: cannot find this binary: {}", ec.message()));

    std::vector<std::string> args{python.string(), script.string(), "--binary", self.string()};
    if (!rayAddress.empty()) {
        args.push_back("--address");
        args.push_back(rayAddress);
    }
    args.push_back("--");
    for (int i = 1; i < argc; ++i) {  // the same command, run by the driver and its workers
        const std::string a = argv[i];
        if (a == "--executor" || a == "--ray-address") ++i;
        else if (!a.starts_with("--executor=") && !a.starts_with("--ray-address=")) args.push_back(a);
    }
    std::vector<char*> cargs;
    for (std::string& a : args) cargs.push_back(a.data());
    cargs.push_back(nullptr);
    std::fflush(nullptr);
    ::execv(python.c_str(), cargs.data());
    throw EnvironmentError(fmt::format("--executor ray: cannot run {}: {}", python.string(), std::strerror(errno)));
}

}  // namespace aamap::app
