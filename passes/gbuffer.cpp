#include "passes/gbuffer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

#include <aamap/spirv.h>
#include <fmt/format.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/image_io.h"
#include "engine/vk/context.h"
#include "glsl/shared/aamap_filter.h"
#include "glsl/shared/snapshot_interface.h"
#include "passes/gbuffer_textures.h"
#include "passes/mirror.h"

namespace aamap::passes {
namespace {

// The mesh is drawn unindexed so that each vertex carries its triangle's material (flat
// attributes: no per-fragment buffer lookups, and no gl_PrimitiveID, which fragment shaders may
// only read with the geometry-shader feature).
struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec3 kd;
    glm::vec3 ke;
};
static_assert(sizeof(Vertex) == GBufferPass::kVertexStride);

// The textured layout: the material's atlas entry travels with the vertex too (flat), as kd does.
struct TexturedVertex {
    Vertex base;
    glm::vec2 uv;
    std::uint16_t rect[4];  // atlas entry x, y, width, height; width 0: samples nothing
    glm::vec2 params;       // atlas layer, alpha threshold (discard where coverage < it)
};
static_assert(sizeof(TexturedVertex) == GBufferPass::kTexturedVertexStride);
static_assert(offsetof(TexturedVertex, uv) == GBufferPass::kUvOffset);
static_assert(offsetof(TexturedVertex, rect) == GBufferPass::kTexRectOffset);
static_assert(offsetof(TexturedVertex, params) == GBufferPass::kTexParamsOffset);

// How one material samples the atlas and tests alpha.
struct MaterialSampling {
    glm::vec3 kd{0.0f};    // mirrors: the diffuse part the tracer keeps (passes/mirror.h)
    bool dropped = false;  // constant coverage below the cutoff: the triangles are never seen
    TexturedVertex fields{};  // rect and params (uv and base filled per vertex)
};

MaterialSampling sampling(const Material& m, const Scene& scene, const TextureAtlas& atlas) {
    MaterialSampling out;
    out.kd = m.kd;
    if (m.kind == MaterialKind::Mirror) {
        glm::vec3 reflectance;
        mirrorAlbedos(m, out.kd, reflectance);
    }
    const auto key = atlasKey(m, scene);
    const auto entry = atlas.entries.find(key);
    const bool sampled = entry != atlas.entries.end();
    // The tracer's rule (tracer/embree_scene.cpp): cut where alpha * coverage < cutoff, i.e.
    // coverage < cutoff / alpha; with no coverage texture the whole material is in or out.
    const bool coverageTexture = sampled && isAlphaTested(m) && key.second == m.alphaTexture && m.alphaTexture >= 0;
    float threshold = 0.0f;
    if (isAlphaTested(m)) {
        const float cutoff = effectiveAlphaCutoff(m);
        if (!coverageTexture || m.alpha <= 0.0f) out.dropped = m.alpha < cutoff;
        else threshold = cutoff / m.alpha;
    }
    if (sampled) {
        const AtlasEntry& e = entry->second;
        out.fields.rect[0] = static_cast<std::uint16_t>(e.x);
        out.fields.rect[1] = static_cast<std::uint16_t>(e.y);
        out.fields.rect[2] = static_cast<std::uint16_t>(e.width);
        out.fields.rect[3] = static_cast<std::uint16_t>(e.height);
        out.fields.params = {static_cast<float>(e.layer), threshold};
    }
    return out;
}

// Unindexed vertices in the plain or the textured layout, as bytes: the triangles the camera sees
// first, then the glass ones, which only cast shadows (GBufferPass, "Glass"). `drawn` gets the
// mesh triangle of each triangle in that order.
struct FlatMesh {
    std::vector<std::byte> bytes;
    std::vector<std::uint32_t> drawn;
    std::uint32_t cameraVertices = 0, allVertices = 0;
    bool alphaMasked = false;
};

FlatMesh flatten(const Scene& scene, const TextureAtlas& atlas, bool textured) {
    const TriangleMesh& mesh = scene.mesh;
    const std::vector<Material>& materials = scene.materials;
    const Material fallback;  // for ids past the material list
    std::vector<MaterialSampling> perMaterial;
    for (const Material& m : materials) perMaterial.push_back(sampling(m, scene, atlas));
    const MaterialSampling fallbackSampling;
    const std::size_t stride = textured ? sizeof(TexturedVertex) : sizeof(Vertex);
    FlatMesh flat;
    std::vector<std::byte>& out = flat.bytes;
    out.reserve(mesh.triangles.size() * 3 * stride);
    const bool hasNormals = mesh.normals.size() == mesh.positions.size();
    const bool hasUvs = !mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size();
    const auto isGlass = [&](std::size_t t) {
        const std::uint32_t id = t < mesh.materialIds.size() ? mesh.materialIds[t] : 0u;
        return id < materials.size() && materials[id].kind == MaterialKind::Glass;
    };
    std::vector<std::uint32_t> order;  // camera triangles, then glass, each in mesh order
    order.reserve(mesh.triangles.size());
    for (int glassPass = 0; glassPass < 2; ++glassPass)
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            if (isGlass(t) == (glassPass == 1)) order.push_back(static_cast<std::uint32_t>(t));
    for (const std::uint32_t t : order) {
        const glm::uvec3 tri = mesh.triangles[t];
        const glm::vec3 p[3] = {mesh.positions[tri.x], mesh.positions[tri.y], mesh.positions[tri.z]};
        const glm::vec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float len = glm::length(cross);
        const glm::vec3 face = len > 0.0f ? cross / len : glm::vec3(0, 0, 1);
        const std::uint32_t id = t < mesh.materialIds.size() ? mesh.materialIds[t] : 0u;
        const Material& m = id < materials.size() ? materials[id] : fallback;
        const MaterialSampling& ms = id < materials.size() ? perMaterial[id] : fallbackSampling;
        if (ms.dropped) continue;
        flat.alphaMasked |= ms.fields.params.y > 0.0f;
        flat.drawn.push_back(t);
        if (!isGlass(t)) flat.cameraVertices += 3;
        for (int k = 0; k < 3; ++k) {
            glm::vec3 n = hasNormals ? mesh.normals[tri[k]] : face;
            if (!(glm::dot(n, n) > 0.0f)) n = face;  // zero or NaN normals in the file
            TexturedVertex v = ms.fields;
            v.base = {p[k], n, id < materials.size() ? ms.kd : m.kd, m.ke};
            v.uv = hasUvs ? mesh.uvs[tri[k]] : glm::vec2(0.0f);
            const auto* bytes = reinterpret_cast<const std::byte*>(&v);
            out.insert(out.end(), bytes, bytes + stride);
            ++flat.allVertices;
        }
    }
    return flat;
}

// The atlas as a sampled RGBA8 sRGB array image, uploaded once, read by the fragment shader.
vk::Image uploadAtlas(VulkanContext& context, const TextureAtlas& atlas) {
    vk::ImageInfo info;
    info.format = VK_FORMAT_R8G8B8A8_SRGB;
    info.width = info.height = atlas.pageSide;
    info.layers = atlas.layers;
    return vk::uploadImage(context, info, std::as_bytes(std::span<const std::uint32_t>(atlas.texels)),
                           VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
}

template <class T>
std::span<const std::byte> bytesOf(const std::vector<T>& v) {
    return std::as_bytes(std::span<const T>(v));
}

// Bit-equal positions merged, in first-seen order; index[i] is vertex i's entry.
struct SharedPositions {
    std::vector<glm::vec3> distinct;
    std::vector<std::uint32_t> index;
};

struct PositionBitsHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
        std::uint64_t h = 0x9E3779B97F4A7C15ull;
        for (std::uint32_t v : k) h = (h ^ v) * 0x100000001B3ull;
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

SharedPositions sharePositions(std::span<const glm::vec3> positions) {
    SharedPositions out;
    std::unordered_map<std::array<std::uint32_t, 3>, std::uint32_t, PositionBitsHash> seen;
    seen.reserve(positions.size() / 2);
    out.index.reserve(positions.size());
    for (const glm::vec3& p : positions) {
        std::array<std::uint32_t, 3> key;
        std::memcpy(key.data(), &p, sizeof(key));
        const auto [it, added] = seen.try_emplace(key, static_cast<std::uint32_t>(out.distinct.size()));
        if (added) out.distinct.push_back(p);
        out.index.push_back(it->second);
    }
    return out;
}

// The pre-pass: positions in, depth out, no fragment work (the empty depth-only shader).
vk::Pipeline makeDepthPipeline(VulkanContext& context) {
    vk::GraphicsDesc desc;
    desc.vertexSpirv = spirv::gbuffer_depth_vert;
    desc.fragmentSpirv = spirv::shadow_cube_frag;
    desc.vertexInput.stride = sizeof(glm::vec3);
    desc.vertexInput.attributes = {{GBUFFER_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
    desc.depthFormat = vk::toVkFormat(GBufferPass::kDepthFormat);
    desc.depthCompare = VK_COMPARE_OP_GREATER;  // reversed depth
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{{}, static_cast<std::uint32_t>(sizeof(gpu::GBufferPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT});
}

vk::Pipeline makePipeline(VulkanContext& context, bool shadowed, bool textured, bool mirrored, bool grey,
                          bool afterPrepass, std::vector<std::uint32_t> lightingConstants) {
    vk::GraphicsDesc desc;
    desc.fragmentConstants = std::move(lightingConstants);
    if (grey) {  // the camera's view only (passes/gbuffer.h, GBufferGrey)
        desc.vertexSpirv = textured ? spirv::gbuffer_textured_vert : spirv::gbuffer_vert;
        desc.fragmentSpirv = textured ? (shadowed ? spirv::gbuffer_textured_shadowed_grey_frag
                                                  : spirv::gbuffer_textured_grey_frag)
                                      : (shadowed ? spirv::gbuffer_shadowed_grey_frag : spirv::gbuffer_grey_frag);
    } else if (mirrored) {
        desc.vertexSpirv = textured ? spirv::gbuffer_mirror_textured_vert : spirv::gbuffer_mirror_vert;
        desc.fragmentSpirv = textured ? (shadowed ? spirv::gbuffer_mirror_textured_shadowed_frag
                                                  : spirv::gbuffer_mirror_textured_frag)
                                      : (shadowed ? spirv::gbuffer_mirror_shadowed_frag : spirv::gbuffer_mirror_frag);
    } else {
        desc.vertexSpirv = textured ? spirv::gbuffer_textured_vert : spirv::gbuffer_vert;
        desc.fragmentSpirv = textured ? (shadowed ? spirv::gbuffer_textured_shadowed_frag : spirv::gbuffer_textured_frag)
                                      : (shadowed ? spirv::gbuffer_shadowed_frag : spirv::gbuffer_frag);
    }
    desc.vertexInput.stride = textured ? sizeof(TexturedVertex) : sizeof(Vertex);
    desc.vertexInput.attributes = {
        {GBUFFER_LOCATION_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
        {GBUFFER_LOCATION_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
        {GBUFFER_LOCATION_KD, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, kd)},
        {GBUFFER_LOCATION_KE, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, ke)},
    };
    if (textured) {
        desc.vertexInput.attributes.push_back({GBUFFER_LOCATION_UV, 0, VK_FORMAT_R32G32_SFLOAT, GBufferPass::kUvOffset});
        desc.vertexInput.attributes.push_back(
            {GBUFFER_LOCATION_TEX_RECT, 0, VK_FORMAT_R16G16B16A16_UINT, GBufferPass::kTexRectOffset});
        desc.vertexInput.attributes.push_back(
            {GBUFFER_LOCATION_TEX_PARAMS, 0, VK_FORMAT_R32G32_SFLOAT, GBufferPass::kTexParamsOffset});
    }
    desc.colorFormats = {vk::toVkFormat(GBufferPass::kColourFormat)};
    if (grey) desc.colorFormats.push_back(vk::toVkFormat(GBufferPass::kGreyFormat));
    desc.depthFormat = vk::toVkFormat(GBufferPass::kDepthFormat);
    // Reversed depth; after the pre-pass the nearest surface's own depth passes.
    desc.depthCompare = afterPrepass ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_GREATER;
    std::vector<VkDescriptorType> bindings{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER};  // GBUFFER_BINDING_LIGHTS
    static_assert(GBUFFER_BINDING_LIGHTS == 0 && GBUFFER_BINDING_SHADOW == 1);
    if (shadowed) bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);  // texelFetch only: no sampler
    static_assert(GBUFFER_BINDING_ATLAS_UNSHADOWED == 1 && GBUFFER_BINDING_ATLAS_SHADOWED == 2);
    if (textured) bindings.push_back(VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE);  // the atlas, after the shadow maps
    return vk::Pipeline(context, desc,
                        vk::LayoutDesc{bindings, static_cast<std::uint32_t>(sizeof(gpu::GBufferPush)),
                                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT});
}

}  // namespace

GBufferPass::GBufferPass(VulkanContext& context, const Scene& scene) : context_(&context) {
    const TextureAtlas atlas = buildTextureAtlas(scene);
    textured_ = !atlas.empty();
    atlasEntries_ = static_cast<std::uint32_t>(atlas.entries.size());
    if (textured_) atlas_ = uploadAtlas(context, atlas);
    FlatMesh flat = flatten(scene, atlas, textured_);
    alphaMasked_ = flat.alphaMasked;
    vertexCount_ = flat.cameraVertices;
    occluderVertexCount_ = flat.allVertices;
    drawnTriangles_ = std::move(flat.drawn);
    const std::vector<std::byte>& vertices = flat.bytes;
    if (!vertices.empty())
        vertices_ = vk::uploadBuffer(context, vertices, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    positions_.resize(occluderVertexCount_);
    for (std::uint32_t i = 0; i < occluderVertexCount_; ++i)
        std::memcpy(&positions_[i], vertices.data() + static_cast<std::size_t>(i) * vertexStride(), sizeof(glm::vec3));
    if (!alphaMasked_ && occluderVertexCount_ > 0) {
        SharedPositions shared = sharePositions(positions_);
        sharedPositions_ = vk::uploadBuffer(context, bytesOf(shared.distinct), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        positionIndices_ = vk::uploadBuffer(context, bytesOf(shared.index), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
        positionIndex_ = std::move(shared.index);
    }
    if (sharedPositions() && vertexCount_ > 0) {  // the camera's depth pre-pass and tie order
        std::vector<std::uint32_t> reversed(vertexCount_);
        for (std::uint32_t v = 0; v < vertexCount_; ++v) reversed[v] = vertexCount_ - 3 * (v / 3 + 1) + v % 3;
        reversedTriangles_ = vk::uploadBuffer(context, bytesOf(reversed), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
        depthPipeline_ = makeDepthPipeline(context);
    }
    if (!positions_.empty()) {
        glm::vec3 lo = positions_.front(), hi = positions_.front();
        for (const glm::vec3& p : positions_) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        coverCentre_ = 0.5f * (lo + hi);
        // 1% slack: vertices on the sphere stay inside the map and its depth range.
        coverRadius_ = std::max(0.505f * glm::length(hi - lo), 1e-6f * std::max(glm::length(coverCentre_), 1.0f));
    }
    setLights({});
}

void GBufferPass::setLights(std::span<const PointLight> lights, std::span<const DirectionalLight> directionals,
                            const std::array<glm::vec3, 9>* ambientSH) {
    std::vector<gpu::GpuLight> gpuLights;
    for (const PointLight& l : lights) {
        // A lobe wins over a spot cone, as in the tracer (tracer/lights.cpp).
        const bool spot = glm::dot(l.normal, l.normal) == 0.0f && glm::dot(l.spotDirection, l.spotDirection) > 0.0f;
        gpuLights.push_back({glm::vec4(l.position, 1.0f), glm::vec4(l.intensity, 0.0f),
                             glm::vec4(spot ? glm::normalize(l.spotDirection) : l.normal, 0.0f),
                             glm::vec4(l.cosInner, std::min(l.cosOuter, l.cosInner), spot ? 1.0f : 0.0f, 0.0f)});
    }
    for (const DirectionalLight& d : directionals) {
        const float len = glm::length(d.direction);
        if (!(len > 0.0f)) continue;
        gpuLights.push_back({glm::vec4(coverCentre_, 1.0f), glm::vec4(d.irradiance, 0.0f),
                             glm::vec4(-d.direction / len, 0.0f),
                             glm::vec4(coverRadius_, 0.0f, LIGHT_CONE_DIRECTIONAL, 0.0f)});
    }
    if (gpuLights.size() > GBUFFER_MAX_LIGHTS)
        throw std::invalid_argument(fmt::format("the Snapshot raster takes at most {} lights, the scene gives {} "
                                                "(point lights plus areaLightSamples per area light, plus directional "
                                                "lights)",
                                                GBUFFER_MAX_LIGHTS, gpuLights.size()));
    ambient_ = ambientSH != nullptr;
    ambientSH_ = ambient_ ? *ambientSH : std::array<glm::vec3, 9>{};
    lightCount_ = static_cast<std::uint32_t>(gpuLights.size());
    const std::size_t inlined = std::min<std::size_t>(gpuLights.size(), LIGHTING_INLINE_LIGHTS);
    inlineLights_.assign(gpuLights.begin(), gpuLights.begin() + static_cast<std::ptrdiff_t>(inlined));
    lightKinds_ = 0;
    lightDirectional_.clear();
    for (const gpu::GpuLight& l : gpuLights) {
        lightDirectional_.push_back(l.cone.z == LIGHT_CONE_DIRECTIONAL ? 1 : 0);
        if (l.cone.z == LIGHT_CONE_DIRECTIONAL) lightKinds_ |= LIGHT_KIND_DIRECTIONAL;
        else if (l.cone.z > 0.0f) lightKinds_ |= LIGHT_KIND_SPOT;
        else if (glm::dot(l.normal, l.normal) > 0.0f) lightKinds_ |= LIGHT_KIND_LOBE;
        else lightKinds_ |= LIGHT_KIND_ISOTROPIC;
    }
    lightPositions_.clear();
    for (const gpu::GpuLight& l : gpuLights) lightPositions_.push_back(glm::vec3(l.position));
    ++lightsVersion_;
    // Pipelines specialised for the old list: only recordings made before this call use them, and
    // those must be declared again anyway (the light buffer is replaced below).
    std::erase_if(pipelines_, [&](const auto& entry) { return entry.first.lightsVersion != lightsVersion_; });
    gpuLights.resize(GBUFFER_MAX_LIGHTS);  // the shader declares the whole array
    lights_ = vk::uploadBuffer(*context_, bytesOf(gpuLights), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
}

graph::PassId GBufferPass::add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& colour,
                               const std::string& depth, const PinholeCamera& camera, float nearPlane,
                               float farPlane, const GBufferShadows& shadows, const GBufferGrey& grey) {
    const bool shadowed = !shadows.resource.empty();
    std::vector<graph::Access> accesses{graph::writes(colour, graph::Usage::ColorAttachment),
                                        graph::writes(depth, graph::Usage::DepthAttachment)};
    if (!grey.resource.empty()) accesses.push_back(graph::writes(grey.resource, graph::Usage::ColorAttachment));
    if (shadowed) accesses.push_back(graph::reads(shadows.resource, graph::Usage::Sampled));
    const graph::PassId id = graph.addPass(
        {"gbuffer", graph::QueueKind::Graphics, accesses,
         std::string(shadowed ? "rasterise the scene with local illumination and shadow-map visibility per light"
                              : "rasterise the scene with local illumination") +
             (textured_ ? "; " + atlasSummary() : "") +
             (grey.resource.empty() ? std::string() : "; and the greyscale of the aamap's step 1") +
             (occluderVertexCount_ > vertexCount_
                  ? fmt::format("; {} glass triangles seen through (they only cast shadows)",
                                (occluderVertexCount_ - vertexCount_) / 3)
                  : std::string())});
    const vk::Pipeline& pipeline = pipelineFor(executor, "gbuffer", shadowed, false, !grey.resource.empty(), shadows.pcf);
    gpu::GBufferPush push{};
    push.exposure = grey.exposure;
    push.viewProj = reversedViewProjection(camera.projectionMatrix(nearPlane, farPlane), camera.viewMatrix());
    push.cameraPos = glm::vec4(camera.origin, 1.0f);
    push.shadow = glm::vec4(shadows.nearPlane, shadows.depthBias, shadows.slopeBias,
                            static_cast<float>(shadows.faceSize));
    executor.setRecord("gbuffer", [this, colour, depth, push, &pipeline, shadow = shadows.resource,
                                   grey = grey.resource](vk::PassContext& pc) {
        record(pc, colour, grey, depth, pipeline, shadow, {&push, 1}, hasDepthPrepass());
    });
    return id;
}

std::vector<std::uint32_t> GBufferPass::lightingConstants(std::uint32_t pcf) const {
    std::vector<std::uint32_t> constants(LIGHTING_SPEC_COUNT);
    constants[LIGHTING_SPEC_LIGHT_COUNT] = lightCount_;
    constants[LIGHTING_SPEC_SHADOW_PCF] = std::max(pcf, 1u);
    constants[LIGHTING_SPEC_LIGHT_KINDS] = lightKinds_;
    static_assert(sizeof(gpu::GpuLight) == 4 * sizeof(glm::vec4) && LIGHTING_SPEC_FLOATS_PER_LIGHT == 12);
    for (std::size_t k = 0; k < inlineLights_.size(); ++k) {
        const gpu::GpuLight& l = inlineLights_[k];
        const glm::vec4 fields[4] = {l.position, l.intensity, l.normal, l.cone};
        for (int f = 0; f < 4; ++f)  // xyz of each field, w dropped
            for (int c = 0; c < 3; ++c)
                constants[LIGHTING_SPEC_LIGHT_DATA + LIGHTING_SPEC_FLOATS_PER_LIGHT * k + 3 * f + c] =
                    std::bit_cast<std::uint32_t>(fields[f][c]);
    }
    constants[LIGHTING_SPEC_AMBIENT] = ambient_ ? 1u : 0u;
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c)
            constants[LIGHTING_SPEC_AMBIENT_SH + 3 * i + c] = std::bit_cast<std::uint32_t>(ambientSH_[i][c]);
    return constants;
}

const vk::Pipeline& GBufferPass::pipelineFor(vk::GraphExecutor& executor, const std::string& pass, bool shadowed,
                                             bool mirrored, bool grey, std::uint32_t pcf) {
    const PipelineKey key{shadowed, mirrored, grey, shadowed ? std::max(pcf, 1u) : 1u, lightsVersion_};
    vk::Pipeline& pipeline = pipelines_[key];
    executor.setPrepare(pass, [this, &pipeline, key] {
        if (!pipeline.handle())
            pipeline = makePipeline(*context_, key.shadowed, textured_, key.mirrored, key.grey,
                                    !key.mirrored && hasDepthPrepass(), lightingConstants(key.pcf));
    });
    return pipeline;
}

glm::mat4 GBufferPass::reversedViewProjection(const glm::mat4& projection, const glm::mat4& view) {
    // Reversed depth (z' = w - z, cleared to 0, GREATER wins): float depth then has about uniform
    // relative precision, so a small near plane does not cost z-fighting far away.
    glm::mat4 reverse(1.0f);
    reverse[2][2] = -1.0f;
    reverse[3][2] = 1.0f;
    return reverse * projection * view;
}

graph::PassId GBufferPass::addReflected(graph::RenderGraph& graph, vk::GraphExecutor& executor,
                                        const std::string& pass, const std::string& colour, const std::string& depth,
                                        std::span<const ReflectedView> views, const GBufferShadows& shadows,
                                        std::string purpose) {
    const bool shadowed = !shadows.resource.empty();
    std::vector<graph::Access> accesses{graph::writes(colour, graph::Usage::ColorAttachment),
                                        graph::writes(depth, graph::Usage::DepthAttachment)};
    if (shadowed) accesses.push_back(graph::reads(shadows.resource, graph::Usage::Sampled));
    const graph::PassId id = graph.addPass({pass, graph::QueueKind::Graphics, accesses, std::move(purpose)});
    const vk::Pipeline& pipeline = pipelineFor(executor, pass, shadowed, true, false, shadows.pcf);
    std::vector<gpu::GBufferPush> pushes;
    for (std::size_t i = 0; i < views.size(); ++i) {
        gpu::GBufferPush push{};
        push.viewProj = views[i].viewProj;
        push.cameraPos = glm::vec4(views[i].eye, 1.0f);
        push.mirrorLayer = static_cast<std::uint32_t>(i);
        push.shadow = glm::vec4(shadows.nearPlane, shadows.depthBias, shadows.slopeBias,
                                static_cast<float>(shadows.faceSize));
        push.clipPlane = views[i].clipPlane;
        pushes.push_back(push);
    }
    executor.setRecord(pass, [this, colour, depth, pushes, &pipeline, shadow = shadows.resource](vk::PassContext& pc) {
        record(pc, colour, "", depth, pipeline, shadow, pushes, false);
    });
    return id;
}

void GBufferPass::record(vk::PassContext& pc, const std::string& colour, const std::string& grey,
                         const std::string& depth, const vk::Pipeline& pipeline, const std::string& shadow,
                         std::span<const gpu::GBufferPush> draws, bool prepass) const {
    const vk::Image& target = pc.image(colour);
    const vk::Image& z = pc.image(depth);
    const VkExtent2D extent{target.info().width, target.info().height};
    // The background (black unless the scene has a sky), and its grey as glsl/display_luma.glsl
    // computes it.
    const VkClearColorValue sky{{background_.r, background_.g, background_.b, 0.0f}};
    std::vector<VkRenderingAttachmentInfo> colourInfos{vk::clearedColourAttachment(target.view(), sky)};
    if (!grey.empty()) {
        const float e = draws[0].exposure;
        const float g = static_cast<float>(AAMAP_LUMA_R) * srgbEncode(e * background_.r) +
                        static_cast<float>(AAMAP_LUMA_G) * srgbEncode(e * background_.g) +
                        static_cast<float>(AAMAP_LUMA_B) * srgbEncode(e * background_.b);
        colourInfos.push_back(vk::clearedColourAttachment(pc.image(grey).view(), VkClearColorValue{{g, 0.0f, 0.0f, 0.0f}}));
    }
    VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depthInfo.imageView = z.view();
    depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depthInfo.clearValue.depthStencil = {0.0f, 0};  // reversed depth: 0 is the far plane
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = target.info().layers;  // mirror.colour: one layer per mirror (gl_Layer)
    rendering.colorAttachmentCount = static_cast<std::uint32_t>(colourInfos.size());
    rendering.pColorAttachments = colourInfos.data();
    rendering.pDepthAttachment = &depthInfo;

    VkCommandBuffer cmd = pc.cmd();
    vkCmdBeginRendering(cmd, &rendering);
    vk::setFullViewport(cmd, extent);
    if (vertexCount_ > 0 && prepass) {
        depthPipeline_.bind(cmd);
        depthPipeline_.pushConstants(cmd, draws[0]);
        const VkBuffer vb = sharedPositions_.handle();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(cmd, positionIndices_.handle(), 0, VK_INDEX_TYPE_UINT32);
        vkCmdDrawIndexed(cmd, vertexCount_, 1, 0, 0, 0);
    }
    if (vertexCount_ > 0) {
        pipeline.bind(cmd);
        vk::DescriptorPush descriptors;
        descriptors.uniformBuffer(GBUFFER_BINDING_LIGHTS, lights_.handle());
        if (!shadow.empty())
            descriptors.sampledImage(GBUFFER_BINDING_SHADOW, pc.image(shadow).view(),
                                     VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
        if (textured_)
            descriptors.sampledImage(shadow.empty() ? GBUFFER_BINDING_ATLAS_UNSHADOWED : GBUFFER_BINDING_ATLAS_SHADOWED,
                                     atlas_.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        descriptors.push(*context_, cmd, pipeline);
        const VkBuffer vb = vertices_.handle();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        if (prepass) vkCmdBindIndexBuffer(cmd, reversedTriangles_.handle(), 0, VK_INDEX_TYPE_UINT32);
        for (const gpu::GBufferPush& push : draws) {
            pipeline.pushConstants(cmd, push);
            if (prepass) vkCmdDrawIndexed(cmd, vertexCount_, 1, 0, 0, 0);
            else vkCmdDraw(cmd, vertexCount_, 1, 0, 0);
        }
    }
    vkCmdEndRendering(cmd);
}

std::string GBufferPass::atlasSummary() const {
    if (!textured_) return "no textures: no texture binding";
    return fmt::format("base-colour textures from a {}x{}x{} atlas of {} entr{} (the scene samples textures){}",
                       atlas_.info().width, atlas_.info().height, atlas_.info().layers, atlasEntries_,
                       atlasEntries_ == 1 ? "y" : "ies", alphaMasked_ ? ", with alpha test" : "");
}

}  // namespace aamap::passes

