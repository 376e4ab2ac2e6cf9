#include "eval/file_digest.h"

#include <cstdint>
#include <fstream>

#include <fmt/format.h>

namespace aamap {

std::string fileDigest(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return "unreadable";
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a 64, as the keys themselves
    char buffer[1 << 16];
    while (in) {
        in.read(buffer, sizeof buffer);
        for (std::streamsize i = 0; i < in.gcount(); ++i) {
            h ^= static_cast<unsigned char>(buffer[i]);
            h *= 0x100000001b3ull;
        }
    }
    if (in.bad()) return "unreadable";
    return fmt::format("{:016x}", h);
}

}  // namespace aamap
