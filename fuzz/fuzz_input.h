#pragma once
// Shared by the libFuzzer targets: the loaders read files, so each input is written to a scratch
// file (in /dev/shm where it exists) and the loader runs on that. A loader may accept the input or
// throw InputError; anything else -- another exception, a sanitizer report, a crash -- is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <spdlog/spdlog.h>
#include <unistd.h>

#include "core/error.h"

namespace aamap::fuzz {

inline const std::filesystem::path& scratchDir() {
    static const std::filesystem::path dir = [] {
        const std::filesystem::path root =
            std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
        auto path = root / ("aamap_fuzz_" + std::to_string(::getpid()));
        std::filesystem::create_directories(path);
        spdlog::set_level(spdlog::level::off);  // warnings are expected; printing them only slows the run
        std::atexit([] { std::error_code ec; std::filesystem::remove_all(scratchDir(), ec); });
        return path;
    }();
    return dir;
}

inline std::filesystem::path writeScratch(const std::string& name, std::string_view bytes) {
    const auto path = scratchDir() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
}

inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// Runs f(); InputError is an accepted outcome, any other exception aborts so libFuzzer keeps it.
template <class F>
void expectLoadOrInputError(F&& f) {
    try {
        f();
    } catch (const InputError&) {
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz: unexpected exception (not InputError): %s\n", e.what());
        std::abort();
    }
}

}  // namespace aamap::fuzz
