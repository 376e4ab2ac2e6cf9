// Structs, push constants and binding numbers shared by the Snapshot's C++ passes and shaders.
// Included from GLSL (glslc -I glsl/shared) and from C++ (glsl/shared/snapshot_interface.h);
// the #ifdef bridge maps the GLSL vocabulary onto glm so both sides read the same declarations.
// Layout: push constants and storage buffers use std430 offsets; keep every member 16-byte
// aligned or a scalar after vec4s, and check sizes with the static_asserts below.
#ifndef AAMAP_SNAPSHOT_INTERFACE_H
#define AAMAP_SNAPSHOT_INTERFACE_H

#ifdef __cplusplus
#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
namespace aamap::gpu {
using vec4 = glm::vec4;
using ivec2 = glm::ivec2;
using mat4 = glm::mat4;
using uint = std::uint32_t;
#endif

// --- G-buffer raster (gbuffer.vert / gbuffer.frag) --------------------------------------------
// Lights live in a uniform buffer: storage-buffer loads with a loop index are scalarised per
// lane on lavapipe and made the raster 7x slower. Materials travel with the vertices (flat).
#define GBUFFER_BINDING_LIGHTS 0     // uniform GpuLights
#define GBUFFER_MAX_LIGHTS 256       // 12 KiB: within the 16 KiB every device allows for a UBO
#define GBUFFER_LOCATION_POSITION 0  // vec3
#define GBUFFER_LOCATION_NORMAL 1    // vec3
#define GBUFFER_LOCATION_KD 2        // vec3, diffuse albedo of the vertex's triangle
#define GBUFFER_LOCATION_KE 3        // vec3, emitted radiance of the vertex's triangle
// Only in the shadowed variant (gbuffer.shadowed.frag): without shadows there is no binding 1.
#define GBUFFER_BINDING_SHADOW 1     // texture2DArray (depth), 6 layers per light, SHADOW_* below

struct GpuLight {
    vec4 position;   // xyz
    vec4 intensity;  // rgb, W/sr
    vec4 normal;     // xyz: lobe axis (unit), or 0 for an isotropic light
};

struct GBufferPush {
    mat4 viewProj;   // world -> Vulkan clip space
    vec4 cameraPos;  // xyz
    uint lightCount;
    uint shadowPcf;  // PCF kernel side in texels (1: one tap)
    uint pad1, pad2;
    vec4 shadow;     // x: cube-map near plane, y: depth bias, z: slope bias (texels), w: face size
};

// --- Shadow cube maps (shadow_cube.vert / .frag) ----------------------------------------------
// One D32 2D-array image: light i owns layers 6i..6i+5 in the face order of Vulkan cube maps
// (+X -X +Y -Y +Z -Z). A face stores near / ma, ma the distance along the face's axis (reversed,
// infinite-far projection: clear 0, nearer wins); the receiver turns it back into a distance.
#define SHADOW_BINDING_LIGHTS 0     // uniform GpuLights, the G-buffer's light buffer
#define SHADOW_LOCATION_POSITION 0  // vec3, the G-buffer's vertex buffer (position only)

struct ShadowPush {
    float nearPlane;  // geometry nearer to the light than this along the face axis casts no shadow
    uint pad0, pad1, pad2;
};

// --- Filter chain (luminance / laplacian / blur / reduce .comp) -------------------------------
#define FILTER_BINDING_INPUT 0   // storage image, read
#define FILTER_BINDING_OUTPUT 1  // storage image, written (r32f)

struct FilterPush {
    ivec2 inSize;    // input image size
    ivec2 outSize;   // output image size (reduce; equal to inSize elsewhere)
    float exposure;  // luminance
    int radius;      // blur radius
    float noiseFloor;
    float gain;
};

#ifdef __cplusplus
static_assert(sizeof(GpuLight) == 48);
static_assert(sizeof(GBufferPush) == 112);
static_assert(sizeof(ShadowPush) == 16);
static_assert(sizeof(FilterPush) == 32);
}  // namespace aamap::gpu
#endif

#endif
