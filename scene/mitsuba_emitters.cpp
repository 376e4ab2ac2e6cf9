#include "scene/mitsuba_emitters.h"

#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "scene/environment_map.h"
#include "scene/mitsuba_transform.h"
#include "scene/text_util.h"
#include "scene/texture_loader.h"  // resolveCaseInsensitive

namespace aamap::mitsuba {
namespace fs = std::filesystem;

namespace {


glm::vec3 axisOf(const glm::mat4& m, int column) { return glm::vec3(m[column]); }

void loadMap(const Element& emitter, EnvironmentLight& env) {
    const std::string name = stringProperty(emitter, "filename", "");
    if (name.empty()) fail(emitter, "envmap has no filename");
    const auto path = resolveCaseInsensitive(emitter.file.parent_path(), name);
    if (!path) fail(emitter, fmt::format("environment map '{}' not found", (emitter.file.parent_path() / name).string()));
    std::string error;
    if (!loadEnvironmentMap(*path, env, error)) fail(emitter, error);
}

void setEnvironment(const Element& emitter, Scene& scene, EnvironmentLight env) {
    if (scene.environment) fail(emitter, "a second environment emitter (envmap or constant); a scene has at most one");
    scene.environment = std::move(env);
}

// tan of the half field of view along x and y for the sensor's fov and fov_axis.
std::pair<double, double> halfTangents(const Element& sensor, double fovDeg, int width, int height) {
    const std::string axis = text::toLower(stringProperty(sensor, "fov_axis", "x"));
    const double t = std::tan(glm::radians(fovDeg) * 0.5);
    const double aspect = static_cast<double>(width) / height;
    std::string a = axis;
    if (a == "smaller") a = width < height ? "x" : "y";
    if (a == "larger") a = width > height ? "x" : "y";
    if (a == "x") return {t, t / aspect};
    if (a == "y") return {t * aspect, t};
    if (a == "diagonal") {
        const double d = std::hypot(static_cast<double>(width), static_cast<double>(height));
        return {t * width / d, t * height / d};
    }
    fail(*sensor.property("fov_axis"), fmt::format("fov_axis '{}' is not x, y, diagonal, smaller or larger", axis));
}

}  // namespace

glm::vec3 areaRadiance(const Element& emitter, Warnings& warnings) {
    if (emitter.type() != "area") fail(emitter, fmt::format("a shape's emitter must be 'area', not '{}'", emitter.type()));
    return colourProperty(emitter, "radiance", glm::vec3(1.0f), warnings, SpectrumUse::Emission);
}

void addEmitter(const Element& emitter, Scene& scene, Warnings& warnings) {
    const std::string type = emitter.type();
    const glm::mat4 toWorld = transformProperty(emitter);
    const std::string name = emitter.id().empty() ? fmt::format("{}@{}", type, emitter.line) : emitter.id();
    if (type == "point") {
        PointLight p;
        p.name = name;
        p.position = emitter.property("position") ? pointProperty(emitter, "position", glm::vec3(0.0f)) : glm::vec3(toWorld[3]);
        p.intensity = colourProperty(emitter, "intensity", glm::vec3(1.0f), warnings, SpectrumUse::Emission);
        scene.pointLights.push_back(std::move(p));
    } else if (type == "spot") {
        PointLight p;
        p.name = name;
        p.position = glm::vec3(toWorld[3]);
        p.intensity = colourProperty(emitter, "intensity", glm::vec3(1.0f), warnings, SpectrumUse::Emission);
        const float cutoff = floatProperty(emitter, "cutoff_angle", 20.0f);
        const float beam = floatProperty(emitter, "beam_width", cutoff * 0.75f);
        if (!(cutoff > 0.0f && cutoff < 180.0f) || !(beam >= 0.0f && beam <= cutoff))
            fail(emitter, fmt::format("spot cutoff_angle {} and beam_width {} need 0 <= beam_width <= cutoff_angle < 180",
                                      cutoff, beam));
        const glm::vec3 axis = axisOf(toWorld, 2);
        if (!(glm::length(axis) > 0.0f)) fail(emitter, "spot to_world has no direction");
        p.spotDirection = glm::normalize(axis);
        p.cosInner = std::cos(glm::radians(beam));
        p.cosOuter = std::cos(glm::radians(cutoff));
        warnings.once("spot", fmt::format("{}: spot falloff between beam_width and cutoff_angle uses aamap's smooth "
                                          "(glTF) curve instead of Mitsuba's linear one", emitter.location()));
        scene.pointLights.push_back(std::move(p));
    } else if (type == "directional") {
        DirectionalLight d;
        d.name = name;
        const glm::vec3 dir = emitter.property("direction") ? pointProperty(emitter, "direction", glm::vec3(0, 0, 1))
                                                            : axisOf(toWorld, 2);
        if (!(glm::length(dir) > 0.0f)) fail(emitter, "directional light has a zero direction");
        d.direction = glm::normalize(dir);
        d.irradiance = colourProperty(emitter, "irradiance", glm::vec3(1.0f), warnings, SpectrumUse::Emission);
        scene.directionalLights.push_back(std::move(d));
    } else if (type == "envmap") {
        EnvironmentLight env;
        env.name = name;
        env.scale = glm::vec3(floatProperty(emitter, "scale", 1.0f));
        loadMap(emitter, env);
        // Only the rotation: a scale in to_world must not change directions' lengths.
        glm::mat3 r(toWorld);
        for (int c = 0; c < 3; ++c) r[c] = glm::normalize(r[c]);
        env.toLocal = glm::transpose(r);
        setEnvironment(emitter, scene, std::move(env));
    } else if (type == "constant") {
        EnvironmentLight env;
        env.name = name;
        env.scale = colourProperty(emitter, "radiance", glm::vec3(1.0f), warnings, SpectrumUse::Emission);
        setEnvironment(emitter, scene, std::move(env));
    } else if (type == "area") {
        fail(emitter, "an area emitter belongs inside a <shape>");
    } else {
        fail(emitter, fmt::format("unknown emitter type '{}' (supported: area, point, spot, directional, envmap, constant)",
                                  type));
    }
}

void addSensor(const Element& sensor, Scene& scene, Warnings& warnings) {
    const std::string type = sensor.type();
    if (type == "thinlens") {
        warnings.once("thinlens", fmt::format("{}: the thin-lens sensor is a pinhole here (no depth of field)", sensor.location()));
    } else if (type != "perspective") {
        fail(sensor, fmt::format("sensor type '{}' is not supported (only perspective and thinlens)", type));
    }
    int width = 768, height = 576;
    const bool first = scene.views.empty();  // the scene's render settings come from its first sensor
    for (const Element& c : sensor.children) {
        if (c.tag == "sampler" && first) {
            const int spp = integerProperty(c, "sample_count", 4);
            if (spp < 1) fail(c, fmt::format("sample_count {} is not positive", spp));
            scene.render.sampleCount = spp;
        }
        if (c.tag != "film") continue;
        width = integerProperty(c, "width", width);
        height = integerProperty(c, "height", height);
        if (width < 1 || height < 1 || width > 16384 || height > 16384)
            fail(c, fmt::format("film size {} x {} is outside 1..16384", width, height));
        for (const Element& f : c.children)
            if (f.tag == "rfilter" && first) scene.render.filter = f.type();
    }
    double fov = 0.0;
    if (sensor.property("fov") != nullptr) {
        fov = floatProperty(sensor, "fov", 0.0f);
    } else {
        // A focal length on 35 mm film, measured along the diagonal as Mitsuba does.
        std::string focal = stringProperty(sensor, "focal_length", "50mm");
        if (focal.ends_with("mm")) focal.resize(focal.size() - 2);
        const auto f = text::parseNumber(text::trim(focal));
        if (!f || !(*f > 0.0)) fail(sensor, fmt::format("focal_length '{}' is not a positive length", focal));
        fov = glm::degrees(2.0 * std::atan(std::hypot(36.0, 24.0) / (2.0 * *f)));
    }
    if (!(fov > 0.0 && fov < 180.0)) fail(sensor, fmt::format("fov {} is outside (0, 180) degrees", fov));
    auto [tx, ty] = halfTangents(sensor, fov, width, height);
    if (sensor.property("fov") == nullptr) {  // focal_length: the diagonal
        const double t = std::tan(glm::radians(fov) * 0.5), d = std::hypot(double(width), double(height));
        tx = t * width / d;
        ty = t * height / d;
    }
    const float nearClip = floatProperty(sensor, "near_clip", 1e-2f);
    if (!(nearClip > 0.0f)) fail(sensor, fmt::format("near_clip {} is not positive", nearClip));

    const glm::mat4 m = transformProperty(sensor);
    View v;
    v.name = sensor.id().empty() ? fmt::format("{}:sensor", sensor.file.stem().string()) : sensor.id();
    v.position = glm::vec3(m[3]);
    v.direction = glm::normalize(axisOf(m, 2));
    v.up = glm::normalize(axisOf(m, 1));
    if (glm::length(glm::cross(v.direction, v.up)) < 1e-6f) fail(sensor, "the sensor's to_world has up parallel to its view");
    // Mitsuba's image right is the local -X; a transform whose -X is not cross(direction, up)
    // mirrors the image, which a View cannot.
    if (glm::dot(-axisOf(m, 0), glm::cross(v.direction, v.up)) < 0.0f)
        warnings.once("mirrored-sensor", fmt::format("{}: the sensor's to_world mirrors the image; it is rendered unmirrored",
                                                     sensor.location()));
    v.horizontalFovDeg = static_cast<float>(glm::degrees(2.0 * std::atan(tx)));
    v.verticalFovDeg = static_cast<float>(glm::degrees(2.0 * std::atan(ty)));
    scene.views.push_back(v);
    if (scene.imageWidth == 0) {
        scene.imageWidth = width;
        scene.imageHeight = height;
    }
}

}  // namespace aamap::mitsuba
