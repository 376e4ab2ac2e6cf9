#include "eval/config.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "eval/config_schema.h"
#include "eval/config_sections.h"
#include "eval/config_sweeps.h"
#include "eval/file_digest.h"
#include "eval/light_list.h"
#include "eval/strategies.h"
#include "eval/yaml_reader.h"
#include "passes/snapshot_params.h"
#include "tracer/shading_params.h"

namespace aamap {
namespace {

using yaml::MapReader;

}  // namespace

// Every value --set can reach; '#' is a list index. The schema sections' keys come from the
// schema (eval/config_schema.h); the rest are read by hand and listed here.
std::vector<std::string> settableKeys() {
    std::vector<std::string> l = {
        "scene", "view", "seed", "camera.position", "camera.look_at", "camera.up", "camera.fov", "light_file",
        "renders.#.name", "renders.#.series", "renders.#.strategy", "renders.#.rpp",
        "reference.type", "reference.rpp", "reference.mode", "reference.path",
    };
    for (const std::string& k : sectionKeys()) l.push_back(k);
    for (const std::string& p : allStrategyParamNames()) l.push_back("renders.#." + p);
    for (const std::string& k : lightKeys()) l.push_back("lights.#." + k);
    return l;
}

namespace {

SourceLocation locationOf(const yaml::Context& ctx, MapReader& map, const std::string& key) {
    const YAML::Node n = map.node(key);
    return ctx.locate(n.IsDefined() ? n : map.self(), map.childPath(key));
}

ExperimentConfig readConfig(const yaml::Context& ctx, const YAML::Node& root) {
    if (root.IsNull() || !root.IsDefined())
        throw InputError(ctx.file(), 1, 1, "the config is empty; it needs at least 'scene' and 'renders'");
    MapReader top(ctx, root, "",
                  sectionKeyNames(topLevelParams(), {"scene", "view", "camera", "light_file", "lights", "image", "seed",
                                                     "snapshot", "shading", "renders", "reference", "metrics", "report",
                                                     "timing"}));
    ExperimentConfig c;
    c.file = ctx.file();
    top.require("scene");
    top.require("renders");
    top.getString("scene", c.scene);
    c.sceneLocation = locationOf(ctx, top, "scene");
    if (top.has("view") && !top.node("view").IsNull()) {
        std::string view;
        top.getString("view", view);
        c.view = view;
    }
    c.viewLocation = locationOf(ctx, top, "view");
    readSection(ctx, top, topLevelSchema(), c);
    c.viewIndexLocation = locationOf(ctx, top, "view_index");
    if (top.has("camera") && !top.node("camera").IsNull()) {
        c.camera = detail::readCamera(ctx, top.node("camera"));
        if (c.view)
            ctx.fail(top.node("camera"), "camera", "camera: set either 'camera' or 'view' (a .vf file), not both");
    }
    c.cameraLocation = locationOf(ctx, top, "camera");
    top.getUInt64("seed", c.seed);

    // One schema and parser for the light file and the inline list (eval/light_list.h).
    if (top.has("light_file") && !top.node("light_file").IsNull()) {
        std::string lightFile;
        top.getString("light_file", lightFile);
        c.lightFile = lightFile;
        try {
            c.lights = loadLightFile(*c.resolvedLightFile());
        } catch (const InputError& e) {
            if (e.line() > 0) throw;  // inside the light file: its own file:line:col
            const SourceLocation at = locationOf(ctx, top, "light_file");
            throw InputError(at.file, at.line, at.column, fmt::format("light_file '{}': {}", lightFile, e.what()));
        }
    }
    const bool fileHasEnvironment = std::any_of(c.lights.begin(), c.lights.end(),
                                                [](const LightSpec& l) { return l.type == LightType::Environment; });
    for (LightSpec& l : readLightList(ctx, top.node("lights"), "lights")) {
        if (fileHasEnvironment && l.type == LightType::Environment)
            ctx.fail(top.node("lights"), "lights",
                     fmt::format("lights: environment '{}' would be a second one (the light file has one); a scene has "
                                 "at most one", l.name));
        c.lights.push_back(std::move(l));
    }

    // Each section: its schema's keys read generically, then the struct filled from the values.
    // Which keys the config writes: where it is silent, a Mitsuba scene file's own settings decide.
    const auto noteWritten = [&c](const MapReader& m, const std::string& section, const std::vector<ParamSpec>& specs) {
        for (const ParamSpec& p : specs)
            if (m.has(p.name)) c.written.insert(section + "." + p.name);
    };
    MapReader image(ctx, top.node("image"), "image", sectionKeyNames(imageParams()));
    readSection(ctx, image, imageSchema(), c.image);
    noteWritten(image, "image", imageParams());
    if (image.has("filter_stddev") && c.image.filter.type != PixelFilterType::Gaussian)
        ctx.fail(image.node("filter_stddev"), "image.filter_stddev",
                 fmt::format("image.filter_stddev: only the gaussian filter has a stddev (image.filter is '{}')",
                             toString(c.image.filter.type)));

    MapReader snap(ctx, top.node("snapshot"), "snapshot", sectionKeyNames(snapshotParams()));
    readSection(ctx, snap, snapshotSchema(), c.snapshot);

    MapReader shading(ctx, top.node("shading"), "shading", sectionKeyNames(shadingParams(), {"cache"}));
    readSection(ctx, shading, shadingSchema(), c.shading);
    noteWritten(shading, "shading", shadingParams());
    MapReader cache(ctx, shading.node("cache"), "shading.cache", sectionKeyNames(shadingCacheParams()));
    readSection(ctx, cache, shadingCacheSchema(), c.shading.cache);

    c.renders = detail::readRenders(ctx, top.node("renders"));
    c.reference = detail::readReference(ctx, top.node("reference"), c.renders);
    c.metrics = detail::readMetrics(ctx, top.node("metrics"));
    c.report = detail::readReport(ctx, top.node("report"));
    MapReader timing(ctx, top.node("timing"), "timing", sectionKeyNames(timingParams()));
    readSection(ctx, timing, timingSchema(), c.timing);
    return c;
}

}  // namespace

int RenderConfig::strata() const { return static_cast<int>(std::lround(std::sqrt(rpp))); }

bool ExperimentConfig::usesAamap() const {
    return std::any_of(renders.begin(), renders.end(), [](const RenderConfig& r) {
        const StrategyDescriptor* s = findStrategy(r.strategy);
        return s != nullptr && s->usesAamap;
    });
}

std::optional<std::filesystem::path> ReferenceConfig::resolvedPath(const std::filesystem::path& configFile) const {
    if (type != ReferenceType::File) return std::nullopt;
    const std::filesystem::path p(path);
    return (p.is_absolute() || configFile.empty() ? p : configFile.parent_path() / p).lexically_normal();
}

std::string ExperimentConfig::resolvedScene() const {
    if (scene.starts_with("builtin:")) return scene;
    const std::filesystem::path p(scene);
    return (p.is_absolute() || file.empty() ? p : file.parent_path() / p).lexically_normal().string();
}

std::optional<std::filesystem::path> ExperimentConfig::resolvedLightFile() const {
    if (!lightFile) return std::nullopt;
    const std::filesystem::path p(*lightFile);
    return (p.is_absolute() || file.empty() ? p : file.parent_path() / p).lexically_normal();
}

std::optional<std::filesystem::path> ExperimentConfig::resolvedView() const {
    if (!view) return std::nullopt;
    const std::filesystem::path p(*view);
    return (p.is_absolute() || file.empty() ? p : file.parent_path() / p).lexically_normal();
}

namespace {

using Json = nlohmann::ordered_json;

// Numbers as doubles, choices by name: the render keys of existing configs stay as they were.
// For cache keys: integers as doubles, as the key format has always hashed them (so keys stay).
Json paramsJson(const RenderConfig& r) {
    Json p = Json::object();
    for (const auto& [k, v] : r.params.entries()) {
        if (const std::string* name = std::get_if<std::string>(&v)) p[k] = *name;
        else p[k] = std::holds_alternative<int>(v) ? static_cast<double>(std::get<int>(v)) : std::get<double>(v);
    }
    return p;
}

// A file as the cache keys name it: absolute and without . or .. (symbolic links resolved), so
// that a config reached by another path, or from another working directory, keeps its keys.
std::string keyPath(const std::filesystem::path& p) {
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(p, ec);
    return (ec ? std::filesystem::absolute(p).lexically_normal() : canonical).string();
}

// forKey: for a cache key, with keyPath's environment-map paths.
Json lightsJson(const ExperimentConfig& c, bool forKey = false) {
    Json lights = Json::array();
    for (const LightConfig& l : c.lights) {
        Json j = lightJson(l);
        if (forKey && !l.map.empty()) j["map"] = keyPath(l.map);
        lights.push_back(std::move(j));
    }
    return lights;
}

// The snapshot section: every key (canonical form), or for a cache key the keys not at their default.
Json snapshotJson(const ExperimentConfig& c, bool forKey) { return sectionJson(snapshotSchema(), c.snapshot, forKey); }

// The subpixel map holds its predicted error against the metrics' FLIP threshold, so that
// threshold is part of its Snapshot (beside the snapshot section: it is a metrics key).
void addSubpixelThreshold(const ExperimentConfig& c, Json& key) {
    if (c.snapshot.map == passes::AamapSource::Subpixel) key["subpixel_flip_threshold"] = c.metrics.flipThreshold;
}

// A Mitsuba scene file says how it is rendered (film size, integrator depths): what the config
// leaves out, the file decides.

// What every image of the experiment depends on, with paths resolved. forKey: for one render's
// cache key, which leaves out what its shading mode never reads (the cache outside cache mode).
Json shadingJson(const ExperimentConfig& c, std::optional<ShadingMode> modeOverride = std::nullopt,
                 bool forKey = false) {
    ShadingSettings s = c.shading;
    if (modeOverride) s.mode = *modeOverride;  // the reference's own mode
    Json j = sectionJson(shadingSchema(), s, forKey);
    if (forKey) {
        // A Mitsuba file's own integrator decides what the config leaves out; the key then follows
        // the file's contents (scene_content) instead of the value.
        if (sceneDecidesRendering(c)) {
            if (!c.given("shading.max_depth")) j["max_depth"] = "scene";
            if (!c.given("shading.roulette_depth")) j["roulette_depth"] = "scene";
            if (c.given("shading.hide_emitters")) j["hide_emitters"] = s.hideEmitters;
        }
        // The cache's settings only in cache mode: a path-traced reference keeps its key when the cache is tuned.
        if (s.mode == ShadingMode::Cache) {
            Json cache = sectionJson(shadingCacheSchema(), s.cache, true);
            if (!cache.empty()) j["cache"] = cache;
        }
    } else {
        j["cache"] = sectionJson(shadingCacheSchema(), s.cache, false);
    }
    return j;
}

// The pixel filter as the render keys have always named it.
Json filterJson(const ImageConfig& image) {
    const PixelFilterSettings& f = image.filter;
    Json j = {{"type", toString(f.type)}, {"radius", shortestDouble(f.radius)}};
    if (f.type == PixelFilterType::Gaussian) j["stddev"] = shortestDouble(f.stddev);
    j["mode"] = toString(f.mode);
    return j;
}

Json cameraJson(const CameraConfig& cam) {
    return {{"position", cam.position}, {"look_at", cam.lookAt}, {"up", cam.up}, {"fov", cam.fov}};
}

Json sceneJson(const ExperimentConfig& c) {
    const auto view = c.resolvedView();
    const std::string scene = c.scene.starts_with("builtin:") ? c.scene : keyPath(c.resolvedScene());
    Json j = {{"scene", scene}, {"view", view ? Json(keyPath(*view)) : Json(nullptr)},
              {"view_index", c.viewIndex}, {"lights", lightsJson(c, true)},
              {"image", {{"width", c.image.width}, {"height", c.image.height}, {"exposure", c.image.exposure}}}};
    // Only when they apply, so that other configs keep their keys.
    if (c.camera) j["camera"] = cameraJson(*c.camera);
    // The files' contents, not only their names: an edited scene or view file re-traces. (Files
    // a scene refers to, such as an OBJ's .mtl and textures, are not followed.)
    if (!c.scene.starts_with("builtin:")) j["scene_content"] = fileDigest(c.resolvedScene());
    if (view) j["view_content"] = fileDigest(*view);
    // Environment maps likewise: an edited sky re-traces.
    Json maps = Json::array();
    for (const LightConfig& l : c.lights)
        if (!l.map.empty()) maps.push_back(fileDigest(l.map));
    if (!maps.empty()) j["light_map_content"] = maps;
    if (!c.sizeGiven() && sceneDecidesRendering(c))
        j["image"]["size"] = "scene";  // the Mitsuba film's size, which the file decides
    return j;
}

}  // namespace

std::string fnv1a64Hex(const std::string& text) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char ch : text) {
        h ^= ch;
        h *= 0x100000001b3ull;
    }
    return fmt::format("{:016x}", h);
}

