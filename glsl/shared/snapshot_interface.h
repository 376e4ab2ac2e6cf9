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
#define GBUFFER_MAX_LIGHTS 256       // 16 KiB: exactly the UBO range every device allows
#define GBUFFER_LOCATION_POSITION 0  // vec3
#define GBUFFER_LOCATION_NORMAL 1    // vec3
#define GBUFFER_LOCATION_KD 2        // vec3, diffuse albedo of the vertex's triangle
#define GBUFFER_LOCATION_KE 3        // vec3, emitted radiance of the vertex's triangle
#define GBUFFER_LOCATION_SPECULAR 7  // vec4: Phong: ks and exponent ns (ks 0: no glossy lobe); a microfacet
                                     // lobe: specular_reflectance (tint) and 0
// The glossy lobe of Mitsuba's rough conductor and rough plastic (tracer/bsdf.h), as 16-bit
// floats (passes/scene_gpu.cpp packs a GpuLobe into them): the Snapshot evaluates the tracer's
// microfacet lobes for its light samples.
#define GBUFFER_LOCATION_LOBE 8      // vec4: GBUFFER_LOBE_* model, alpha_u, alpha_v, distribution (0 Beckmann, 1 GGX)
#define GBUFFER_LOCATION_LOBE_ETA 9  // vec4: conductor eta (rgb); w: plastic's coating index (int_ior / ext_ior)
#define GBUFFER_LOCATION_LOBE_K 10   // vec4: conductor k (rgb)
#define GBUFFER_LOBE_PHONG 0         // the Phong lobe of GBUFFER_LOCATION_SPECULAR (or none)
#define GBUFFER_LOBE_CONDUCTOR 1     // F D G / (4 cos_o cos_i), F of the complex index eta + i k
#define GBUFFER_LOBE_PLASTIC 2       // the coating's F D G / (4 cos_o cos_i) over the base, kd (T(cos_o) T(cos_i))
#ifdef __cplusplus
// The lobe's parameters in one place: a material's model, roughness, distribution and indices.
struct GpuLobe {
    float model = GBUFFER_LOBE_PHONG, alphaU = 0.0f, alphaV = 0.0f, distribution = 0.0f;
    glm::vec4 eta{0.0f};  // rgb, ior in w
    glm::vec4 k{0.0f};
};
#endif
// Only in the shadowed variant (gbuffer.shadowed.frag): without shadows there is no binding 1.
#define GBUFFER_BINDING_SHADOW 1     // texture2DArray (depth), 6 layers per light, SHADOW_* below
// Only in the textured variants (gbuffer.textured*.{vert,frag}, passes/gbuffer_textures.h): the
// vertex also carries uv and its material's atlas entry, and the atlas follows the other bindings.
#define GBUFFER_LOCATION_UV 4         // vec2
#define GBUFFER_LOCATION_TEX_RECT 5   // uvec4 (16-bit): atlas entry x, y, width, height; width 0: none
#define GBUFFER_LOCATION_TEX_PARAMS 6 // vec2: atlas layer, alpha threshold (discard if a < it)
#define GBUFFER_BINDING_ATLAS_UNSHADOWED 1  // texture2DArray, RGBA8 sRGB
// The colour lookup's most probes along a footprint (core/texture_filter.h, kMaxTextureAnisotropy).
#define TEXTURE_MAX_ANISOTROPY 16
#define GBUFFER_BINDING_ATLAS_SHADOWED 2

// A directional light (LIGHT_KIND_DIRECTIONAL, cone.z = 2) reuses the fields: intensity holds its
// irradiance (W/m^2), normal the unit direction towards it, position the centre and cone.x the
// radius of the sphere its orthographic shadow map covers (the scene's bounds): layer 6i of the
// shadow array holds that map, layers 6i+1..6i+5 stay empty.
struct GpuLight {
    vec4 position;   // xyz; w: the side of its shadow cube faces in texels (shadow maps by need,
                     // passes/view_budget.h), drawn in the layers' top-left corner
    vec4 intensity;  // rgb, W/sr
    vec4 normal;     // xyz: lobe or spot-cone axis (unit), or 0 for an isotropic light
    vec4 cone;       // x: cos inner, y: cos outer half-angle; z: 1 for a spot (axis in normal), else 0;
                     // w: half the side of the patch of an area light that this point sample stands
                     // for (a square of area A / samples), 0 for a true point: its soft-shadow size
};
#define LIGHT_CONE_DIRECTIONAL 2.0  // GpuLight::cone.z of a directional light

