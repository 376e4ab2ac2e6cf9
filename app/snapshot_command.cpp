// `aamap snapshot`: load a scene (plus a light file), run only the Snapshot graph, write its
// images, and optionally print or dump the compiled render graph.
#include "app/snapshot_command.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image_io.h"
#include "engine/vk/context.h"
#include "eval/config.h"
#include "eval/light_list.h"
#include "core/params.h"
#include "passes/snapshot.h"
#include "passes/snapshot_params.h"
#include "scene/framing.h"
#include "scene/light_file.h"
#include "scene/lights.h"
#include "scene/load_scene.h"
#include "scene/view_file.h"

namespace aamap::app {
namespace {

constexpr int kExitValidation = 3;

constexpr int kDefaultSide = 512;

// --camera, else --view, else the scene's views, else a view framing the scene (with a warning).
View pickView(const SnapshotOptions& o, const Scene& scene, int width, int height) {
    if (!o.camera.empty()) {
        const CameraConfig c = parseCameraOption(o.camera);
        const auto vec = [](const std::array<double, 3>& v) { return glm::vec3(v[0], v[1], v[2]); };
        try {
            return lookAtView(vec(c.position), vec(c.lookAt), vec(c.up), static_cast<float>(c.fov), width, height);
        } catch (const std::invalid_argument& e) {
            throw InputError("--camera", e.what());
        }
    }
    const std::vector<View> views = o.view.empty() ? scene.views : loadViewFile(o.view);
    const std::string source = o.view.empty() ? fmt::format("scene '{}'", o.scene) : o.view;
    if (views.empty() && o.viewIndex == 0) {
        spdlog::warn("{} has no camera: using a view that frames the scene's bounds (pass --camera or --view to choose one)",
                     source);
        return framingView(sceneBounds(scene), width, height);
    }
    if (views.empty()) throw InputError(o.scene, "the scene has no view; pass --camera or --view FILE.vf");
    if (o.viewIndex >= static_cast<int>(views.size()))
        throw InputError(o.view.empty() ? o.scene : o.view,
                         fmt::format("--view-index {} is out of range: {} has {} view(s)", o.viewIndex, source,
                                     views.size()));
    return views[static_cast<std::size_t>(o.viewIndex)];
}

// Why the scene needs (or does not need) its light-dependent passes, ahead of the compiled graph:
// passes the scene does not call for are never declared, so the graph alone cannot say so.
// areaSamples: the point samples each area light got (SnapshotResult::areaLightSamples).
std::string sceneDecisions(const Scene& scene, const SnapshotSettings& s, const std::vector<int>& areaSamples) {
    int spots = 0, lobes = 0;
    for (const PointLight& p : scene.pointLights) {
        if (glm::dot(p.normal, p.normal) > 0.0f) ++lobes;
        else if (glm::dot(p.spotDirection, p.spotDirection) > 0.0f) ++spots;
    }
    const int points = static_cast<int>(scene.pointLights.size()) - spots - lobes;
    const int areas = static_cast<int>(scene.areaLights.size());
    const int directional = static_cast<int>(scene.directionalLights.size());
    const bool map = scene.environment && !scene.environment->map.empty();
    const int fromMap = map ? s.environmentLights : 0;  // at most: a dark map may give fewer
    int areaTotal = 0;
    for (const int n : areaSamples) areaTotal += n;
    if (areaSamples.size() != scene.areaLights.size()) areaTotal = areas * s.areaLightSamples;
    const int samples = static_cast<int>(scene.pointLights.size()) + areaTotal + directional + fromMap;
    std::string atInfinity = directional > 0 ? fmt::format(", {} directional", directional) : std::string();
    if (map) atInfinity += fmt::format(", up to {} from the environment map", fromMap);
    std::string text = fmt::format("scene: {} triangles; lights: {} point, {} cosine-lobe point, {} spot, {} area "
                                   "({} point samples in all, by solid angle over the view, at most {} each){} -> {} "
                                   "light samples in the raster\n",
                                   scene.mesh.triangles.size(), points, lobes, spots, areas, areaTotal,
                                   s.areaLightSamples, atInfinity, samples);
    if (scene.environment)
        text += fmt::format("  environment: {}; the rest as an SH ambient term (unshadowed)\n",
                            map ? fmt::format("a {}x{} map, its {} brightest region(s) as directional lights",
                                              scene.environment->mapWidth, scene.environment->mapHeight, fromMap)
                                : std::string("constant"));
    if (samples == 0)
        text += "  shadow pass: not declared: the scene has no lights (unlit: emission only)\n";
    else if (!s.shadows.enabled)
        text += "  shadow pass: not declared: shadows are off (--no-shadows)\n";
    else if (scene.mesh.triangles.empty())
        text += "  shadow pass: not declared: no geometry to cast shadows\n";
    else
        text += fmt::format("  shadow pass: {} cube map(s) of at most {}^2 per face (each light's by need, listed "
                            "below), one per light sample{}{}\n",
                            samples,
                            s.shadows.resolution, spots > 0 ? " (spots too: a cube map, not a 2D map)" : "",
                            directional + fromMap > 0 ? " (a directional light's orthographic map takes one face)" : "");
    return text;
}

}  // namespace

CLI::App* addSnapshotCommand(CLI::App& app, SnapshotOptions& o) {
    CLI::App* cmd = app.add_subcommand("snapshot", "Run only the Snapshot: snapshot.png/.exr, laplacian.png, aamap.png/.exr; "
                                                   "--explain / --dot show the compiled render graph");
    cmd->add_option("SCENE", o.scene, "Scene: builtin:<name>, or an .obj/.gltf/.glb/.xml (Mitsuba) file")->required();
    CLI::Option* view =
        cmd->add_option("--view", o.view, "Radiance .vf view file (default: the scene's own views)")->type_name("VF");
    cmd->add_option("--camera", o.camera,
                    "Camera as YAML, the config's camera keys: '{position: [x, y, z], look_at: [x, y, z], up: [0, 1, 0], "
                    "fov: 45}' (fov: horizontal degrees)")
        ->type_name("YAML")->excludes(view);
    cmd->add_option("--view-index", o.viewIndex, "Which view of the file or scene")->check(CLI::NonNegativeNumber);
    cmd->add_option("--lights", o.lights, "Light file to add to the scene's lights (docs/lights.md)")->type_name("FILE");
    cmd->add_flag("--explain", o.explain, "Print the compiled graph: each pass kept and why, each culled and why");
    cmd->add_option("--dot", o.dot, "Write the compiled graph as Graphviz DOT (culled passes dashed)")->type_name("FILE");
    cmd->add_option("-o,--out", o.outDir, "Output folder")->type_name("OUTDIR")->capture_default_str();
    cmd->add_option("--width", o.width,
                    "Render width (bounding box; the view's aspect ratio fits inside; default: the scene file's, else 512)")
        ->check(CLI::Range(1, 16384));
    cmd->add_option("--height", o.height, "Render height (default: the scene file's, else 512)")->check(CLI::Range(1, 16384));
    cmd->add_option("--exposure", o.exposure, "Exposure of snapshot.png and of the aamap's greyscale")
        ->check(CLI::PositiveNumber)->capture_default_str();
    cmd->add_option("--shadow-resolution", o.shadowResolution, "Shadow cube-face size in texels")
        ->check(CLI::Range(1, 8192))->capture_default_str();
    cmd->add_flag("--no-shadows", o.noShadows, "No shadow maps");
    // One option per snapshot key, generated from its declaration: --blur-radius 2 is --set snapshot.blur_radius=2.
    for (const ParamSpec& p : snapshotParams()) {
        std::string flag = "--" + p.name;
        std::replace(flag.begin(), flag.end(), '_', '-');
        const std::string type = p.type == ParamType::Choice ? fmt::format("{{{}}}", fmt::join(p.choices, ","))
                                 : p.type == ParamType::Bool ? std::string("BOOL")
                                                             : fmt::format("{} in {}", p.type == ParamType::Int ? "INT" : "FLOAT",
                                                                           p.rangeText());
        cmd->add_option(flag, o.keys[p.name], fmt::format("{} (snapshot.{})", p.doc, p.name))
            ->type_name(type)
            ->default_str(toString(p.defaultParam()));
    }
    cmd->add_option("--set", o.set, "Set a snapshot key as the config's --set does: --set snapshot.blur_radius=2 "
                                    "(docs/config.md; every snapshot.* key)")
        ->type_name("snapshot.KEY=VALUE");
    cmd->add_option("--device", o.device, "Vulkan device: index or name substring (default: best GPU)")
        ->type_name("NAME");
    cmd->add_flag("--validation", o.validation, "Enable the Vulkan validation layer; any message fails (exit 3)");
    return cmd;
}

int runSnapshotCommand(const SnapshotOptions& o, bool validation, const std::string& device) {
    Scene scene = loadScene(o.scene);
    if (!o.lights.empty()) addLights(scene, loadLightFile(o.lights));
    // What `aamap run` would say about this scene before its Snapshot.
    if (auto unlit = unlitSceneWarning(scene)) spdlog::warn("{}", *unlit);
    for (const std::string& note : snapshotLimitations(scene)) spdlog::warn("{}", note);
    // The scene file's image size (a Mitsuba film) where --width/--height are not given.
    const bool sceneSize = o.width == 0 && o.height == 0 && scene.imageWidth > 0;
    const int boxWidth = o.width > 0 ? o.width : sceneSize ? scene.imageWidth : kDefaultSide;
    const int boxHeight = o.height > 0 ? o.height : sceneSize ? scene.imageHeight : kDefaultSide;
    const View view = pickView(o, scene, boxWidth, boxHeight);
    const auto [width, height] = fitResolution(view, boxWidth, boxHeight);

    // The generated --KEY options first, then --set: both read as the config's --set.
    std::vector<std::string> overrides;
    for (const auto& entry : o.keys)
        if (!entry.second.empty()) overrides.push_back("snapshot." + entry.first + "=" + entry.second);
    overrides.insert(overrides.end(), o.set.begin(), o.set.end());
    SnapshotSettings settings(snapshotFromOverrides(overrides));
    settings.filter.exposure = o.exposure;
    settings.shadows.enabled = !o.noShadows;
    settings.shadows.resolution = o.shadowResolution;
    settings.keepDebugImages = true;

    VulkanContext context(ContextOptions{validation, device});
    if (validation && !context.validationEnabled())
        throw EnvironmentError("validation was requested but VK_LAYER_KHRONOS_validation is not available");
    SnapshotResult r;
    {
        SnapshotRenderer renderer(context, scene);
        r = renderer.render(view, width, height, settings);
    }  // GPU objects freed here, so their destruction is validated too
    for (const std::string& w : r.warnings) spdlog::warn("{}", w);

    const std::filesystem::path out(o.outDir);
    std::filesystem::create_directories(out);
    writePng(out / "snapshot.png", toneMap(r.snapshot, o.exposure));
    writeExr(out / "snapshot.exr", r.snapshot);  // linear radiance, for measuring the map's input
    if (!r.laplacian.empty()) writePng(out / "laplacian.png", quantise(r.laplacian));  // the Laplacian maps only
    writeExr(out / "aamap.exr", r.aamap);
    writePng(out / "aamap.png", quantise(r.aamap));
    if (!o.dot.empty()) writeTextAtomically(o.dot, r.dot);
    if (o.explain) fmt::print("{}{}", sceneDecisions(scene, settings, r.areaLightSamples), r.explain);

    double gpu = 0.0;
    for (const PassTiming& t : r.passTimes) gpu += t.gpuMilliseconds;
    spdlog::info("snapshot {}x{} for {}x{} on '{}': {:.1f} ms GPU, {:.1f} ms total; wrote {}", r.snapshot.width(),
                 r.snapshot.height(), width, height, r.deviceName, gpu, r.totalSeconds * 1e3, out.string());
    if (context.validationEnabled() && context.validationMessageCount() > 0) {
        spdlog::error("{} Vulkan validation message(s), logged above", context.validationMessageCount());
        return kExitValidation;
    }
    return 0;
}

}  // namespace aamap::app