bool sceneDecidesRendering(const ExperimentConfig& c) {
    return !c.scene.starts_with("builtin:") && c.scene.ends_with(".xml");
}

Json renderKeyObject(const ExperimentConfig& c, const RenderConfig& r) {
    Json j;
    j["format"] = "aamap-render-18";  // bump when the image for the same settings and files changes (tracer or loader)
    j["scene"] = sceneJson(c);
    j["seed"] = c.seed;
    j["shading"] = shadingJson(c, r.shadingMode, true);
    j["strategy"] = r.strategy;
    j["rpp"] = r.rpp;
    j["params"] = paramsJson(r);
    if (!c.image.defaultFilter()) j["filter"] = filterJson(c.image);  // only then: other configs keep their keys
    if (!c.given("image.filter") && sceneDecidesRendering(c)) j["filter"] = "scene";  // the film's, as the file says
    const StrategyDescriptor* s = findStrategy(r.strategy);
    if (s != nullptr && s->usesAamap) {
        j["snapshot"] = snapshotJson(c, true);
        addSubpixelThreshold(c, j);
    }
    return j;
}

Json strategyParamsJson(const RenderConfig& r) {
    Json p = Json::object();
    for (const auto& entry : r.params.entries())  // not a structured binding: clang's lambdas cannot capture one
        std::visit([&p, &entry](const auto& value) { p[entry.first] = value; }, entry.second);
    return p;
}

