#include "scene/load_scene.h"

#include <filesystem>
#include <system_error>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "scene/builtin_scenes.h"
#include "scene/gltf_loader.h"
#include "scene/obj_loader.h"
#include "scene/text_util.h"
#include "scene/view_file.h"

namespace aamap {
namespace fs = std::filesystem;

Scene loadScene(const std::string& spec) {
    constexpr std::string_view kBuiltin = "builtin:";
    if (spec.starts_with(kBuiltin)) return builtinScene(std::string_view(spec).substr(kBuiltin.size()));

    const fs::path path(spec);
    const std::string ext = text::toLower(path.extension().string());
    if (ext == ".gltf" || ext == ".glb") return loadGltf(path);
    if (ext != ".obj") {
        throw InputError(path, fmt::format("unsupported scene format '{}' (expected .obj, .gltf, .glb or builtin:<name>)",
                                           path.extension().string()));
    }
    Scene scene = loadObj(path);
    fs::path viewFile = path;
    viewFile.replace_extension(".vf");
    std::error_code ec;
    if (fs::is_regular_file(viewFile, ec)) {
        scene.views = loadViewFile(viewFile);
        spdlog::info("{}: {} view(s) from {}", path.string(), scene.views.size(), viewFile.string());
    }
    return scene;
}

}  // namespace aamap
