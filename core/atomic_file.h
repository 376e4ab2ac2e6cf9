#pragma once
// Outputs are written to a temporary name in the destination folder and renamed into place,
// so a crash, a full disk or a SIGKILL never leaves a half-written file under the final name.
#include <filesystem>
#include <functional>
#include <string_view>

namespace aamap {

// Calls write(tmpPath), then renames tmpPath to path. If write throws, the temporary is removed
// and the exception propagates. Throws EnvironmentError if the rename fails.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& tmpPath)>& write);

// Convenience for text and byte payloads.
void writeTextAtomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace aamap