std::string renderKeyJson(const ExperimentConfig& c, const RenderConfig& r) { return renderKeyObject(c, r).dump(); }

Json snapshotSettingsJson(const ExperimentConfig& c) { return snapshotJson(c, false); }

std::string renderKey(const ExperimentConfig& c, const RenderConfig& r) { return fnv1a64Hex(renderKeyJson(c, r)); }

std::string snapshotKey(const ExperimentConfig& c) {
    Json j;
    j["format"] = "aamap-snapshot-14";  // bump as the render key
    j["scene"] = sceneJson(c);
    j["snapshot"] = snapshotJson(c, true);
    addSubpixelThreshold(c, j);
    return fnv1a64Hex(j.dump());
}

namespace {

Json rendersJson(const ExperimentConfig& c) {
    Json renders = Json::array();
    for (const RenderConfig& r : c.renders)
        renders.push_back({{"name", r.name}, {"series", r.series}, {"strategy", r.strategy}, {"rpp", r.rpp},
                           {"params", paramsJson(r)}});
    return renders;
}

Json referenceJson(const ReferenceConfig& r) {
    return {{"type", toString(r.type)}, {"rpp", r.rpp}, {"mode", r.mode ? toString(*r.mode) : ""}, {"path", r.path}};
}

}  // namespace

