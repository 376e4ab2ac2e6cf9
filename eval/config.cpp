#include "eval/config.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "eval/yaml_reader.h"

namespace aamap {
namespace {

using yaml::MapReader;

// Every value --set can reach; '#' is a list index. Keep in step with the readers below.
const std::vector<std::string> kLeaves = {
    "scene", "view", "view_index", "seed", "threads",
    "image.width", "image.height", "image.exposure",
    "snapshot.scale", "snapshot.area_light_samples", "snapshot.blur_radius", "snapshot.noise_floor",
    "snapshot.gain", "shading.area_light_samples",
    "lights.#.type", "lights.#.name", "lights.#.position", "lights.#.intensity", "lights.#.normal",
    "renders.#.name", "renders.#.strategy", "renders.#.rpp",
};
const std::vector<std::string> kStrategies = {"uniform", "aamap"};
// Render names become file stems beside these outputs; a render may not shadow them.
const std::vector<std::string> kReservedNames = {"snapshot", "laplacian", "aamap", "results"};
constexpr int kMaxRpp = 1024;   // 32 x 32; the rays-per-pixel image is 16-bit
constexpr int kMaxSide = 16384;

SourceLocation locationOf(const yaml::Context& ctx, MapReader& map, const std::string& key) {
    const YAML::Node n = map.node(key);
    return ctx.locate(n.IsDefined() ? n : map.self(), map.childPath(key));
}

LightConfig readLight(const yaml::Context& ctx, const YAML::Node& node, const std::string& path, std::size_t index) {
    MapReader m(ctx, node, path, {"type", "name", "position", "intensity", "normal"});
    LightConfig light;
    m.getString("type", light.type);
    if (light.type != "point")
        ctx.fail(m.node("type"), m.childPath("type"),
                 fmt::format("{}: unknown light type '{}' (supported: point)", m.childPath("type"), light.type));
    light.name = fmt::format("light{}", index);
    m.getString("name", light.name);
    m.require("position");
    m.require("intensity");
    const double big = 1e30;
    m.getVec3("position", light.position, -big, big);
    m.getVec3("intensity", light.intensity, 0.0, big);
    m.getVec3("normal", light.normal, -big, big);
    m.finish();
    return light;
}

bool isFileNameSafe(const std::string& s) {
    return !s.empty() && s.size() <= 64 &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; });
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

RenderConfig readRender(const yaml::Context& ctx, const YAML::Node& node, const std::string& path) {
    MapReader m(ctx, node, path, {"name", "strategy", "rpp"});
    RenderConfig r;
    m.require("strategy");
    m.require("rpp");
    m.getString("strategy", r.strategy);
    if (std::find(kStrategies.begin(), kStrategies.end(), r.strategy) == kStrategies.end())
        ctx.fail(m.node("strategy"), m.childPath("strategy"),
                 fmt::format("{}: unknown strategy '{}' (supported: {})", m.childPath("strategy"), r.strategy,
                             fmt::join(kStrategies, ", ")));
    m.getInt("rpp", r.rpp, 1, kMaxRpp);
    const int n = static_cast<int>(std::lround(std::sqrt(r.rpp)));
    if (n * n != r.rpp)
        ctx.fail(m.node("rpp"), m.childPath("rpp"),
                 fmt::format("{}: {} is not a perfect square; rays per pixel are n x n strata (1, 4, 9, 16, 25, "
                             "36, ...)", m.childPath("rpp"), r.rpp));
    r.name = fmt::format("{}{}", r.strategy, r.rpp);
    m.getString("name", r.name);
    if (!isFileNameSafe(r.name))
        ctx.fail(m.node("name"), m.childPath("name"),
                 fmt::format("{}: '{}' is not a safe file name (use 1-64 letters, digits, '_' or '-')",
                             m.childPath("name"), r.name));
    if (std::find(kReservedNames.begin(), kReservedNames.end(), lower(r.name)) != kReservedNames.end())
        ctx.fail(m.node("name"), m.childPath("name"),
                 fmt::format("{}: '{}' is reserved for another output file ({})", m.childPath("name"), r.name,
                             fmt::join(kReservedNames, ", ")));
    m.finish();
    return r;
}

ExperimentConfig readConfig(const yaml::Context& ctx, const YAML::Node& root) {
    if (root.IsNull() || !root.IsDefined())
        throw InputError(ctx.file(), 1, 1, "the config is empty; it needs at least 'scene' and 'renders'");
    MapReader top(ctx, root, "",
                  {"scene", "view", "view_index", "lights", "image", "seed", "threads", "snapshot", "shading",
                   "renders"});
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
    top.getInt("view_index", c.viewIndex, 0, 1000000);
    c.viewIndexLocation = locationOf(ctx, top, "view_index");
    top.getUInt64("seed", c.seed);
    top.getInt("threads", c.threads, 0, 4096);

    if (const YAML::Node lights = top.node("lights"); lights.IsDefined() && !lights.IsNull()) {
        if (!lights.IsSequence()) ctx.fail(lights, "lights", fmt::format("lights: expected a list, found {}", yaml::describe(lights)));
        for (std::size_t i = 0; i < lights.size(); ++i)
            c.lights.push_back(readLight(ctx, lights[i], fmt::format("lights.{}", i), i));
    }

    MapReader image(ctx, top.node("image"), "image", {"width", "height", "exposure"});
    image.getInt("width", c.image.width, 1, kMaxSide);
    image.getInt("height", c.image.height, 1, kMaxSide);
    image.getDouble("exposure", c.image.exposure, 0.0, 1e6, true);
    image.finish();

    MapReader snap(ctx, top.node("snapshot"), "snapshot",
                   {"scale", "area_light_samples", "blur_radius", "noise_floor", "gain"});
    snap.getDouble("scale", c.snapshot.scale, 1.0, 4.0);
    snap.getInt("area_light_samples", c.snapshot.areaLightSamples, 1, 64);
    snap.getInt("blur_radius", c.snapshot.blurRadius, 0, 16);
    snap.getDouble("noise_floor", c.snapshot.noiseFloor, 0.0, 1.0);
    snap.getDouble("gain", c.snapshot.gain, 0.0, 1e6, true);
    snap.finish();

    MapReader shading(ctx, top.node("shading"), "shading", {"area_light_samples"});
    shading.getInt("area_light_samples", c.shading.areaLightSamples, 1, 4096);
    shading.finish();

    const YAML::Node renders = top.node("renders");
    if (!renders.IsSequence() || renders.size() == 0)
        ctx.fail(renders, "renders", fmt::format("renders: expected a non-empty list, found {}", yaml::describe(renders)));
    std::set<std::string> names;
    for (std::size_t i = 0; i < renders.size(); ++i) {
        const std::string path = fmt::format("renders.{}", i);
        c.renders.push_back(readRender(ctx, renders[i], path));
        if (!names.insert(lower(c.renders.back().name)).second)
            ctx.fail(renders[i], path, fmt::format("{}: render name '{}' is used twice (names are output file names)",
                                                   path, c.renders.back().name));
    }
    top.finish();
    return c;
}

}  // namespace

