#pragma once
// Texture files for the scene loaders: path resolution that forgives the usual OBJ/MTL habits
// (Windows backslashes, a different letter case than on disk) and decoding to linear RGBA.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace aamap {

// Finds `name` (relative to `baseDir`, or absolute) on disk; where the exact path does not exist,
// each path component is matched case-insensitively against its folder. nullopt if not found.
std::optional<std::filesystem::path> resolveCaseInsensitive(const std::filesystem::path& baseDir, std::string_view name);

// Decodes an image with stb_image to linear RGBA floats, row 0 at the top. 8-bit images are taken
// to be sRGB-encoded (colour channels linearised, alpha left as is) unless `raw` (Mitsuba's
// bitmap raw=true: the values / 255 as they are); .hdr files are already linear.
// On failure returns nullopt and sets `error`.
std::optional<Texture> loadTexture(const std::filesystem::path& path, std::string* error = nullptr, bool raw = false);

// Decodes a coverage map (MTL map_d) to a texture whose alpha channel is the coverage: the image's
// alpha channel if it has one, else its first channel. Coverage is data, not colour: no sRGB decode.
std::optional<Texture> loadCoverageTexture(const std::filesystem::path& path, std::string* error = nullptr);

// De-duplicates textures by resolved path while a scene is loaded.
class TextureCache {
public:
    explicit TextureCache(std::vector<Texture>& textures) : textures_(textures) {}

    // Index into the scene's textures, or -1 (after a spdlog warning naming the texture and the
    // referring file, also appended to `warnings` if given) when it is missing or unreadable.
    // raw: no sRGB decode of 8-bit images (loadTexture); cached apart from the decoded texture.
    int get(const std::filesystem::path& baseDir, std::string_view name, const std::filesystem::path& referrer,
            std::vector<std::string>* warnings = nullptr, bool raw = false);
    // The same for a coverage map (loadCoverageTexture), cached apart from colour textures.
    int getCoverage(const std::filesystem::path& baseDir, std::string_view name, const std::filesystem::path& referrer,
                    std::vector<std::string>* warnings = nullptr);

private:
    enum class Kind { Colour, Coverage, RawColour };
    int load(const std::filesystem::path& baseDir, std::string_view name, const std::filesystem::path& referrer,
             std::vector<std::string>* warnings, Kind kind);

    std::vector<Texture>& textures_;
    std::map<std::pair<std::filesystem::path, Kind>, int> byPath_;
};

}  // namespace aamap