static nlohmann::ordered_json canonical(const ExperimentConfig& c) {
    Json j;
    j["scene"] = c.scene;
    j["view"] = c.view ? Json(*c.view) : Json(nullptr);
    j["view_index"] = c.viewIndex;
    if (c.camera) j["camera"] = cameraJson(*c.camera);  // only when set: older configs keep their hash
    if (c.lightFile) j["light_file"] = *c.lightFile;  // only when set: older configs keep their hash
    j["lights"] = lightsJson(c);
    j["image"] = {{"width", c.image.width}, {"height", c.image.height}, {"exposure", c.image.exposure}};
    if (!c.image.defaultFilter()) {  // else older configs keep their hash
        const Json filter = sectionJson(pixelFilterSchema(), c.image.filter, false);
        for (const auto& [key, value] : filter.items())
            if (key != "filter_stddev" || c.image.filter.type == PixelFilterType::Gaussian) j["image"][key] = value;
    }
    j["seed"] = c.seed;
    j["threads"] = c.threads;
    j["snapshot"] = snapshotJson(c, false);
    j["shading"] = shadingJson(c);
    j["renders"] = rendersJson(c);
    j["reference"] = referenceJson(c.reference);
    j["metrics"] = sectionJson(metricsSchema(), c.metrics, false);
    j["report"] = sectionJson(reportSchema(), c.report, false);
    j["timing"] = sectionJson(timingSchema(), c.timing, false);
    return j;
}

