#pragma once
// The Embree side of the tracer: one device, the merged mesh as one triangle geometry, and the
// per-triangle data that shading needs (kept here so the tracer does not depend on the Scene
// outliving it). Also decides which shading features the scene needs (textures, glossy, mirror,
// glass): code paths for the others are never entered.
#include <cstdint>
#include <limits>
#include <string>
#include <array>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"
#include "core/texture_filter.h"

namespace aamap {

// What shading reads per material; precomputed so the hot path only multiplies. Mapping from the
// Scene's Material (see docs/tracer.md): Diffuse = Lambert kd (x texture) + modified-Phong glossy
// lobe ks, ns; Mirror = Lambert kd + ideal reflection ks; Glass = dielectric (Fresnel, ior) tinted
// by ks. When kd + ks exceeds 1 in a channel both are scaled down so no material creates energy.
struct ShadingMaterial {
    MaterialKind kind = MaterialKind::Diffuse;
    bool emissive = false;
    bool diffuse = false;  // a non-zero Lambert lobe (kd > 0 or textured)
    bool glossy = false;   // Diffuse kind with ks > 0: Phong lobe
    int texture = -1;      // index into the scene's textures, modulates kd
    glm::vec3 kd{0.0f};
    glm::vec3 kdOverPi{0.0f};  // Lambert BRDF (untextured)
    glm::vec3 ks{0.0f};        // glossy albedo, mirror reflectance or glass tint
    float ns = 0.0f;
    float phongNorm = 0.0f;    // (ns + 2) / (2 pi): BRDF normalisation
    float phongPdfNorm = 0.0f; // (ns + 1) / (2 pi): sampling pdf normalisation
    float diffuseWeight = 1.0f;  // probability of sampling the Lambert lobe (vs glossy)
    float ior = 1.5f;
    bool thin = false;      // Glass: a thin sheet (straight through, R' = 2R / (1 + R)); see scene.h
    bool oneSided = false;  // the back reflects nothing (Mitsuba's BSDFs outside twosided)
    glm::vec3 ke{0.0f};
    // Alpha test (Mask, or Blend cut at 0.5; see scene.h): a hit is cut out where
    // alpha * alphaTexture.a < alphaCutoff. Only tested materials reach the Embree filter.
    bool alphaTested = false;
    float alpha = 1.0f, alphaCutoff = 0.5f;
    int alphaTexture = -1;  // index into the scene's textures, -1: constant alpha
    // Normal and bump maps (scene.h): indices into the scene's textures, -1: none.
    int normalMap = -1, bumpMap = -1;
    float bumpScale = 1.0f;
    bool mapMirroredOnBack = false;
    bool perturbed() const { return normalMap >= 0 || bumpMap >= 0; }
    // A mapped material as seen from below its tilted normal: its emission and cut-outs, no
    // reflection (owned by the EmbreeScene). nullptr for unmapped materials.
    const ShadingMaterial* unlit = nullptr;

