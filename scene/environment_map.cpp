#include "scene/environment_map.h"

#include <exception>

#include <fmt/format.h>

#include "core/image_io.h"
#include "scene/text_util.h"
#include "scene/texture_loader.h"

namespace aamap {

bool loadEnvironmentMap(const std::filesystem::path& path, EnvironmentLight& env, std::string& error) {
    const std::string ext = text::toLower(path.extension().string());
    if (ext != ".exr" && ext != ".hdr") {
        error = fmt::format("environment map '{}' is not EXR or Radiance HDR (8-bit images hold no radiance)",
                            path.string());
        return false;
    }
    env.mapPath = path;
    if (ext == ".exr") {
        try {
            const ImageRGB image = readExr(path);
            env.mapWidth = image.width();
            env.mapHeight = image.height();
            env.map.resize(image.size());
            for (int y = 0; y < image.height(); ++y)
                for (int x = 0; x < image.width(); ++x)
                    env.map[static_cast<std::size_t>(y) * image.width() + x] = image.at(x, y);
            return true;
        } catch (const std::exception& e) {
            error = fmt::format("cannot read environment map '{}': {}", path.string(), e.what());
            return false;
        }
    }
    std::string why;
    const auto texture = loadTexture(path, &why);
    if (!texture) {
        error = fmt::format("cannot read environment map '{}': {}", path.string(), why);
        return false;
    }
    env.mapWidth = texture->width;
    env.mapHeight = texture->height;
    env.map.resize(static_cast<std::size_t>(texture->width) * texture->height);
    for (std::size_t i = 0; i < env.map.size(); ++i)
        env.map[i] = {texture->rgba[4 * i], texture->rgba[4 * i + 1], texture->rgba[4 * i + 2]};
    return true;
}

}  // namespace aamap
