#pragma once
// The scene's GPU state, shared by every Snapshot raster (G-buffer, shadow cube maps, geometry
// buffer, mirror views): the mesh flattened into one vertex buffer with its materials, the
// distinct positions for position-only draws, the light list as a uniform buffer plus the
// specialisation constants that inline it, the texture atlas, and the CPU copies the shadow pass
// culls with. Built once per scene, so that several views and passes reuse it; passes read it
// and never each other.
//
// Glass: the tracer ignores a dielectric's kd and shows what lies behind it (Fresnel reflection
// and refraction; a thin pane transmits ~92 % of it, barely shifted), and its shadow rays stop at
// glass. So the camera's opaque draws skip glass triangles, the G-buffer then draws them over
// what they show, Fresnel-weighted (passes/gbuffer.h; without the refraction offset), and the
// shadow cube maps draw them as occluders. They come last in the vertex buffer, so the opaque
// draws take the first vertexCount() vertices, the glass draw the rest of occluderVertexCount(),
// and the shadow pass all of them. Glass vertices carry their normal-incidence Fresnel
// reflectance in the kd slot.
//
// Textures and alpha (passes/gbuffer_textures.h): a scene whose used materials sample a texture
// gets the textured vertex layout (uv and atlas entry per vertex) and an atlas; other scenes bind
// no texture at all. Alpha-tested materials with constant coverage need no texture: their
// triangles are either dropped (alpha < cutoff) or opaque.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "engine/vk/resources.h"
#include "glsl/shared/snapshot_interface.h"
#include "scene/scene.h"

namespace aamap::passes {

class SceneGpu {
public:
    // Vertex layout: position, normal, kd, ke (vec3 each), then the glossy lobe (ks, Phong
    // exponent ns; ks 0: none) as the tracer's modified Phong, or a microfacet lobe's tint; then
    // the microfacet lobe's parameters (GpuLobe, 3 x 4 16-bit floats); the textured layout adds uv, the
    // atlas entry (4 x u16) and its parameters (layer, alpha threshold) at the offsets below.
    static constexpr std::uint32_t kVertexStride = 88;
    static constexpr std::uint32_t kNormalOffset = 12, kKdOffset = 24, kKeOffset = 36, kSpecularOffset = 48;
    static constexpr std::uint32_t kLobeOffset = 64, kLobeEtaOffset = 72, kLobeKOffset = 80;
    static constexpr std::uint32_t kTexturedVertexStride = 112;
    static constexpr std::uint32_t kUvOffset = 88, kTexRectOffset = 96, kTexParamsOffset = 104;

    SceneGpu(VulkanContext& context, const Scene& scene);  // uploads the mesh with its materials

    // Uploads the light list: the point lights, then the directional ones (each shadowed by an
    // orthographic map over the bounding sphere of the mesh), and the ambient SH irradiance
    // (passes/environment_lighting.h; null: none). Throws std::invalid_argument past
    // GBUFFER_MAX_LIGHTS (256) lights. Passes declared before must be declared again before they
    // execute (the light buffer is replaced), and lightsVersion() counts the calls.
    // patchHalfSides[i] > 0 marks point light i (a cosine lobe) as the sample of a patch of an area
    // light, a square of that half side: its shadows are soft (GpuLight::cone.w). Missing entries,
    // zeros, non-finite values and non-lobe lights: hard shadows.
    void setLights(std::span<const PointLight> lights, std::span<const DirectionalLight> directionals = {},
                   const std::array<glm::vec3, 9>* ambientSH = nullptr, std::span<const float> patchHalfSides = {});
    bool softShadows() const { return softShadows_; }  // some light has a patch
    // Radiance of the background (where no surface is drawn); black by default. Passes declared
    // before must be declared again, as after setLights.
    void setBackground(const glm::vec3& radiance) { background_ = radiance; }
    glm::vec3 background() const { return background_; }

    // Vertices the camera draws (three per triangle, vertex-buffer order from 0), and those the
    // shadow pass draws: the same followed by the glass triangles (see "Glass" above).
    std::uint32_t vertexCount() const { return vertexCount_; }
    std::uint32_t occluderVertexCount() const { return occluderVertexCount_; }
    std::uint32_t glassVertexCount() const { return occluderVertexCount_ - vertexCount_; }
    // The mesh triangle of each triangle of the vertex buffer (occluderVertexCount() / 3 of them).
    std::span<const std::uint32_t> drawnTriangles() const { return drawnTriangles_; }
    bool textured() const { return textured_; }        // the atlas is bound (scene has textures)
    bool alphaMasked() const { return alphaMasked_; }  // some texel can be cut out (shadows test it)
    const vk::Image& atlas() const { return atlas_; }  // valid only when textured()
    std::string atlasSummary() const;                  // for --explain
    std::uint32_t vertexStride() const { return textured_ ? kTexturedVertexStride : kVertexStride; }
    const vk::Buffer& vertexBuffer() const { return vertices_; }

