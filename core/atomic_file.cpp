#include "core/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <unistd.h>

#include <fmt/format.h>

#include "core/error.h"

namespace aamap {

void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path&)>& write) {
    // Same directory as the target so that rename() is atomic (same file system).
    std::filesystem::path tmp = path;
    tmp += fmt::format(".tmp-{}", ::getpid());
    try {
        write(tmp);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw EnvironmentError(fmt::format("{}: cannot write: {}", path.string(), std::strerror(err)));
    }
}

void writeTextAtomically(const std::filesystem::path& path, std::string_view contents) {
    writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        out.close();
        if (!out) throw EnvironmentError(fmt::format("{}: cannot write: {}", path.string(), std::strerror(errno)));
    });
}

}  // namespace aamap
