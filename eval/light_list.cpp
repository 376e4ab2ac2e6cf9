#include "eval/light_list.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.h"

namespace aamap {
namespace {

using yaml::MapReader;
constexpr double kBig = 1e30;

struct TypeInfo {
    LightType type;
    const char* name;
    const char* nativeUnit;  // the emission key besides "power" (the lights at infinity: the only one)
    std::vector<std::string> keys;
};

bool atInfinity(LightType t) { return t == LightType::Directional || t == LightType::Environment; }

const std::vector<TypeInfo>& types() {
    static const std::vector<TypeInfo> t = {
        {LightType::Point, "point", "intensity", {"type", "name", "position", "intensity", "power", "normal"}},
        {LightType::Spot, "spot", "intensity",
         {"type", "name", "position", "intensity", "power", "direction", "inner_angle", "outer_angle"}},
        {LightType::Quad, "quad", "radiance", {"type", "name", "position", "radiance", "power", "normal", "up", "size"}},
        {LightType::Disk, "disk", "radiance",
         {"type", "name", "position", "radiance", "power", "normal", "radius", "segments"}},
        {LightType::Directional, "directional", "irradiance", {"type", "name", "direction", "irradiance"}},
        {LightType::Environment, "environment", "radiance", {"type", "name", "radiance", "map", "scale", "rotation", "up"}},
    };
    return t;
}

void requireNonZero(const yaml::Context& ctx, MapReader& m, const std::string& key, const std::array<double, 3>& v) {
    if (v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
        ctx.fail(m.node(key), m.childPath(key), fmt::format("{}: must not be the zero vector", m.childPath(key)));
}

void getPositive2(const yaml::Context& ctx, MapReader& m, const std::string& key, std::array<double, 2>& out) {
    const YAML::Node n = m.node(key);
    if (!n.IsDefined()) return;
    if (!n.IsSequence() || n.size() != 2)
        ctx.fail(n, m.childPath(key),
                 fmt::format("{}: expected a list of 2 numbers, found {}", m.childPath(key), yaml::describe(n)));
    for (std::size_t i = 0; i < 2; ++i) {
        double v = 0;
        if (!yaml::decodePlain(n[i], v) || !std::isfinite(v) || !(v > 0.0) || v > kBig)
            ctx.fail(n[i], m.childPath(key),
                     fmt::format("{}[{}]: expected a positive number, found {}", m.childPath(key), i, yaml::describe(n[i])));
        out[i] = v;
    }
}

// directional: a direction and an irradiance. environment: a constant radiance, or a map with its
// scale and orientation (both only with a map).
void readAtInfinity(const yaml::Context& ctx, MapReader& m, LightSpec& light) {
    if (light.type == LightType::Directional) {
        m.require("direction");
        m.require("irradiance");
        m.getVec3("direction", light.direction, -kBig, kBig);
        requireNonZero(ctx, m, "direction", light.direction);
        light.unit = EmissionUnit::Irradiance;
        m.getVec3("irradiance", light.emission, 0.0, kBig);
        return;
    }
    const bool hasRadiance = m.has("radiance"), hasMap = m.has("map");
    if (hasRadiance == hasMap)
        ctx.fail(hasMap ? m.node("map") : m.self(), hasMap ? m.childPath("map") : m.path(),
                 fmt::format("{}: give exactly one of 'radiance' (a constant sky) and 'map' (a lat-long EXR or HDR "
                             "image) for an environment", m.path()));
    light.unit = EmissionUnit::Radiance;
    if (hasRadiance) {
        for (const char* key : {"scale", "rotation", "up"})
            if (m.has(key))
                ctx.fail(m.node(key), m.childPath(key),
                         fmt::format("{}: only an environment with a 'map' has a {}", m.childPath(key), key));
        m.getVec3("radiance", light.emission, 0.0, kBig);
        return;
    }
    const YAML::Node mapNode = m.node("map");
    std::string map;
    m.getString("map", map);
    std::filesystem::path file(map);
    if (file.is_relative()) file = ctx.file().parent_path() / file;
    std::string ext = file.extension().string();
    for (char& c : ext) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    if (ext != ".exr" && ext != ".hdr")
        ctx.fail(mapNode, m.childPath("map"),
                 fmt::format("{}: '{}' is not an EXR or Radiance HDR image (8-bit images hold no radiance)",
                             m.childPath("map"), map));
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error))
        ctx.fail(mapNode, m.childPath("map"), fmt::format("{}: environment map '{}' not found", m.childPath("map"),
                                                          file.string()));
    light.map = file.string();
    m.getDouble("scale", light.scale, 0.0, kBig);
    m.getDouble("rotation", light.rotation, -360.0, 360.0);
    m.getVec3("up", light.up, -kBig, kBig);
    if (m.has("up")) requireNonZero(ctx, m, "up", light.up);
}

LightSpec readLight(const yaml::Context& ctx, const YAML::Node& node, const std::string& path, std::size_t index) {
    if (!node.IsMap())
        ctx.fail(node, path, fmt::format("{}: expected a mapping (a light), found {}", path, yaml::describe(node)));
    // The type decides which keys are allowed, so read it first.
    std::string typeName = "point";
    const YAML::Node& constNode = node;
    if (const YAML::Node t = constNode["type"]; t.IsDefined()) {
        if (!t.IsScalar()) ctx.fail(t, path + ".type", fmt::format("{}.type: expected a string, found {}", path, yaml::describe(t)));
        typeName = t.Scalar();
    }
    const TypeInfo* info = nullptr;
    for (const TypeInfo& t : types())
        if (typeName == t.name) info = &t;
    if (info == nullptr) {
        std::vector<std::string> names;
        for (const TypeInfo& t : types()) names.push_back(t.name);
        const std::string hint = yaml::closest(typeName, names);
        ctx.fail(constNode["type"], path + ".type",
                 fmt::format("{}.type: unknown light type '{}'{} (supported: point, spot, quad, disk, directional, "
                             "environment)", path, typeName, hint.empty() ? "" : fmt::format("; did you mean '{}'?", hint)));
    }

    // A point or spot light given radiance (or an area light given intensity) is a likely slip; say
    // what this type takes instead.
    const char* otherUnit = std::string(info->nativeUnit) == "intensity" ? "radiance" : "intensity";
    if (const YAML::Node k = constNode[otherUnit]; k.IsDefined() && !atInfinity(info->type))
        ctx.fail(k, path + "." + otherUnit,
                 fmt::format("{}: a {} light is given by exactly one of '{}' and 'power', not '{}'", path, typeName,
                             info->nativeUnit, otherUnit));
    MapReader m(ctx, node, path, info->keys);
    LightSpec light;
    light.type = info->type;
    light.name = fmt::format("light{}", index);
    m.getString("name", light.name);
    if (atInfinity(info->type)) {
        readAtInfinity(ctx, m, light);
        return light;
    }
    m.require("position");
    m.getVec3("position", light.position, -kBig, kBig);

    // Emission: the type's own quantity or the total power, exactly one of them.
    const bool hasNative = m.has(info->nativeUnit), hasPower = m.has("power");
    if (hasNative == hasPower)
        ctx.fail(hasPower ? m.node("power") : node, hasPower ? m.childPath("power") : path,
                 fmt::format("{}: give exactly one of '{}' and 'power' for a {} light", path, info->nativeUnit, typeName));
    light.unit = hasPower ? EmissionUnit::Power
                 : info->type == LightType::Point || info->type == LightType::Spot ? EmissionUnit::Intensity
                                                                                   : EmissionUnit::Radiance;
    m.getVec3(toString(light.unit), light.emission, 0.0, kBig);

    switch (info->type) {
        case LightType::Point:
            m.getVec3("normal", light.normal, -kBig, kBig);
            break;
        case LightType::Spot: {
            m.require("direction");
            m.getVec3("direction", light.direction, -kBig, kBig);
            requireNonZero(ctx, m, "direction", light.direction);
            m.getDouble("outer_angle", light.outerAngle, 0.0, 180.0, true);
            m.getDouble("inner_angle", light.innerAngle, 0.0, 180.0);
            if (light.innerAngle > light.outerAngle)
                ctx.fail(m.has("inner_angle") ? m.node("inner_angle") : node, m.childPath("inner_angle"),
                         fmt::format("{}: {} degrees is wider than outer_angle ({} degrees)", m.childPath("inner_angle"),
                                     light.innerAngle, light.outerAngle));
            break;
        }
        case LightType::Quad:
            m.require("normal");
            m.require("size");
            m.getVec3("normal", light.normal, -kBig, kBig);
            requireNonZero(ctx, m, "normal", light.normal);
            m.getVec3("up", light.up, -kBig, kBig);
            getPositive2(ctx, m, "size", light.size);
            break;
        case LightType::Disk:
            m.require("normal");
            m.require("radius");
            m.getVec3("normal", light.normal, -kBig, kBig);
            requireNonZero(ctx, m, "normal", light.normal);
            m.getDouble("radius", light.radius, 0.0, kBig, true);
            m.getInt("segments", light.segments, 3, 4096);
            break;
        case LightType::Directional:
        case LightType::Environment:
            break;  // read above
    }
    return light;
}

}  // namespace