    std::uint32_t lightCount() const { return lightCount_; }
    bool ambient() const { return ambient_; }  // the environment's SH term is shaded
    const vk::Buffer& lightBuffer() const { return lights_; }
    // The LIGHTING_SPEC_* specialisation constants of a lit fragment shader drawing these lights
    // with this PCF side (glsl/lights.glsl).
    std::vector<std::uint32_t> lightingConstants(std::uint32_t pcf) const;
    std::uint64_t lightsVersion() const { return lightsVersion_; }
    // Texels per side of each light's shadow cube faces (GpuLight::position.w, inlined by the lit
    // shaders; passes/view_budget.h shadowFaceSizes). setLights sets them to 0: whoever adds the
    // shadow pass sets them, one per light, each at least 1. A change replaces the light buffer,
    // as setLights does, but keeps lightsVersion() (the light set, its positions) and bumps
    // shadingVersion().
    void setShadowFaceSizes(std::span<const std::uint32_t> sizes);
    std::span<const std::uint32_t> shadowFaceSizes() const { return faceSizes_; }
    // Counts the changes of what the lit shaders inline: light lists and shadow face sizes.
    std::uint64_t shadingVersion() const { return shadingVersion_; }

    // CPU copies for the shadow pass's per-face culling: the occluders' vertex positions (three per
    // triangle, in vertex-buffer order) and the lights' positions.
    std::span<const glm::vec3> vertexPositions() const { return positions_; }
    std::span<const glm::vec3> lightPositions() const { return lightPositions_; }
    // Per light: 1 if directional (its shadow map is one orthographic layer, face 0), else 0.
    std::span<const std::uint8_t> lightDirectional() const { return lightDirectional_; }

    // The distinct positions (bit-equal corners merged) and, per vertex of vertexBuffer(), its
    // index among them: position-only passes (depth pre-pass, shadow cube maps) draw these, so
    // the vertex cache shades a shared corner once. Empty when alphaMasked() (those passes then
    // need uv and atlas entry per vertex).
    bool sharedPositions() const { return !positionIndex_.empty(); }
    const vk::Buffer& positionBuffer() const { return sharedPositions_; }
    const vk::Buffer& positionIndexBuffer() const { return positionIndices_; }
    std::span<const std::uint32_t> positionIndex() const { return positionIndex_; }
    // The camera's vertices by triangle, last triangle first (same corners, same provoking
    // vertex), as an index buffer; only with sharedPositions() (passes/gbuffer.h, depth pre-pass).
    const vk::Buffer& reversedTriangleBuffer() const { return reversedTriangles_; }

private:
    VulkanContext* context_;
    vk::Buffer vertices_, lights_;
    vk::Buffer sharedPositions_, positionIndices_;  // positionIndex_ as an index buffer
    vk::Buffer reversedTriangles_;
    std::vector<std::uint32_t> positionIndex_;
    vk::Image atlas_;
    std::vector<glm::vec3> positions_, lightPositions_;
    std::vector<std::uint8_t> lightDirectional_;
    glm::vec3 coverCentre_{0.0f};  // the sphere every directional shadow map covers
    float coverRadius_ = 1.0f;
    bool ambient_ = false;
    bool microfacet_ = false;  // some drawn material has a microfacet lobe (LIGHTING_SPEC_MICROFACET)
    glm::vec3 background_{0.0f};
    std::array<glm::vec3, 9> ambientSH_{};
    std::uint64_t lightsVersion_ = 0, shadingVersion_ = 0;
    std::vector<gpu::GpuLight> gpuLights_;    // the whole list as uploaded (GBUFFER_MAX_LIGHTS entries)
    std::vector<std::uint32_t> faceSizes_;    // per light, its position.w
    bool textured_ = false, alphaMasked_ = false;
    std::uint32_t atlasEntries_ = 0;
    std::uint32_t vertexCount_ = 0, occluderVertexCount_ = 0;
    std::vector<std::uint32_t> drawnTriangles_;
    std::uint32_t lightCount_ = 0, lightKinds_ = 0;  // LIGHT_KIND_* bits
    bool softShadows_ = false;
    std::vector<gpu::GpuLight> inlineLights_;        // the first LIGHTING_INLINE_LIGHTS, for the constants
};

}  // namespace aamap::passes