// Specialisation constants of the lit fragment shaders (gbuffer*.frag, geometry_buffer.shadowed*
// .frag; glsl/lights.glsl): the light list's length and kinds, the PCF side, whether some light
// is a patch of an area light (soft shadows, glsl/shadow_visibility.glsl) and the first
// LIGHTING_INLINE_LIGHTS lights themselves are fixed per pipeline. So the code of absent light
// kinds and of the other PCF path is dropped (lavapipe's SIMD lanes run both sides of every
// branch), and those lights cost no uniform loads (lavapipe gathers every uniform load lane by
// lane, constant offset or not); docs/results.md has the G-buffer's time with and without them.
// Values in this order.
#define LIGHTING_SPEC_LIGHT_COUNT 0  // uint: lights[0 .. count)
#define LIGHTING_SPEC_SHADOW_PCF 1   // uint: PCF kernel side in texels (1: one tap)
#define LIGHTING_SPEC_LIGHT_KINDS 2  // uint: the LIGHT_KIND_* bits of the kinds in the list
#define LIGHTING_SPEC_SOFT_SHADOWS 3 // uint: 1 if some light has a patch (GpuLight::cone.w > 0)
// Then light k < LIGHTING_INLINE_LIGHTS as floats from LIGHTING_SPEC_LIGHT_DATA + 14 k: position
// xyz, intensity rgb, normal xyz, cone xyzw (GpuLight's fields in order, the other w dropped),
// then position.w (the shadow face size); zeros past the list. Lights from
// LIGHTING_INLINE_LIGHTS on are read from the uniform buffer.
#define LIGHTING_SPEC_LIGHT_DATA 4
#define LIGHTING_SPEC_FLOATS_PER_LIGHT 14
#define LIGHTING_INLINE_LIGHTS 8  // = the APPLY list of FOR_EACH_INLINE_LIGHT (glsl/lights.glsl)
#define LIGHT_KIND_ISOTROPIC 1u      // GpuLight::normal is 0
#define LIGHT_KIND_LOBE 2u           // cosine lobe about GpuLight::normal (area-light samples)
#define LIGHT_KIND_SPOT 4u           // spot cone about GpuLight::normal (GpuLight::cone.z = 1)
#define LIGHT_KIND_DIRECTIONAL 8u    // at infinity along GpuLight::normal (cone.z = 2), orthographic shadow map
// The environment's ambient term (passes/environment_lighting.h): a uint flag (0: none, the code
// folds away), then its 9 order-2 SH irradiance coefficients as 27 floats (rgb of Y_0..Y_8), so
// that E(n) = sum_i c_i Y_i(n). After the inline lights.
#define LIGHTING_SPEC_AMBIENT (LIGHTING_SPEC_LIGHT_DATA + LIGHTING_SPEC_FLOATS_PER_LIGHT * LIGHTING_INLINE_LIGHTS)
#define LIGHTING_SPEC_AMBIENT_SH (LIGHTING_SPEC_AMBIENT + 1)
// uint: 1 if some drawn material has a microfacet lobe (GpuLobe); 0 folds the lobe's code away,
// which lavapipe would otherwise run for every light and pixel (both sides of the branch).
#define LIGHTING_SPEC_MICROFACET (LIGHTING_SPEC_AMBIENT_SH + 27)
#define LIGHTING_SPEC_COUNT (LIGHTING_SPEC_MICROFACET + 1)

struct GBufferPush {
    mat4 viewProj;   // world -> Vulkan clip space
    vec4 cameraPos;  // xyz
    uint mirrorLayer;  // mirror variants (GBUFFER_MIRROR): the layer of mirror.colour to draw into
    float exposure;    // grey variants (GBUFFER_GREY): as FilterPush::exposure
    uint pad1, pad2;
    vec4 shadow;     // x: cube-map near plane, y: depth bias, z: slope bias (texels), w: the layers'
                     // size (each light's faces: GpuLight::position.w)
    vec4 clipPlane;  // mirror variants: keep dot(xyz, p) >= w, the mirror's side of its plane
};