std::vector<LightSpec> readLightList(const yaml::Context& ctx, const YAML::Node& node, const std::string& path) {
    std::vector<LightSpec> lights;
    if (!node.IsDefined() || node.IsNull()) return lights;
    if (!node.IsSequence())
        ctx.fail(node, path, fmt::format("{}: expected a list of lights, found {}", path, yaml::describe(node)));
    std::size_t environment = node.size();  // index of the first environment entry
    for (std::size_t i = 0; i < node.size(); ++i) {
        const std::string entry = fmt::format("{}.{}", path, i);
        lights.push_back(readLight(ctx, node[i], entry, i));
        if (lights.back().type != LightType::Environment) continue;
        if (environment < node.size())
            ctx.fail(node[i], entry, fmt::format("{}: a second environment (the first is {}.{}); a scene has at most one",
                                                 entry, path, environment));
        environment = i;
    }
    return lights;
}

std::vector<LightSpec> loadLightFile(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in || std::filesystem::is_directory(file))
        throw InputError(file, fmt::format("cannot read light file: {}",
                                           std::filesystem::is_directory(file) ? "it is a directory" : std::strerror(errno)));
    std::ostringstream text;
    text << in.rdbuf();
    YAML::Node root;
    try {
        root = YAML::Load(text.str());
    } catch (const YAML::ParserException& e) {
        throw InputError(file, e.mark.line + 1, e.mark.column + 1, fmt::format("invalid YAML: {}", e.msg));
    }
    const yaml::Context ctx(file);
    if (!root.IsSequence())
        ctx.fail(root, "lights",
                 fmt::format("a light file is a YAML list of lights (docs/lights.md), found {}", yaml::describe(root)));
    return readLightList(ctx, root, "lights");
}

