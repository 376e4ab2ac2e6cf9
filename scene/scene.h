#pragma once
// The scene model shared by the Snapshot passes and the tracer. Loaders (OBJ, glTF, view files,
// light lists, the built-in scenes) produce it; nothing downstream knows which format it came from.
//
// Units: positions are in scene units (metres for the built-in scenes; a scene may declare its
// own scale). Radiance is in W/(sr m^2) per RGB channel, point-light intensity in W/sr.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace aamap {

enum class MaterialKind : std::uint8_t {
    Diffuse,  // Lambert (+ optional glossy lobe from ks/ns, used by later tracer work)
    Mirror,   // ideal specular reflector (MTL illum 3 or 5)
    Glass,    // dielectric (MTL illum 7)
};

enum class AlphaMode : std::uint8_t { Opaque, Mask, Blend };

// How the tracer scatters at a material (docs/tracer.md, "BSDFs"). Classic reads kind, kd, ks, ns,
// ior; the others are Mitsuba's BSDFs of the same names and read the fields after `model`, while
// kind, kd, ks, ns stay the Snapshot's approximation of them.
enum class BsdfModel : std::uint8_t {
    Classic,    // Lambert + modified Phong, ideal mirror, Fresnel dielectric
    Conductor,  // conductor / roughconductor: complex-IOR Fresnel, optional microfacet roughness
    Plastic,    // plastic / roughplastic: dielectric coating over a diffuse base
    Dielectric, // roughdielectric: microfacet reflection and refraction (kind Glass)
    Blend,      // blendbsdf: (1 - blendWeight) x blend[0] + blendWeight x blend[1] (kind Diffuse)
};

// Microfacet normal distributions (tracer/microfacet.h).
enum class MicrofacetType : std::uint8_t { Beckmann, GGX };

struct Material {
    std::string name;
    MaterialKind kind = MaterialKind::Diffuse;
    glm::vec3 kd{0.8f};   // diffuse albedo
    glm::vec3 ks{0.0f};   // specular albedo
    float ns = 0.0f;      // Phong exponent
    glm::vec3 ke{0.0f};   // emitted radiance; non-zero makes its triangles area lights
    float ior = 1.5f;
    // Glass only: a thin sheet (Mitsuba's thindielectric) that light crosses straight, without
    // refraction: reflectance R' = 2R / (1 + R) of the single interface's R (both faces and their
    // inter-reflections), transmittance 1 - R'.
    bool thin = false;
    // Reflects only from the front (Mitsuba's BSDFs outside `twosided`); the back is black. Emission
    // is one-sided regardless. OBJ and glTF materials shade both sides.
    bool oneSided = false;
    int diffuseTexture = -1;  // index into Scene::textures, -1 if untextured
    // Coverage (docs/architecture.md, "Alpha"): alpha = alpha * (alphaTexture's alpha channel).
    // Mask cuts out where alpha < alphaCutoff; Blend is treated as Mask at alphaCutoff = 0.5 by
    // both the Snapshot and the tracer (a deterministic cut-out that both agree on).
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alpha = 1.0f;        // glTF baseColorFactor.a, MTL d (or 1 - Tr)
    float alphaCutoff = 0.5f;  // glTF alphaCutoff
    int alphaTexture = -1;     // glTF: the baseColorTexture; MTL: map_d (coverage in alpha)
    // Mitsuba's normalmap / bumpmap around this material (docs/tracer.md, "Normal and bump maps"):
    // the shading normal is tilted in the frame of the shading normal and dp/du.
    int normalMap = -1;      // texel rgb -> 2 rgb - 1 in (dp/du, n x dp/du, n); -1: none
    int bumpMap = -1;        // a height field: its uv gradient (of the luminance) times bumpScale
    float bumpScale = 1.0f;
    // A twosided wraps the map: seen from the back, the map's tilt is mirrored through the
    // tangent plane (twosided mirrors the directions); otherwise the tilted normal is negated.
    bool mapMirroredOnBack = false;

    BsdfModel model = BsdfModel::Classic;
    MicrofacetType distribution = MicrofacetType::Beckmann;
    float alphaU = 0.0f, alphaV = 0.0f;  // microfacet roughness along tangent / bitangent; 0: smooth
    // Conductor, Plastic: a textured isotropic roughness (Mitsuba's `alpha` as a texture): alpha is
    // the texel's luminance; alphaU = alphaV hold the texture's mean (the Snapshot's). -1: none.
    int roughnessTexture = -1;
    glm::vec3 eta{0.0f}, k{1.0f};        // Conductor: complex index of refraction per channel
    glm::vec3 specularReflectance{1.0f}; // Conductor, Plastic, Dielectric: tint of the specular lobes
    bool nonlinear = false;              // Plastic: the diffuse base's colour shifts with internal scattering
    // Plastic and Dielectric use `ior` (interior over exterior) and Plastic `kd` / `diffuseTexture`.
    // Blend: its two components, each non-delta, untextured and not itself a blend; kd, ks, ns
    // are the Snapshot's mix of theirs.
    std::vector<Material> blend;
    float blendWeight = 0.5f;
};

// Whether a material can cut holes: Mask, or Blend (treated as a mask at 0.5).
inline bool isAlphaTested(const Material& m) { return m.alphaMode != AlphaMode::Opaque; }
// The cutoff that applies: Blend cuts at 0.5.
inline float effectiveAlphaCutoff(const Material& m) {
    return m.alphaMode == AlphaMode::Blend ? 0.5f : m.alphaCutoff;
}

