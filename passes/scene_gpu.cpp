#include "passes/scene_gpu.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

#include "engine/vk/context.h"
#include "passes/gbuffer_textures.h"
#include "passes/mirror.h"
#include "tracer/microfacet.h"

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
    glm::vec4 specular;  // ks, ns: the glossy lobe of a diffuse material (ks 0: none); a microfacet lobe's tint
    std::uint16_t lobe[4], eta[4], k[4];  // GpuLobe as 16-bit floats
};
static_assert(sizeof(Vertex) == SceneGpu::kVertexStride);
static_assert(offsetof(Vertex, lobe) == SceneGpu::kLobeOffset && offsetof(Vertex, eta) == SceneGpu::kLobeEtaOffset &&
              offsetof(Vertex, k) == SceneGpu::kLobeKOffset);

void packHalves(const glm::vec4& v, std::uint16_t out[4]) {
    const glm::u16vec4 h(glm::packHalf1x16(v.x), glm::packHalf1x16(v.y), glm::packHalf1x16(v.z), glm::packHalf1x16(v.w));
    for (int i = 0; i < 4; ++i) out[i] = h[i];
}
static_assert(offsetof(Vertex, normal) == SceneGpu::kNormalOffset && offsetof(Vertex, kd) == SceneGpu::kKdOffset &&
              offsetof(Vertex, ke) == SceneGpu::kKeOffset && offsetof(Vertex, specular) == SceneGpu::kSpecularOffset);

// The textured layout: the material's atlas entry travels with the vertex too (flat), as kd does.
struct TexturedVertex {
    Vertex base;
    glm::vec2 uv;
    std::uint16_t rect[4];  // atlas entry x, y, width, height; width 0: samples nothing
    glm::vec2 params;       // atlas layer, alpha threshold (discard where coverage < it)
};
static_assert(sizeof(TexturedVertex) == SceneGpu::kTexturedVertexStride);
static_assert(offsetof(TexturedVertex, uv) == SceneGpu::kUvOffset);
static_assert(offsetof(TexturedVertex, rect) == SceneGpu::kTexRectOffset);
static_assert(offsetof(TexturedVertex, params) == SceneGpu::kTexParamsOffset);