// --- Planar mirrors (passes/mirror.h) --------------------------------------------------------
// mirror.colour: the scene seen in each mirror (gbuffer.mirror*: the G-buffer with the reflected
// view and a clip plane, one layer per mirror). mirror_mask: the mirror triangles from the camera
// write (reflectance, layer + 1) where they are the visible surface. mirror_composite adds
// reflectance x reflected colour into the snapshot.
#define MIRROR_MASK_LOCATION_POSITION 0     // vec3
#define MIRROR_MASK_LOCATION_REFLECTANCE 1  // vec3
#define MIRROR_MASK_LOCATION_LAYER 2        // float
#define MIRROR_MASK_BINDING_DEPTH 0         // texture2D, the camera's depth (reversed)
#define MIRROR_COMPOSITE_BINDING_SNAPSHOT 0  // rgba32f storage image, read and written
#define MIRROR_COMPOSITE_BINDING_MASK 1      // rgba32f storage image, read
#define MIRROR_COMPOSITE_BINDING_COLOUR 2    // texture2DArray, mirror.colour
#define MIRROR_COMPOSITE_GROUP 8

struct MirrorMaskPush {
    mat4 viewProj;  // the camera's (reversed depth), as the G-buffer's
};

// Environment probes of curved mirrors (passes/mirror_probes.h): mirror.probes renders the
// G-buffer into 6 cube faces per probe (layers 6i..6i+5, the shadow maps' face order and
// coordinates, shadow_cube.glsl); mirror_probe.* then draws the curved mirror triangles from the
// camera and adds reflectance x the probe's colour in the reflected direction where they are the
// visible surface.
#define MIRROR_PROBE_LOCATION_POSITION 0     // vec3
#define MIRROR_PROBE_LOCATION_NORMAL 1       // vec3
#define MIRROR_PROBE_LOCATION_REFLECTANCE 2  // vec3
#define MIRROR_PROBE_LOCATION_LAYER 3        // float: the probe's first layer (6 x its index)
#define MIRROR_PROBE_BINDING_DEPTH 0         // texture2D, the camera's depth (reversed)
#define MIRROR_PROBE_BINDING_COLOUR 1        // texture2DArray, mirror.probes.colour

struct MirrorProbePush {
    mat4 viewProj;   // the camera's (reversed depth), as the G-buffer's
    vec4 cameraPos;  // xyz: the eye; w: the probes' face size in texels
};

struct MirrorCompositePush {
    ivec2 size;
    ivec2 pad;
};

// --- Shadow cube maps (shadow_cube.vert / .frag) ----------------------------------------------
// One D32 2D-array image: light i owns layers 6i..6i+5 in the face order of Vulkan cube maps
// (+X -X +Y -Y +Z -Z). A face stores near / ma, ma the distance along the face's axis (reversed,
// infinite-far projection: clear 0, nearer wins); the receiver turns it back into a distance.
#define SHADOW_BINDING_LIGHTS 0     // uniform GpuLights, the G-buffer's light buffer
#define SHADOW_LOCATION_POSITION 0  // vec3, the G-buffer's vertex buffer (position only)
// The masked variant (shadow_cube.masked.*: a scene with alpha-tested textures) also reads the
// G-buffer's uv and atlas entry and discards cut-out texels, so cut-outs cast cut-out shadows.
#define SHADOW_LOCATION_UV 1          // = GBUFFER_LOCATION_UV's data
#define SHADOW_LOCATION_TEX_RECT 2
#define SHADOW_LOCATION_TEX_PARAMS 3
#define SHADOW_BINDING_ATLAS 1        // texture2DArray, the G-buffer's atlas

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
    float noiseFloor;  // blur
    float gain;        // blur
    float flatRange;   // laplacian: the flat gate (aamap_filter.h step 2)
};
// The blur's radius is a specialisation constant (a pipeline per radius), so that its loops
// unroll (lavapipe runs a loop bounded by a push constant several times slower; docs/results.md).
#define FILTER_SPEC_BLUR_RADIUS 0  // int, >= 0

// --- Block sums (block_sum_rows.comp / block_sum_columns.comp) -------------------------------
// Summed-area tables of the aamap for adaptive subsampling (tracer/block_sums.h has the layout):
// rows: the aamap (storage image) -> per-row prefixes, (W + 1) x H; columns: prefixes of those
// down each of the W + 1 columns -> the (W + 1) x (H + 1) tables. Sums are float-float (hi, lo).
#define BLOCKSUM_ROWS_BINDING_MAP 0         // r32f storage image, read
#define BLOCKSUM_ROWS_BINDING_SUMS 1        // vec2 row prefixes, written
#define BLOCKSUM_ROWS_BINDING_COUNTS 2      // uint row counts, written
#define BLOCKSUM_COLUMNS_BINDING_ROW_SUMS 0    // vec2 row prefixes, read
#define BLOCKSUM_COLUMNS_BINDING_ROW_COUNTS 1  // uint row counts, read
#define BLOCKSUM_COLUMNS_BINDING_SUMS 2        // vec2 table, written
#define BLOCKSUM_COLUMNS_BINDING_COUNTS 3      // uint table, written
#define BLOCKSUM_GROUP 64               // invocations per workgroup (one per row or column)