    // Mitsuba's BSDFs (model != Classic; tracer/bsdf.h). kind is Mirror for the smooth conductor and
    // plastic (their delta lobe goes through the mirror paths), Diffuse for the rough ones.
    BsdfModel model = BsdfModel::Classic;
    bool rough = false;  // a microfacet lobe (alpha > 0)
    MicrofacetType distribution = MicrofacetType::Beckmann;
    float alphaU = 0.0f, alphaV = 0.0f;
    glm::vec3 eta{0.0f}, k{1.0f};         // Conductor
    glm::vec3 specularTint{1.0f};         // specular_reflectance
    bool nonlinear = false;               // Plastic
    float specularWeight = 0.5f;          // Plastic: share of samples for the coating, by albedo
    float internalReflectance = 0.0f;     // Plastic: the coating's reflectance seen from below, averaged
    float meanExitTransmittance = 1.0f;   // Plastic: the coating's transmittance averaged over the hemisphere
    // Rough plastic: the coating's transmittance (1 - its directional albedo) at cos = i / (N - 1).
    static constexpr int kTransmittanceRes = 64;
    std::array<float, kTransmittanceRes> transmittance{};
    // Textured roughness (scene.h, Material::roughnessTexture): the material at kRoughnessLevels
    // alphas from roughnessMin in steps of roughnessStep (owned by the EmbreeScene); a hit takes
    // the level nearest its texel's alpha (EmbreeScene::atHit). nullptr: one alpha.
    static constexpr int kRoughnessLevels = 64;
    int roughnessTexture = -1;
    const ShadingMaterial* roughnessLevels = nullptr;
    float roughnessMin = 0.0f, roughnessStep = 0.0f;
    // Blend: the two components (owned by the EmbreeScene, which cannot be copied) and the
    // second one's weight.
    const ShadingMaterial* blendA = nullptr;
    const ShadingMaterial* blendB = nullptr;
    float blendWeight = 0.5f;
};

struct Triangle {
    glm::vec3 v0, e1, e2;  // v1 = v0 + e1, v2 = v0 + e2
    glm::vec3 normal;      // unit geometric normal, cross(e1, e2): counter-clockwise is the front
    std::uint32_t material;
    float vertexScale;     // max |coordinate| of its vertices: sets the float error of a rebuilt hit point
    bool flat;             // its vertex normals equal `normal` (or there are none): skip interpolation
};

// Which optional shading paths the scene needs, and why (logged once per scene).
struct SceneFeatures {
    bool textures = false, glossy = false, mirror = false, glass = false, emissive = false;
    bool alphaMask = false;  // a used material can cut holes: Embree filter functions installed
    std::string describe() const;
};

struct TextureData {
    int width = 0, height = 0;
    std::vector<PackedLevel> rgb;  // linear colour's mip chain (core/texture_filter.h); empty: unusable
    glm::vec3 mean{1.0f};          // the texture's mean colour (the 1 x 1 top of the chain, unrounded)
    std::vector<float> alpha;   // coverage at level 0, only for textures an alpha-tested material uses
};

// A single ray from origin along dir over [0, inf), ready for rtcIntersect1: every field Embree
// reads is set, so callers never hand-fill RTCRayHit.
inline RTCRayHit makeRayHit(const glm::vec3& origin, const glm::vec3& dir) {
    RTCRayHit rh{};
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

class EmbreeScene {
public:
    explicit EmbreeScene(const Scene& scene);  // validates the mesh (std::invalid_argument) and builds
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    RTCScene handle() const { return scene_; }
    double buildSeconds() const { return buildSeconds_; }
    const SceneFeatures& features() const { return features_; }

    const Triangle& triangle(std::uint32_t id) const { return triangles_[id]; }
    std::size_t triangleCount() const { return triangles_.size(); }
    const ShadingMaterial& material(std::uint32_t id) const { return materials_[id]; }
    // The material that shades a hit on triangle `id` at barycentrics (u, v): m, or for a textured
    // roughness the level of m nearest the texel's alpha (bilinear, level 0, as Mitsuba's bitmap).
    const ShadingMaterial& atHit(const ShadingMaterial& m, std::uint32_t id, float u, float v) const {
        return m.roughnessLevels == nullptr ? m : roughnessLevel(m, id, u, v);
    }
    std::size_t materialCount() const { return materials_.size(); }
    // Unit interpolated vertex normal at barycentrics (u, v); the geometric normal if the mesh has
    // no usable normals there.
    glm::vec3 shadingNormal(std::uint32_t id, float u, float v) const;
    // The shading normal `n` (shadingNormal's, not turned to a side) tilted by m's normal or bump
    // map as Mitsuba 3 does (docs/tracer.md, "Normal and bump maps"); `n` itself where m has no
    // map, the triangle's uvs are degenerate or the result is not finite.
    glm::vec3 perturbedNormal(const ShadingMaterial& m, std::uint32_t id, float u, float v, const glm::vec3& n) const;
    // Diffuse albedo at barycentrics (u, v): kd, times the texture for a textured material (only
    // those fetch). footprint: the width of the ray's cone at the hit, arriving along unit `dir`;
    // the texture is filtered over the cone's footprint on the triangle (core/texture_filter.h),
    // and a zero footprint takes the plain bilinear (repeating) texel.
    glm::vec3 albedo(const ShadingMaterial& m, std::uint32_t id, float u, float v, const glm::vec3& dir = {},
                     float footprint = 0.0f) const {
        return m.texture < 0 ? m.kd : m.kd * texel(m.texture, id, u, v, dir, footprint);
    }
    // Whether the surface of triangle `id` at barycentrics (u, v) is cut out by its material's
    // alpha test (bilinear coverage, the same texel rule as albedo()). False for opaque materials.
    bool cutOut(std::uint32_t id, float u, float v) const;

private:
    glm::vec3 texel(int texture, std::uint32_t id, float u, float v, const glm::vec3& dir, float footprint) const;
    const ShadingMaterial& roughnessLevel(const ShadingMaterial& m, std::uint32_t id, float u, float v) const;
    // The levels of each used material with a roughness texture (after the textures are read).
    void buildRoughnessLevels(const std::vector<char>& used);
    float coverage(int texture, std::uint32_t id, float u, float v) const;
    glm::vec2 textureCoordinates(std::uint32_t id, float u, float v) const;

    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    double buildSeconds_ = 0.0;
    SceneFeatures features_;
    std::vector<Triangle> triangles_;
    std::vector<ShadingMaterial> materials_;
    std::vector<ShadingMaterial> blendComponents_;  // what Blend materials point to, two each
    std::vector<ShadingMaterial> roughnessLevels_;  // what textured-roughness materials point to
    std::vector<ShadingMaterial> unlit_;            // what mapped materials point to, one each
    std::vector<glm::vec3> vertexNormals_;  // 3 per triangle, empty without normals
    std::vector<glm::vec2> vertexUvs_;      // 3 per triangle, only when a used material is textured,
                                            // alpha-tested with a texture, or has a map (normal,
                                            // bump, roughness)
    std::vector<TextureData> textures_;     // only when a used material is textured, alpha-tested or mapped
};

}  // namespace aamap
