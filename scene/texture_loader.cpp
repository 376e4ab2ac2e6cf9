#include "scene/texture_loader.h"

#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <system_error>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <stb_image.h>  // the implementation is in libstb

#include "core/srgb.h"
#include "scene/text_util.h"

namespace aamap {
namespace fs = std::filesystem;

std::optional<fs::path> resolveCaseInsensitive(const fs::path& baseDir, std::string_view name) {
    std::string cleaned(text::trim(name));
    for (char& c : cleaned) {
        if (c == '\\') c = '/';  // MTL files written on Windows
    }
    if (cleaned.empty()) return std::nullopt;
    const fs::path relative(cleaned);
    const fs::path direct = relative.is_absolute() ? relative : baseDir / relative;
    std::error_code ec;
    if (fs::is_regular_file(direct, ec)) return direct.lexically_normal();

    // Walk the components, matching each one case-insensitively where the exact name is missing.
    fs::path current = relative.is_absolute() ? relative.root_path() : baseDir;
    for (const fs::path& part : relative.relative_path()) {
        const std::string partName = part.string();
        if (partName == "." || partName.empty()) continue;
        if (partName == "..") {
            current /= part;
            continue;
        }
        if (fs::exists(current / part, ec)) {
            current /= part;
            continue;
        }
        const std::string wanted = text::toLower(partName);
        std::optional<fs::path> match;
        for (fs::directory_iterator it(current.empty() ? fs::path(".") : current, ec), end; !ec && it != end; it.increment(ec)) {
            if (text::toLower(it->path().filename().string()) == wanted) {
                match = it->path();
                break;
            }
        }
        if (!match) return std::nullopt;
        current = *match;
    }
    if (!fs::is_regular_file(current, ec)) return std::nullopt;
    return current.lexically_normal();
}

namespace {

// Decoded textures are float RGBA (16 bytes a texel): 8192 x 8192 is 1 GiB. A header declaring
// more is refused before stb_image allocates for it (a hostile or corrupt file, or a mistake).
constexpr long long kMaxTexels = 8192LL * 8192LL;

// Binary PNM (P5/P6) other than 8 bits with maxval 255 is refused: Debian 12's stb_image reads
// 16-bit samples in the wrong byte order and, converting channels, past its buffer (found by
// fuzz_texture; tests/corpus/texture/warn-16-bit-pnm-*), and it never scales by maxval. So is a
// header stb_image would accept but that does not describe the file: a field that is not a
// number (stb reads it as 0: a 22-byte file declared 5 x 11512711 decoded to 920 MB of zeros,
// found by fuzz_texture, tests/corpus/texture/warn-pnm-maxval-not-a-number.ppm), or more texels
// than the file holds (warn-pnm-data-truncated.ppm).
bool supportedPnm(const std::string& name, std::string* error) {
    std::ifstream in(name, std::ios::binary);
    char magic[2] = {};
    if (!in.read(magic, 2) || magic[0] != 'P' || (magic[1] != '5' && magic[1] != '6')) return true;  // not PNM
    const auto fail = [&](const std::string& why) {
        if (error) *error = why;
        return false;
    };
    long long fields[3] = {};
    for (long long& field : fields) {
        int c = in.get();
        while (c != EOF && (std::isspace(c) || c == '#')) {
            if (c == '#')
                while (c != EOF && c != '\n') c = in.get();  // a comment to the end of the line
            c = in.get();
        }
        if (c == EOF || !std::isdigit(c)) return fail("malformed PNM header: width, height and maxval must be numbers");
        for (; c != EOF && std::isdigit(c) && field < (1LL << 40); c = in.get()) field = 10 * field + (c - '0');
    }
    if (fields[2] != 255)
        return fail(fmt::format("PNM with maxval {} is not supported (8-bit samples with maxval 255 only)", fields[2]));
    // The loop consumed the one whitespace character after maxval: the samples start here.
    const long long header = static_cast<long long>(in.tellg());
    std::error_code ec;
    const auto size = static_cast<long long>(fs::file_size(name, ec));
    // In double: each field may be up to 2^40, their product overflows 64 bits.
    const double need = static_cast<double>(fields[0]) * static_cast<double>(fields[1]) * (magic[1] == '5' ? 1 : 3);
    if (!ec && header >= 0 && static_cast<double>(size - header) < need)
        return fail(fmt::format("PNM data truncated: the header declares {} x {} texels ({} bytes), the file holds {}",
                                fields[0], fields[1], need, std::max(0LL, size - header)));
    return true;
}

bool withinTexelLimit(const std::string& name, std::string* error) {
    int width = 0, height = 0, channels = 0;
    if (!stbi_info(name.c_str(), &width, &height, &channels)) return true;  // stbi_load reports why
    if (static_cast<long long>(width) * height <= kMaxTexels) return true;
    if (error) *error = fmt::format("{} x {} texels, more than the 8192 x 8192 texture limit", width, height);
    return false;
}

// 8-bit texels in the file's own channel count: stb_image's channel conversion (req_comp) is not
// used either, so a format whose conversion is as broken as 16-bit PNM's cannot overrun a buffer.
struct Decoded8 {
    unsigned char* pixels = nullptr;
    int width = 0, height = 0, channels = 0;
    Decoded8() = default;
    Decoded8(const Decoded8&) = delete;  // owns `pixels`
    Decoded8& operator=(const Decoded8&) = delete;
    ~Decoded8() { stbi_image_free(pixels); }
    // Texel i as RGBA: grey and grey + alpha replicate the grey, a missing alpha is opaque.
    std::array<unsigned char, 4> rgba(std::size_t i) const {
        const unsigned char* t = pixels + i * static_cast<std::size_t>(channels);
        switch (channels) {
            case 1: return {t[0], t[0], t[0], 255};
            case 2: return {t[0], t[0], t[0], t[1]};
            case 3: return {t[0], t[1], t[2], 255};
            default: return {t[0], t[1], t[2], t[3]};
        }
    }
};

bool decode8(const std::string& name, Decoded8& out, std::string* error) {
    out.pixels = stbi_load(name.c_str(), &out.width, &out.height, &out.channels, 0);
    if (out.pixels && out.channels >= 1 && out.channels <= 4) return true;
    if (error) {
        *error = out.pixels ? fmt::format("{} channels per texel", out.channels)
                 : stbi_failure_reason() ? stbi_failure_reason()
                                         : "unknown stb_image error";
    }
    return false;
}

}  // namespace

std::optional<Texture> loadTexture(const fs::path& path, std::string* error, bool raw) {
    const std::string name = path.string();
    if (!supportedPnm(name, error) || !withinTexelLimit(name, error)) return std::nullopt;
    int width = 0, height = 0, channels = 0;
    Texture texture;
    texture.path = path;
    if (stbi_is_hdr(name.c_str())) {
        float* pixels = stbi_loadf(name.c_str(), &width, &height, &channels, 4);
        if (!pixels) {
            if (error) *error = stbi_failure_reason() ? stbi_failure_reason() : "unknown stb_image error";
            return std::nullopt;
        }
        texture.rgba.assign(pixels, pixels + static_cast<std::size_t>(width) * height * 4);
        stbi_image_free(pixels);
    } else {
        Decoded8 decoded;
        if (!decode8(name, decoded, error)) return std::nullopt;
        width = decoded.width;
        height = decoded.height;
        std::array<float, 256> toLinear{};
        for (int i = 0; i < 256; ++i) toLinear[i] = raw ? static_cast<float>(i) / 255.0f : srgbToLinear(static_cast<float>(i) / 255.0f);
        const std::size_t texels = static_cast<std::size_t>(width) * height;
        texture.rgba.resize(4 * texels);
        for (std::size_t i = 0; i < texels; ++i) {
            const std::array<unsigned char, 4> t = decoded.rgba(i);
            for (int c = 0; c < 3; ++c) texture.rgba[4 * i + c] = toLinear[t[c]];
            texture.rgba[4 * i + 3] = static_cast<float>(t[3]) / 255.0f;
        }
    }
    texture.width = width;
    texture.height = height;
    return texture;
}

std::optional<Texture> loadCoverageTexture(const fs::path& path, std::string* error) {
    const std::string name = path.string();
    if (!supportedPnm(name, error) || !withinTexelLimit(name, error)) return std::nullopt;
    Decoded8 decoded;
    if (!decode8(name, decoded, error)) return std::nullopt;
    const bool hasAlpha = decoded.channels == 2 || decoded.channels == 4;
    Texture texture;
    texture.path = path;
    texture.width = decoded.width;
    texture.height = decoded.height;
    const std::size_t texels = static_cast<std::size_t>(decoded.width) * decoded.height;
    texture.rgba.resize(4 * texels);
    for (std::size_t i = 0; i < texels; ++i) {
        const std::array<unsigned char, 4> t = decoded.rgba(i);
        const float coverage = static_cast<float>(hasAlpha ? t[3] : t[0]) / 255.0f;
        for (int c = 0; c < 4; ++c) texture.rgba[4 * i + c] = coverage;
    }
    return texture;
}

int TextureCache::get(const fs::path& baseDir, std::string_view name, const fs::path& referrer,
                      std::vector<std::string>* warnings, bool raw) {
    return load(baseDir, name, referrer, warnings, raw ? Kind::RawColour : Kind::Colour);
}

int TextureCache::getCoverage(const fs::path& baseDir, std::string_view name, const fs::path& referrer,
                              std::vector<std::string>* warnings) {
    return load(baseDir, name, referrer, warnings, Kind::Coverage);
}

int TextureCache::load(const fs::path& baseDir, std::string_view name, const fs::path& referrer,
                       std::vector<std::string>* warnings, Kind kind) {
    const auto warn = [&](const std::string& message) {
        spdlog::warn("{}", message);
        if (warnings) warnings->push_back(message);
    };
    const auto resolved = resolveCaseInsensitive(baseDir, name);
    if (!resolved) {
        warn(fmt::format("{}: texture '{}' not found (looked in {}); using the plain colour instead", referrer.string(),
                         name, baseDir.string()));
        return -1;
    }
    const std::pair key(*resolved, kind);
    if (const auto it = byPath_.find(key); it != byPath_.end()) return it->second;
    std::string error;
    auto texture = kind == Kind::Coverage ? loadCoverageTexture(*resolved, &error)
                                          : loadTexture(*resolved, &error, kind == Kind::RawColour);
    if (!texture) {
        warn(fmt::format("{}: texture '{}' could not be decoded ({}); using the plain colour instead",
                         referrer.string(), resolved->string(), error));
        byPath_[key] = -1;
        return -1;
    }
    const int index = static_cast<int>(textures_.size());
    textures_.push_back(std::move(*texture));
    byPath_[key] = index;
    return index;
}

}  // namespace aamap