std::vector<std::string> lightKeys() {
    std::vector<std::string> keys;
    for (const TypeInfo& t : types())
        for (const std::string& k : t.keys)
            if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    return keys;
}

nlohmann::ordered_json lightJson(const LightSpec& l) {
    if (l.type == LightType::Directional)
        return {{"type", toString(l.type)}, {"name", l.name}, {"direction", l.direction}, {"irradiance", l.emission}};
    if (l.type == LightType::Environment) {
        if (l.map.empty()) return {{"type", toString(l.type)}, {"name", l.name}, {"radiance", l.emission}};
        return {{"type", toString(l.type)}, {"name", l.name}, {"map", l.map}, {"scale", l.scale},
                {"rotation", l.rotation}, {"up", l.up}};
    }
    nlohmann::ordered_json j{{"type", toString(l.type)}, {"name", l.name}, {"position", l.position},
                             {toString(l.unit), l.emission}};
    switch (l.type) {
        case LightType::Point: j["normal"] = l.normal; break;
        case LightType::Spot:
            j["direction"] = l.direction;
            j["inner_angle"] = l.innerAngle;
            j["outer_angle"] = l.outerAngle;
            break;
        case LightType::Quad:
            j["normal"] = l.normal;
            j["up"] = l.up;
            j["size"] = l.size;
            break;
        case LightType::Disk:
            j["normal"] = l.normal;
            j["radius"] = l.radius;
            j["segments"] = l.segments;
            break;
        case LightType::Directional:
        case LightType::Environment: break;  // returned above
    }
    return j;
}

}  // namespace aamap