int RenderConfig::strata() const { return static_cast<int>(std::lround(std::sqrt(rpp))); }

std::string ExperimentConfig::resolvedScene() const {
    if (scene.starts_with("builtin:")) return scene;
    const std::filesystem::path p(scene);
    return (p.is_absolute() || file.empty() ? p : file.parent_path() / p).lexically_normal().string();
}

std::optional<std::filesystem::path> ExperimentConfig::resolvedView() const {
    if (!view) return std::nullopt;
    const std::filesystem::path p(*view);
    return (p.is_absolute() || file.empty() ? p : file.parent_path() / p).lexically_normal();
}

static nlohmann::ordered_json canonical(const ExperimentConfig& c) {
    using Json = nlohmann::ordered_json;
    Json j;
    j["scene"] = c.scene;
    j["view"] = c.view ? Json(*c.view) : Json(nullptr);
    j["view_index"] = c.viewIndex;
    j["lights"] = Json::array();
    for (const LightConfig& l : c.lights)
        j["lights"].push_back({{"type", l.type}, {"name", l.name}, {"position", l.position},
                               {"intensity", l.intensity}, {"normal", l.normal}});
    j["image"] = {{"width", c.image.width}, {"height", c.image.height}, {"exposure", c.image.exposure}};
    j["seed"] = c.seed;
    j["threads"] = c.threads;
    j["snapshot"] = {{"scale", c.snapshot.scale}, {"area_light_samples", c.snapshot.areaLightSamples},
                     {"blur_radius", c.snapshot.blurRadius}, {"noise_floor", c.snapshot.noiseFloor},
                     {"gain", c.snapshot.gain}};
    j["shading"] = {{"area_light_samples", c.shading.areaLightSamples}};
    j["renders"] = Json::array();
    for (const RenderConfig& r : c.renders)
        j["renders"].push_back({{"name", r.name}, {"strategy", r.strategy}, {"rpp", r.rpp}});
    return j;
}

std::string ExperimentConfig::canonicalJson() const { return canonical(*this).dump(); }

std::string ExperimentConfig::hash() const {
    nlohmann::ordered_json j = canonical(*this);
    j.erase("threads");
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a 64
    for (unsigned char ch : j.dump()) {
        h ^= ch;
        h *= 0x100000001b3ull;
    }
    return fmt::format("{:016x}", h);
}

ExperimentConfig parseConfig(const std::string& text, const std::filesystem::path& file,
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
    for (const std::string& o : overrides) yaml::applyOverride(root, o, kLeaves, ctx);
    return readConfig(ctx, root);
}

ExperimentConfig loadConfig(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file, fmt::format("cannot read config file: {}", std::strerror(errno)));
    if (std::filesystem::is_directory(file)) throw InputError(file, "cannot read config file: it is a directory");
    std::ostringstream text;
    text << in.rdbuf();
    return parseConfig(text.str(), file, overrides);
}

}  // namespace aamap