std::string ExperimentConfig::canonicalJson() const { return canonical(*this).dump(); }

std::string ExperimentConfig::hashJson() const {
    Json j;
    j["scene"] = scene;
    j["view"] = view ? Json(*view) : Json(nullptr);
    if (camera) j["camera"] = cameraJson(*camera);
    if (lightFile) j["light_file"] = *lightFile;
    j["lights"] = lightsJson(*this);
    j["seed"] = seed;
    // The schema sections by the keys not at their default, as the cache keys hold them: a key
    // added later leaves every hash as it was. Threads never change an image.
    for (const ConfigSection& s : configSections()) {
        const Json changed = toJson(s.changed(*this));
        if (!s.path.empty()) {
            if (!changed.empty()) j[s.path] = changed;
            continue;
        }
        for (const auto& [key, value] : changed.items())
            if (key != "threads") j[key] = value;
    }
    j["renders"] = rendersJson(*this);
    j["reference"] = referenceJson(reference);
    return j.dump();
}

std::string ExperimentConfig::hash() const { return fnv1a64Hex(hashJson()); }

SnapshotSettings snapshotFromOverrides(const std::vector<std::string>& overrides) {
    yaml::Context ctx("--set");
    YAML::Node root(YAML::NodeType::Map);
    std::vector<std::string> keys;
    for (const ParamSpec& p : snapshotParams()) keys.push_back("snapshot." + p.name);
    for (const std::string& o : overrides) yaml::applyOverride(root, o, keys, ctx);
    MapReader snap(ctx, root["snapshot"], "snapshot", sectionKeyNames(snapshotParams()));
    SnapshotSettings c;
    readSection(ctx, snap, snapshotSchema(), c);
    return c;
}

CameraConfig parseCameraOption(const std::string& text) {
    yaml::Context ctx("--camera");
    YAML::Node node;
    try {
        node = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
        throw InputError("--camera", 0, e.mark.column + 1, fmt::format("invalid YAML: {}", e.msg));
    }
    return detail::readCamera(ctx, node);
}

std::vector<std::string> cameraOverrides(const CameraConfig& cam) {
    const auto vec = [](const std::array<double, 3>& v) { return fmt::format("[{}, {}, {}]", v[0], v[1], v[2]); };
    return {"camera.position=" + vec(cam.position), "camera.look_at=" + vec(cam.lookAt), "camera.up=" + vec(cam.up),
            fmt::format("camera.fov={}", cam.fov)};
}