// One merged triangle mesh: the scene is small enough that Embree and Vulkan both take it whole.
struct TriangleMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;     // per vertex, same count as positions
    std::vector<glm::vec2> uvs;         // per vertex, empty if none; v = 0 is the image's top row
                                        // (glTF/Vulkan convention; OBJ vt is flipped on load)
    std::vector<glm::uvec3> triangles;  // indices into positions
    std::vector<std::uint32_t> materialIds;  // per triangle, index into Scene::materials
    std::vector<std::uint32_t> objectIds;    // per triangle, the OBJ group / glTF node it came from
};

struct PointLight {
    std::string name;
    glm::vec3 position{0.0f};
    glm::vec3 intensity{0.0f};  // W/sr per channel: isotropic, or along `normal` for a lobe
    // Zero: isotropic. Non-zero (unit): emits intensity * max(0, cos) around it, as a point sample
    // of a one-sided Lambertian area light does.
    glm::vec3 normal{0.0f};
    // Spot cone (glTF KHR_lights_punctual spot; the light file's `spot`). Non-zero (unit, and
    // `normal` zero): emits intensity * spotFalloff(cos to the axis, cosInner, cosOuter)
    // (scene/lights.h): full inside the inner cone, nothing outside the outer one, smooth between.
    glm::vec3 spotDirection{0.0f};
    float cosInner = 1.0f, cosOuter = 0.0f;  // cosines of the half-angles, cosInner >= cosOuter
};

// A group of emissive triangles with one radiance (one OBJ object with a Ke material, say).
// The tracer samples it by area; the Snapshot approximates it with k point samples.
struct AreaLight {
    std::string name;
    std::vector<std::uint32_t> triangles;  // indices into TriangleMesh::triangles
    glm::vec3 radiance{0.0f};              // W/(sr m^2), one-sided, along the triangle normal
    float area = 0.0f;                     // total area in scene units^2
};

// Light from infinitely far away in one direction (a sun; Mitsuba's `directional`).
struct DirectionalLight {
    std::string name;
    glm::vec3 direction{0, -1, 0};  // unit, the direction the light travels (from the light)
    glm::vec3 irradiance{0.0f};     // W/m^2 per channel on a surface facing the light
};

// Radiance arriving from infinitely far away in every direction: a constant sky, or an
// equirectangular (latitude-longitude) map. Radiance from world direction d (pointing away from
// the scene, towards the sky) is scale * map(toLocal * d), or scale alone without a map.
// The map's convention is Mitsuba's `envmap`, so imported scenes need no conversion: in the
// light's local frame (+Y up), column u = atan2(x, -z) / (2 pi) (wrapping) and row
// v = acos(y) / pi, row 0 at the top (+Y).
struct EnvironmentLight {
    std::string name;
    glm::vec3 scale{1.0f};               // multiplies the map; the radiance itself without one
    std::optional<std::filesystem::path> mapPath;  // EXR or Radiance HDR, linear RGB
    int mapWidth = 0, mapHeight = 0;
    std::vector<glm::vec3> map;          // linear radiance, row 0 at the top; empty: constant
    glm::mat3 toLocal{1.0f};             // world direction -> the map's frame (inverse rotation)
};

// A Radiance view (rview/rpict -v options). Only perspective (-vtv) views for now.
struct View {
    std::string name;             // "" or the name given in the view file / config
    glm::vec3 position{0.0f};     // -vp
    glm::vec3 direction{0, 0, -1};  // -vd (not necessarily unit length in the file; stored normalised)
    glm::vec3 up{0, 1, 0};        // -vu
    float horizontalFovDeg = 45;  // -vh, full angle
    float verticalFovDeg = 45;    // -vv, full angle
    float shiftX = 0, shiftY = 0;  // -vs, -vl (fractions of the view)
};

struct Texture {
    std::filesystem::path path;
    int width = 0, height = 0;
    std::vector<float> rgba;  // linear, row 0 at the top
};

// How the scene file asks to be rendered (a Mitsuba <integrator>, its sensor's <sampler> and
// <rfilter>). The experiment config's own settings win; eval/experiment.cpp applies the rest and
// says which.
struct SceneRenderSettings {
    std::string integrator;         // its type ("path", "direct", ...); "" when the file names none
    std::string at;                 // "file:line" of the integrator
    std::optional<int> maxDepth;    // longest path in segments; unset: unlimited (Mitsuba's -1)
    std::optional<int> rrDepth;     // Russian roulette from this depth on
    bool hideEmitters = false;      // camera rays see no emission and no environment
    std::optional<int> sampleCount;  // the sampler's samples per pixel
    std::string filter;             // the film's rfilter type; "" when the file names none
};

struct Scene {
    std::string name;
    std::filesystem::path source;  // file it was loaded from, "" for built-in scenes
    TriangleMesh mesh;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<PointLight> pointLights;
    std::vector<AreaLight> areaLights;
    std::vector<DirectionalLight> directionalLights;
    std::optional<EnvironmentLight> environment;  // at most one sky
    std::vector<View> views;  // views that came with the scene (glTF cameras, built-in default view)
    int imageWidth = 0, imageHeight = 0;  // the image size the scene file asks for (a Mitsuba film); 0: none
    SceneRenderSettings render;           // the rest of how the file asks to be rendered

    bool hasTextures() const { return !textures.empty(); }
};

}  // namespace aamap
