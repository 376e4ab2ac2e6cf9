#include "scene/load_scene.h"

#include <filesystem>
#include <system_error>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "scene/builtin_scenes.h"
#include "scene/gltf_loader.h"
#include "scene/lights.h"
#include "scene/mesh_orientation.h"
#include "scene/mitsuba_loader.h"
#include "scene/obj_loader.h"
#include "scene/text_util.h"
#include "scene/view_file.h"

namespace aamap {
namespace fs = std::filesystem;

namespace {

Scene loadSceneFile(const std::string& spec) {
    constexpr std::string_view kBuiltin = "builtin:";
    if (spec.starts_with(kBuiltin)) return builtinScene(std::string_view(spec).substr(kBuiltin.size()));

    const fs::path path(spec);
    const std::string ext = text::toLower(path.extension().string());
    if (ext == ".gltf" || ext == ".glb") return loadGltf(path);
    if (ext == ".xml") return loadMitsuba(path);
    if (ext != ".obj") {
        throw InputError(path, fmt::format("unsupported scene format '{}' (expected .obj, .gltf, .glb, .xml (Mitsuba) "
                                           "or builtin:<name>)", path.extension().string()));
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

}  // namespace

Scene loadScene(const std::string& spec) {
    Scene scene = loadSceneFile(spec);
    if (const std::size_t reversed = orientTrianglesToNormals(scene.mesh); reversed > 0)
        spdlog::info("scene '{}': {} triangle(s) wound against their vertex normals, turned to face where the normals "
                     "point (the emitting side of a light, the outside of glass)", scene.name, reversed);
    // Where the scene is and how big, so that cameras and lights can be placed in its units.
    const Bounds b = sceneBounds(scene);
    spdlog::info("scene '{}': {} triangles, bounds ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}), size "
                 "{:.4g} x {:.4g} x {:.4g}", scene.name, scene.mesh.triangles.size(), b.lo.x, b.lo.y, b.lo.z, b.hi.x,
                 b.hi.y, b.hi.z, b.extent().x, b.extent().y, b.extent().z);
    return scene;
}

}  // namespace aamap