// How one material samples the atlas and tests alpha.
struct MaterialSampling {
    glm::vec3 kd{0.0f};    // mirrors: the diffuse part the tracer keeps (passes/mirror.h)
    glm::vec4 specular{0.0f};  // glossy diffuse materials: ks and ns, as the tracer scales them
    gpu::GpuLobe lobe;         // a rough conductor's or plastic's microfacet lobe
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
    const glm::vec3 ks = glm::max(m.ks, glm::vec3(0.0f));
    if (m.kind == MaterialKind::Diffuse && (ks.x > 0.0f || ks.y > 0.0f || ks.z > 0.0f)) {
        // The tracer's energy rule (tracer/embree_scene.cpp convertMaterial): kd + ks <= 1.
        const glm::vec3 sum = out.kd + ks;
        const float most = std::max({sum.x, sum.y, sum.z, 1.0f});
        out.kd /= most;
        out.specular = glm::vec4(ks / most, std::max(m.ns, 0.0f));
    }
    // Mitsuba's rough conductor and plastic: their microfacet lobe, as the tracer evaluates it
    // (tracer/bsdf.h); the smooth ones are mirrors (passes/mirror.h).
    const bool rough = m.alphaU > 0.0f && m.alphaV > 0.0f;
    if (m.kind == MaterialKind::Diffuse && rough && (m.model == BsdfModel::Conductor || m.model == BsdfModel::Plastic)) {
        const bool conductor = m.model == BsdfModel::Conductor;
        const float ior = m.ior > 0.0f && m.ior != 1.0f ? m.ior : 1.49f;  // the tracer's default
        out.lobe.model = conductor ? GBUFFER_LOBE_CONDUCTOR : GBUFFER_LOBE_PLASTIC;
        out.lobe.alphaU = std::max(m.alphaU, microfacet::kMinAlpha);
        out.lobe.alphaV = std::max(m.alphaV, microfacet::kMinAlpha);
        out.lobe.distribution = m.distribution == MicrofacetType::GGX ? 1.0f : 0.0f;
        out.lobe.eta = glm::vec4(m.eta, ior);
        out.lobe.k = glm::vec4(m.k, 0.0f);
        out.specular = glm::vec4(glm::max(m.specularReflectance, glm::vec3(0.0f)), 0.0f);
        // The plastic's base seen through the coating: kd / (1 - R_int) / ior^2 (nonlinear: kd
        // R_int), R_int the rough coating's internal reflectance as the tracer computes it, times
        // the coating's transmittances the shader takes as 1 - F at both ends.
        const microfacet::Distribution dist(m.distribution, m.alphaU, m.alphaV);
        const float internal = conductor ? 0.0f : microfacet::coatingHemisphericalAverage(dist, ior, true);
        out.kd = conductor ? glm::vec3(0.0f)
                           : (m.nonlinear ? m.kd / (1.0f - m.kd * internal) : m.kd / (1.0f - internal)) / (ior * ior);
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
// first, then the glass ones, which only cast shadows (SceneGpu, "Glass"). `drawn` gets the
// mesh triangle of each triangle in that order.
struct FlatMesh {
    std::vector<std::byte> bytes;
    std::vector<std::uint32_t> drawn;
    std::uint32_t cameraVertices = 0, allVertices = 0;
    bool alphaMasked = false;
    bool microfacet = false;  // some drawn material has a microfacet lobe
};

// What glass vertices carry in their kd slot (a dielectric has no diffuse albedo): the Fresnel
// reflectance at normal incidence, ((ior - 1) / (ior + 1))^2, which gbuffer.glass.frag reads.
glm::vec3 glassKd(const Material& m) {
    const float ior = std::isfinite(m.ior) && m.ior > 0.0f ? m.ior : 1.5f;
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return glm::vec3(r * r);
}

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
            v.base = {p[k], n, isGlass(t) ? glassKd(m) : id < materials.size() ? ms.kd : m.kd, m.ke,
                      id < materials.size() ? ms.specular : glm::vec4(0.0f), {}, {}, {}};
            const gpu::GpuLobe lobe = id < materials.size() ? ms.lobe : gpu::GpuLobe{};
            flat.microfacet |= lobe.model != GBUFFER_LOBE_PHONG;
            packHalves({lobe.model, lobe.alphaU, lobe.alphaV, lobe.distribution}, v.base.lobe);
            packHalves(lobe.eta, v.base.eta);
            packHalves(lobe.k, v.base.k);
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

}  // namespace

SceneGpu::SceneGpu(VulkanContext& context, const Scene& scene) : context_(&context) {
    const TextureAtlas atlas = buildTextureAtlas(scene);
    textured_ = !atlas.empty();
    atlasEntries_ = static_cast<std::uint32_t>(atlas.entries.size());
    if (textured_) atlas_ = uploadAtlas(context, atlas);
    FlatMesh flat = flatten(scene, atlas, textured_);
    alphaMasked_ = flat.alphaMasked;
    microfacet_ = flat.microfacet;
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
    if (sharedPositions() && vertexCount_ > 0) {  // the G-buffer's depth pre-pass and tie order
        std::vector<std::uint32_t> reversed(vertexCount_);
        for (std::uint32_t v = 0; v < vertexCount_; ++v) reversed[v] = vertexCount_ - 3 * (v / 3 + 1) + v % 3;
        reversedTriangles_ = vk::uploadBuffer(context, bytesOf(reversed), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
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

void SceneGpu::setLights(std::span<const PointLight> lights, std::span<const DirectionalLight> directionals,
                            const std::array<glm::vec3, 9>* ambientSH, std::span<const float> patchHalfSides) {
    std::vector<gpu::GpuLight> gpuLights;
    softShadows_ = false;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const PointLight& l = lights[i];
        // A lobe wins over a spot cone, as in the tracer (tracer/lights.cpp).
        const bool spot = glm::dot(l.normal, l.normal) == 0.0f && glm::dot(l.spotDirection, l.spotDirection) > 0.0f;
        // Only lobes (area-light samples) have patches; anything else keeps its hard shadow.
        const float given = i < patchHalfSides.size() ? patchHalfSides[i] : 0.0f;
        const bool lobe = glm::dot(l.normal, l.normal) > 0.0f;
        const float patch = lobe && std::isfinite(given) && given > 0.0f ? given : 0.0f;
        softShadows_ = softShadows_ || patch > 0.0f;
        gpuLights.push_back({glm::vec4(l.position, 1.0f), glm::vec4(l.intensity, 0.0f),
                             glm::vec4(spot ? glm::normalize(l.spotDirection) : l.normal, 0.0f),
                             glm::vec4(l.cosInner, std::min(l.cosOuter, l.cosInner), spot ? 1.0f : 0.0f, patch)});
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
    ++shadingVersion_;
    faceSizes_.assign(gpuLights.size(), 0u);
    for (gpu::GpuLight& l : gpuLights) l.position.w = 0.0f;  // set by setShadowFaceSizes
    gpuLights.resize(GBUFFER_MAX_LIGHTS);  // the shader declares the whole array
    gpuLights_ = std::move(gpuLights);
    lights_ = vk::uploadBuffer(*context_, bytesOf(gpuLights_), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
}

void SceneGpu::setShadowFaceSizes(std::span<const std::uint32_t> sizes) {
    if (sizes.size() != faceSizes_.size())
        throw std::logic_error(fmt::format("SceneGpu::setShadowFaceSizes: {} sizes for {} lights", sizes.size(),
                                           faceSizes_.size()));
    if (std::equal(sizes.begin(), sizes.end(), faceSizes_.begin())) return;
    faceSizes_.assign(sizes.begin(), sizes.end());
    for (std::size_t i = 0; i < faceSizes_.size(); ++i) gpuLights_[i].position.w = static_cast<float>(faceSizes_[i]);
    for (std::size_t k = 0; k < inlineLights_.size(); ++k) inlineLights_[k].position.w = gpuLights_[k].position.w;
    ++shadingVersion_;
    lights_ = vk::uploadBuffer(*context_, bytesOf(gpuLights_), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
}

std::vector<std::uint32_t> SceneGpu::lightingConstants(std::uint32_t pcf) const {
    std::vector<std::uint32_t> constants(LIGHTING_SPEC_COUNT);
    constants[LIGHTING_SPEC_LIGHT_COUNT] = lightCount_;
    constants[LIGHTING_SPEC_SHADOW_PCF] = std::max(pcf, 1u);
    constants[LIGHTING_SPEC_LIGHT_KINDS] = lightKinds_;
    constants[LIGHTING_SPEC_SOFT_SHADOWS] = softShadows_ ? 1u : 0u;
    static_assert(sizeof(gpu::GpuLight) == 4 * sizeof(glm::vec4) && LIGHTING_SPEC_FLOATS_PER_LIGHT == 14);
    for (std::size_t k = 0; k < inlineLights_.size(); ++k) {
        const gpu::GpuLight& l = inlineLights_[k];
        const glm::vec4 fields[4] = {l.position, l.intensity, l.normal, l.cone};
        const std::size_t first = LIGHTING_SPEC_LIGHT_DATA + LIGHTING_SPEC_FLOATS_PER_LIGHT * k;
        for (int f = 0; f < 4; ++f)  // xyz of each field, w dropped
            for (int c = 0; c < 3; ++c) constants[first + 3 * f + c] = std::bit_cast<std::uint32_t>(fields[f][c]);
        constants[first + 12] = std::bit_cast<std::uint32_t>(l.cone.w);      // the patch's half side
        constants[first + 13] = std::bit_cast<std::uint32_t>(l.position.w);  // the shadow face size
    }
    constants[LIGHTING_SPEC_MICROFACET] = microfacet_ ? 1u : 0u;
    constants[LIGHTING_SPEC_AMBIENT] = ambient_ ? 1u : 0u;
    for (int i = 0; i < 9; ++i)
        for (int c = 0; c < 3; ++c)
            constants[LIGHTING_SPEC_AMBIENT_SH + 3 * i + c] = std::bit_cast<std::uint32_t>(ambientSH_[i][c]);
    return constants;
}

std::string SceneGpu::atlasSummary() const {
    if (!textured_) return "no textures: no texture binding";
    return fmt::format("base-colour textures from a {}x{}x{} atlas of {} entr{} (the scene samples textures){}",
                       atlas_.info().width, atlas_.info().height, atlas_.info().layers, atlasEntries_,
                       atlasEntries_ == 1 ? "y" : "ies", alphaMasked_ ? ", with alpha test" : "");
}

}  // namespace aamap::passes
