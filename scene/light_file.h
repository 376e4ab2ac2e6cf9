#pragma once
// Lights described by hand: the light file (a YAML list, docs/lights.md) and the config's inline
// `lights:` list share this schema and one parser (eval/light_list.h reads the YAML into
// LightSpecs). addLights() merges them into a scene: point and spot lights become PointLights;
// quad and disk lights become emissive geometry plus an AreaLight, so the tracer's area-light
// sampling and the Snapshot's k-point approximation treat them like emitters from a model file;
// directional lights become DirectionalLights and an environment the scene's EnvironmentLight.
//
// Numbers stay doubles as written, so a config's canonical form (and its hash) prints them back.
#include <array>
#include <span>
#include <string>

#include <glm/mat3x3.hpp>

namespace aamap {

struct Scene;

enum class LightType { Point, Spot, Quad, Disk, Directional, Environment };
// "point", "spot", "quad", "disk", "directional", "environment". Inline, like the whole schema: the config parser needs no scene library.
inline const char* toString(LightType type) {
    switch (type) {
        case LightType::Point: return "point";
        case LightType::Spot: return "spot";
        case LightType::Quad: return "quad";
        case LightType::Disk: return "disk";
        case LightType::Directional: return "directional";
        case LightType::Environment: return "environment";
    }
    return "?";
}

// Which quantity `emission` holds; each type accepts its natural one or the total power.
enum class EmissionUnit {
    Intensity,  // point, spot: W/sr (a spot's on-axis intensity)
    Radiance,   // quad, disk: W/(sr m^2), one-sided along the normal; environment: the constant sky
    Power,      // point, spot, quad, disk: the total emitted flux in W (converted with the light's shape)
    Irradiance, // directional: W/m^2 on a surface facing the light
};
// The YAML key: "intensity", "radiance", "power", "irradiance".
inline const char* toString(EmissionUnit unit) {
    switch (unit) {
        case EmissionUnit::Intensity: return "intensity";
        case EmissionUnit::Radiance: return "radiance";
        case EmissionUnit::Power: return "power";
        case EmissionUnit::Irradiance: return "irradiance";
    }
    return "?";
}

struct LightSpec {
    LightType type = LightType::Point;
    std::string name;
    std::array<double, 3> position{0, 0, 0};   // point, spot: the light; quad, disk: the centre
    std::array<double, 3> normal{0, 0, 0};     // point: cosine-lobe axis (zero: isotropic); quad, disk: the emitting side
    std::array<double, 3> direction{0, 0, 0};  // spot: the cone axis; directional: where the light travels
    double innerAngle = 0.0, outerAngle = 45.0;  // spot: half-angles from the axis, degrees (glTF defaults)
    std::array<double, 3> up{0, 0, 0};         // quad: direction of the `size[1]` side (zero: any);
                                               // environment: the map's up (+Y of its frame; zero: +Y)
    std::array<double, 2> size{0, 0};          // quad: side lengths
    double radius = 0.0;                       // disk
    int segments = 32;                         // disk: triangles in the fan
    EmissionUnit unit = EmissionUnit::Intensity;
    std::array<double, 3> emission{0, 0, 0};   // RGB, in `unit` (environment with a map: unused)
    std::string map;        // environment: the lat-long EXR/HDR, resolved against the light file; "" = constant
    double scale = 1.0;     // environment: multiplies the map
    double rotation = 0.0;  // environment: degrees about `up`, right-handed, turning the map
};

// The rim radius of a regular `segments`-gon whose area is pi r^2: the disk's tessellation uses it,
// so the emitter's area, and with it the emitted power pi L A, is the disk's exactly.
double diskRimRadius(double radius, int segments);

// The environment frame's world-to-map rotation (EnvironmentLight::toLocal) for an `up` (zero: +Y)
// and a rotation in degrees about it.
glm::mat3 environmentToLocal(const std::array<double, 3>& up, double rotationDeg);

// Appends the lights to the scene, in order. Throws std::invalid_argument for a spec the parser
// would have rejected (zero normal, direction or size; inner angle above the outer one), for a
// second environment (the scene's own counts), and InputError (naming the map) for a map that
// cannot be read.
void addLights(Scene& scene, std::span<const LightSpec> lights);

}  // namespace aamap