struct BlockSumPush {
    ivec2 size;  // aamap width, height
    ivec2 pad;
};

// --- Geometric aamap (geometry_buffer.vert/.frag, geometric_edges[.combined].comp) ------------
// Draws the G-buffer's vertex buffer (its layout, plain or textured) with the object and material
// id of each drawn triangle in a storage buffer, into two RGBA32F colour attachments; variants
// as the G-buffer's: .textured (alpha test on the G-buffer's atlas), .shadowed (the occlusion
// mask from the shadow cube maps). The edge rule is glsl/shared/geometric_edges.h.
#define GEOMETRY_LOCATION_POSITION 0    // vec3, G-buffer vertex offset 0
#define GEOMETRY_LOCATION_NORMAL 1      // vec3, offset 12
#define GEOMETRY_LOCATION_UV 2          // textured: vec2 at GBufferPass::kUvOffset
#define GEOMETRY_LOCATION_TEX_RECT 3    // textured: uvec4 (u16) at kTexRectOffset
#define GEOMETRY_LOCATION_TEX_PARAMS 4  // textured: vec2 at kTexParamsOffset
#define GEOMETRY_BINDING_IDS 0          // storage buffer, uvec2 (object, material) per drawn triangle
#define GEOMETRY_BINDING_LIGHTS 1       // shadowed: uniform GpuLights, the G-buffer's light buffer
#define GEOMETRY_BINDING_SHADOW 2       // shadowed: texture2DArray, the shadow cube maps
#define GEOMETRY_BINDING_ATLAS_UNSHADOWED 1  // textured: texture2DArray, the G-buffer's atlas
#define GEOMETRY_BINDING_ATLAS_SHADOWED 3
#define GEOMETRIC_BINDING_NORMAL_DEPTH 0  // rgba32f storage image, read
#define GEOMETRIC_BINDING_IDS 1           // rgba32f storage image, read
#define GEOMETRIC_BINDING_OUTPUT 2        // r32f storage image, written
#define GEOMETRIC_BINDING_LAPLACIAN 3     // r32f storage image, read (combined variant only)

struct GeometryPush {
    mat4 viewProj;       // world -> Vulkan clip space (reversed depth, as the G-buffer)
    vec4 cameraPos;      // xyz
    vec4 cameraForward;  // xyz, unit: view depth = dot(p - cameraPos, forward)
    vec4 shadow;         // shadowed: as GBufferPush::shadow (light count and PCF: LIGHTING_SPEC_*)
};

// --- Sub-pixel aamap (subpixel_map.comp; the predictor: glsl/shared/subpixel_map.h) -------------
struct SubpixelPush {
    ivec2 outSize;    // render resolution W x H; the inputs are k W x k H
    int k;            // samples per pixel side (also the pipeline's SUBPIXEL_SPEC_K; checked equal)
    float exposure;   // the display transform's, as FilterPush::exposure
    float tolerance;  // tau: display-value error at the FLIP threshold
    uint pad0, pad1, pad2;
};

#ifdef __cplusplus
static_assert(sizeof(GeometryPush) == 112);
static_assert(sizeof(SubpixelPush) == 32);
static_assert(sizeof(BlockSumPush) == 16);
static_assert(sizeof(GpuLight) == 64);
static_assert(sizeof(GpuLight) * GBUFFER_MAX_LIGHTS <= 16384);  // maxUniformBufferRange's minimum
static_assert(sizeof(GBufferPush) == 128);  // maxPushConstantsSize's minimum
static_assert(sizeof(ShadowPush) == 16);
static_assert(sizeof(MirrorMaskPush) == 64);
static_assert(sizeof(MirrorCompositePush) == 16);
static_assert(sizeof(MirrorProbePush) == 80);
static_assert(sizeof(FilterPush) == 32);
}  // namespace aamap::gpu
#endif

#endif