namespace {

// "builtin:cornell" -> "cornell", "../scenes/hall.obj" -> "hall", "0.02" -> "0.02": a swept value
// as a piece of a folder name.
std::string folderPiece(const std::string& key, const std::string& value) {
    std::string v = value;
    if (key == "scene" || key == "view" || key == "light_file" || key == "reference.path") {
        v = v.starts_with("builtin:") ? v.substr(8) : std::filesystem::path(v).stem().string();
    }
    for (char& c : v)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
    return v;
}

std::string readText(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file, fmt::format("cannot read config file: {}", std::strerror(errno)));
    if (std::filesystem::is_directory(file)) throw InputError(file, "cannot read config file: it is a directory");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace

Experiment parseExperiment(const std::string& text, const std::filesystem::path& file,
                           const std::vector<std::string>& overrides) {
    yaml::Context ctx(file);
    YAML::Node root;
    try {
        root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
        throw InputError(file, e.mark.line + 1, e.mark.column + 1, fmt::format("invalid YAML: {}", e.msg));
    }
    if (!root.IsNull() && !root.IsMap())
        ctx.fail(root, "", fmt::format("expected a mapping of settings, found {}", yaml::describe(root)));
    const std::vector<std::string> settable = settableKeys();
    for (const std::string& o : overrides) yaml::applyOverride(root, o, settable, ctx);

    const std::vector<detail::ConfigSweep> sweeps = detail::findConfigSweeps(ctx, root);
    const std::vector<std::vector<std::size_t>> groups = detail::takeZipGroups(ctx, root, sweeps);
    Experiment e;
    for (const detail::ConfigSweep& s : sweeps) {
        e.sweptKeys.push_back(s.key);
        e.sweptAt.push_back(ctx.locate(s.values.front(), s.key));
    }
    // A key's last part names it in folder names, unless two swept keys share it.
    std::vector<std::string> shortKeys;
    for (const std::string& k : e.sweptKeys) {
        const std::string last = k.substr(k.rfind('.') + 1);
        const bool shared = std::count_if(e.sweptKeys.begin(), e.sweptKeys.end(), [&](const std::string& o) {
                                return o.substr(o.rfind('.') + 1) == last;
                            }) > 1;
        std::string name = shared ? k : last;
        std::replace(name.begin(), name.end(), '.', '_');
        shortKeys.push_back(name);
    }
    detail::forEachConfigVariant(ctx, root, sweeps, groups, kMaxConfigVariants, [&](const YAML::Node& doc,
                                                                             const std::vector<std::size_t>& choice) {
        e.variants.push_back(readConfig(ctx, doc));
        std::vector<std::string> values, pieces;
        for (std::size_t i = 0; i < sweeps.size(); ++i) {
            const YAML::Node& node = sweeps[i].values[choice[i]];
            const std::string value = node.IsScalar() ? node.Scalar() : YAML::Dump(node);
            values.push_back(value);
            pieces.push_back(shortKeys[i] + "-" + folderPiece(sweeps[i].key, value));
        }
        e.sweptValues.push_back(std::move(values));
        std::string folder = pieces.empty() ? std::string() : fmt::format("{}", fmt::join(pieces, "_"));
        if (std::find(e.folders.begin(), e.folders.end(), folder) != e.folders.end())
            folder += fmt::format("_{}", e.folders.size());
        e.folders.push_back(std::move(folder));
    });
    return e;
}

Experiment loadExperiment(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
    return parseExperiment(readText(file), file, overrides);
}

ExperimentConfig parseConfig(const std::string& text, const std::filesystem::path& file,
                             const std::vector<std::string>& overrides) {
    Experiment e = parseExperiment(text, file, overrides);
    if (!e.sweptKeys.empty()) {
        const SourceLocation& at = e.sweptAt.front();
        throw InputError(at.file, at.line, at.column,
                         fmt::format("{}: a list here sweeps the setting, and only `aamap run` expands such sweeps; "
                                     "give this command one value",
                                     e.sweptKeys.front()));
    }
    return std::move(e.variants.front());
}

ExperimentConfig loadConfig(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
    return parseConfig(readText(file), file, overrides);
}

}  // namespace aamap
