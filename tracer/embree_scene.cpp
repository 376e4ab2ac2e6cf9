#include "tracer/embree_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "core/error.h"
#include "core/texture_filter.h"
#include "tracer/bsdf.h"

namespace aamap {
namespace {

// Embree filter for primary, secondary and shadow rays alike: a hit on a cut-out texel is no hit.
void alphaFilter(const RTCFilterFunctionNArguments* args) {
    const auto* scene = static_cast<const EmbreeScene*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        if (scene->cutOut(prim, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)))
            args->valid[i] = 0;
    }
}

void onEmbreeError(void*, RTCError code, const char* message) {
    spdlog::error("embree error {}: {}", static_cast<int>(code), message ? message : "(no message)");
}

void validate(const Scene& scene) {
    const TriangleMesh& m = scene.mesh;
    const std::size_t triCount = m.triangles.size();
    if (m.materialIds.size() != triCount)
        throw std::invalid_argument(
            fmt::format("mesh has {} triangles but {} material ids", triCount, m.materialIds.size()));
    if (!m.normals.empty() && m.normals.size() != m.positions.size())
        throw std::invalid_argument(
            fmt::format("mesh has {} positions but {} normals", m.positions.size(), m.normals.size()));
    for (std::size_t t = 0; t < triCount; ++t) {
        const glm::uvec3& tri = m.triangles[t];
        if (tri.x >= m.positions.size() || tri.y >= m.positions.size() || tri.z >= m.positions.size())
            throw std::invalid_argument(fmt::format("triangle {} indexes past the {} positions", t, m.positions.size()));
        if (m.materialIds[t] >= scene.materials.size())
            throw std::invalid_argument(fmt::format("triangle {} has material {} of {}", t, m.materialIds[t],
                                                    scene.materials.size()));
    }
}

bool positive(const glm::vec3& c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }
float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Mitsuba's conductor and plastic: the Snapshot's kind, kd, ks, ns give way to the model's own
// parameters. Smooth ones become Mirror (their delta lobe takes the mirror paths), rough ones
// Diffuse with a glossy lobe.
void convertModel(const Material& mat, ShadingMaterial& s) {
    s.model = mat.model;
    s.distribution = mat.distribution;
    s.alphaU = std::max(mat.alphaU, 0.0f);
    s.alphaV = std::max(mat.alphaV, 0.0f);
    s.rough = s.alphaU > 0.0f && s.alphaV > 0.0f;
    s.eta = mat.eta;
    s.k = mat.k;
    s.specularTint = glm::max(mat.specularReflectance, glm::vec3(0.0f));
    s.nonlinear = mat.nonlinear;
    s.ior = mat.ior > 0.0f && mat.ior != 1.0f ? mat.ior : 1.49f;
    s.kind = s.rough ? MaterialKind::Diffuse : MaterialKind::Mirror;
    s.glossy = s.rough;
    s.ns = 0.0f;
    if (mat.model == BsdfModel::Conductor) {
        s.kd = s.kdOverPi = glm::vec3(0.0f);
        s.diffuse = false;
        s.texture = -1;
        s.ks = s.specularTint;  // for the specular branch cutoffs: the most the lobe reflects
    } else {
        s.kd = mat.kd;  // unscaled: the coating model conserves energy itself
        s.kdOverPi = s.kd * std::numbers::inv_pi_v<float>;
        s.diffuse = s.kd.x != 0.0f || s.kd.y != 0.0f || s.kd.z != 0.0f;
        s.ks = s.specularTint;
        // Mitsuba steers by the mean specular and diffuse reflectances (a texture counts as kd).
        const float sm = (s.specularTint.x + s.specularTint.y + s.specularTint.z) / 3.0f;
        const float dm = (s.kd.x + s.kd.y + s.kd.z) / 3.0f;
        s.specularWeight = sm + dm > 0.0f ? sm / (sm + dm) : 0.5f;
    }
    s.diffuseWeight = 0.0f;
    bsdf::prepareModel(s);
}

ShadingMaterial convertMaterial(const Material& mat, std::size_t textureCount) {
    ShadingMaterial s;
    s.kind = mat.kind;
    s.ke = glm::max(mat.ke, glm::vec3(0.0f));
    s.emissive = positive(s.ke);
    glm::vec3 kd = mat.kd, ks = glm::max(mat.ks, glm::vec3(0.0f));  // kd unclamped: a NaN must show
    // MTL illum 3/5/7 without Ks: a perfect mirror or clear glass is what such files mean.
    if (mat.kind != MaterialKind::Diffuse && !positive(ks)) ks = glm::vec3(1.0f);
    if (mat.kind == MaterialKind::Glass) kd = glm::vec3(0.0f);  // a dielectric has no Lambert lobe
    // Energy conservation: kd + ks <= 1 per channel (Glass: ks is a transmission/reflection tint).
    const glm::vec3 sum = kd + ks;
    const float most = std::max(sum.x, std::max(sum.y, sum.z));
    if (mat.kind != MaterialKind::Glass && most > 1.0f) {
        spdlog::debug("material '{}': kd + ks = {} > 1, scaled down to conserve energy", mat.name, most);
        kd /= most;
        ks /= most;
    }
    s.kd = kd;
    s.kdOverPi = kd * std::numbers::inv_pi_v<float>;
    s.ks = mat.kind == MaterialKind::Glass ? glm::min(ks, glm::vec3(1.0f)) : ks;
    s.ior = mat.ior > 0.0f ? mat.ior : 1.5f;
    s.thin = mat.kind == MaterialKind::Glass && mat.thin;
    s.oneSided = mat.kind != MaterialKind::Glass && mat.oneSided;
    if (mat.diffuseTexture >= 0 && static_cast<std::size_t>(mat.diffuseTexture) < textureCount && positive(kd))
        s.texture = mat.diffuseTexture;
    s.diffuse = kd.x != 0.0f || kd.y != 0.0f || kd.z != 0.0f;  // true for NaN: bad data is counted, not hidden
    s.glossy = mat.kind == MaterialKind::Diffuse && positive(ks);
    s.alphaTested = isAlphaTested(mat);
    s.alpha = mat.alpha;
    s.alphaCutoff = effectiveAlphaCutoff(mat);
    if (s.alphaTested && mat.alphaTexture >= 0 && static_cast<std::size_t>(mat.alphaTexture) < textureCount)
        s.alphaTexture = mat.alphaTexture;
    if (mat.normalMap >= 0 && static_cast<std::size_t>(mat.normalMap) < textureCount) s.normalMap = mat.normalMap;
    if (mat.bumpMap >= 0 && static_cast<std::size_t>(mat.bumpMap) < textureCount) s.bumpMap = mat.bumpMap;
    s.bumpScale = std::isfinite(mat.bumpScale) ? mat.bumpScale : 0.0f;
    s.mapMirroredOnBack = mat.mapMirroredOnBack;
    s.ns = std::max(mat.ns, 0.0f);
    s.phongNorm = (s.ns + 2.0f) * 0.5f * std::numbers::inv_pi_v<float>;
    s.phongPdfNorm = (s.ns + 1.0f) * 0.5f * std::numbers::inv_pi_v<float>;
    if (s.glossy) {
        const float d = luminance(kd), g = luminance(ks);
        s.diffuseWeight = d + g > 0.0f ? d / (d + g) : 0.0f;
    }
    if (mat.model == BsdfModel::Conductor || mat.model == BsdfModel::Plastic) {
        convertModel(mat, s);
        if (s.rough && mat.roughnessTexture >= 0 && static_cast<std::size_t>(mat.roughnessTexture) < textureCount)
            s.roughnessTexture = mat.roughnessTexture;
    }
    if (mat.model == BsdfModel::Blend && mat.blend.size() == 2) {
        // Its components scatter; kd (their mix) is only the albedo the cache mode's Lambert
        // stand-in reads. One non-delta lobe to the integrators: diffuse, never glossy.
        s.model = BsdfModel::Blend;
        s.kind = MaterialKind::Diffuse;
        s.diffuse = true;
        s.glossy = false;
        s.diffuseWeight = 1.0f;
        s.texture = -1;
        s.blendWeight = std::clamp(mat.blendWeight, 0.0f, 1.0f);
    }
    if (mat.model == BsdfModel::Dielectric && mat.kind == MaterialKind::Glass && !mat.thin) {
        // roughdielectric: a Glass whose interface has microfacets (path mode samples them; the
        // direct and cache modes' specular branches see the smooth interface).
        s.model = BsdfModel::Dielectric;
        s.distribution = mat.distribution;
        s.alphaU = std::max(mat.alphaU, 0.0f);
        s.alphaV = std::max(mat.alphaV, 0.0f);
        s.rough = s.alphaU > 0.0f && s.alphaV > 0.0f;
        s.specularTint = glm::max(mat.specularReflectance, glm::vec3(0.0f));
    }
    return s;
}

}  // namespace

std::string SceneFeatures::describe() const {
    const auto on = [](bool b) { return b ? "on" : "off"; };
    return fmt::format(
        "textures {} ({}), glossy {} ({}), mirror {} ({}), glass {} ({}), emitters {} ({})", on(textures),
        textures ? "a used material has a diffuse texture and the mesh has uvs" : "no textured material in use",
        on(glossy), glossy ? "a used diffuse material has Ks > 0" : "no Ks", on(mirror),
        mirror ? "a used material is a mirror" : "no mirror", on(glass), glass ? "a used material is glass" : "no glass",
        on(emissive), emissive ? "a used material has Ke > 0" : "no Ke") +
           fmt::format(", alpha mask {} ({})", on(alphaMask),
                       alphaMask ? "a used material is MASK or BLEND: Embree filters cut out its holes"
                                 : "every used material is opaque: no Embree filter");
}

EmbreeScene::EmbreeScene(const Scene& scene) {
    validate(scene);
    const TriangleMesh& m = scene.mesh;

    materials_.reserve(scene.materials.size());
    for (const Material& mat : scene.materials) materials_.push_back(convertMaterial(mat, scene.textures.size()));
    // Blend components, converted as materials of their own; the pointers are taken once the
    // vector holds them all (it never grows after).
    for (const Material& mat : scene.materials)
        if (mat.model == BsdfModel::Blend)
            for (const Material& part : mat.blend) blendComponents_.push_back(convertMaterial(part, 0));
    for (std::size_t i = 0, next = 0; i < scene.materials.size(); ++i) {
        if (scene.materials[i].model != BsdfModel::Blend) continue;
        materials_[i].blendA = &blendComponents_[next];
        materials_[i].blendB = &blendComponents_[next + 1];
        next += 2;
    }
    std::vector<char> used(materials_.size(), 0);
    for (std::uint32_t id : m.materialIds) used[id] = 1;
    const bool hasUvs = !m.uvs.empty() && m.uvs.size() == m.positions.size();
    for (std::size_t i = 0; i < materials_.size(); ++i) {
        ShadingMaterial& s = materials_[i];
        if (!used[i]) continue;
        if (s.texture >= 0 && !hasUvs) {
            spdlog::warn("material '{}' is textured but the mesh has no uvs; texture ignored", scene.materials[i].name);
            s.texture = -1;
        }
        if (s.alphaTexture >= 0 && !hasUvs) {
            spdlog::warn("material '{}' has an alpha texture but the mesh has no uvs; coverage is constant",
                         scene.materials[i].name);
            s.alphaTexture = -1;
        }
        if (s.roughnessTexture >= 0 && !hasUvs) {
            spdlog::warn("material '{}' has a roughness texture but the mesh has no uvs; its mean roughness is used",
                         scene.materials[i].name);
            s.roughnessTexture = -1;
        }
        if (s.perturbed() && !hasUvs) {
            spdlog::warn("material '{}' has a normal or bump map but the mesh has no uvs; the map is ignored",
                         scene.materials[i].name);
            s.normalMap = s.bumpMap = -1;
        }
        // A constant coverage at or above the cutoff never cuts: no filter calls for it.
        if (s.alphaTested && s.alphaTexture < 0 && s.alpha >= s.alphaCutoff) s.alphaTested = false;
        features_.alphaMask |= s.alphaTested;
        features_.textures |= s.texture >= 0;
        features_.glossy |= s.glossy;
        features_.mirror |= s.kind == MaterialKind::Mirror;
        features_.glass |= s.kind == MaterialKind::Glass;
        features_.emissive |= s.emissive;
    }
    std::vector<char> coverageUsed(scene.textures.size(), 0);
    for (std::size_t i = 0; i < materials_.size(); ++i)
        if (used[i] && materials_[i].alphaTested && materials_[i].alphaTexture >= 0)
            coverageUsed[static_cast<std::size_t>(materials_[i].alphaTexture)] = 1;
    const bool alphaTextures = std::find(coverageUsed.begin(), coverageUsed.end(), 1) != coverageUsed.end();
    // Textures that a normal or bump map reads (level 0, unfiltered, as Mitsuba's bitmap).
    std::vector<char> mapUsed(scene.textures.size(), 0);
    for (std::size_t i = 0; i < materials_.size(); ++i)
        if (used[i])
            for (int t : {materials_[i].normalMap, materials_[i].bumpMap, materials_[i].roughnessTexture})
                if (t >= 0) mapUsed[static_cast<std::size_t>(t)] = 1;
    const bool maps = std::find(mapUsed.begin(), mapUsed.end(), 1) != mapUsed.end();
    const bool needUvs = features_.textures || alphaTextures || maps;
    if (needUvs) textures_.resize(scene.textures.size());
    for (std::size_t i = 0; i < coverageUsed.size(); ++i) {
        const Texture& t = scene.textures[i];
        const std::size_t texels = static_cast<std::size_t>(std::max(t.width, 0)) * std::max(t.height, 0);
        if (!coverageUsed[i] || t.rgba.size() < 4 * texels || texels == 0) continue;  // unusable: alpha constant
        textures_[i].width = t.width;
        textures_[i].height = t.height;
        textures_[i].alpha.resize(texels);
        for (std::size_t k = 0; k < texels; ++k) textures_[i].alpha[k] = t.rgba[4 * k + 3];
    }
    if (features_.textures || maps) {
        for (std::size_t i = 0; i < scene.textures.size(); ++i) {
            const Texture& t = scene.textures[i];
            if (!features_.textures && !mapUsed[i]) continue;
            TextureData& d = textures_[i];
            const std::size_t texels = static_cast<std::size_t>(std::max(t.width, 0)) * std::max(t.height, 0);
            if (t.rgba.size() < 4 * texels || texels == 0) continue;  // unusable: albedo stays kd
            d.width = t.width;
            d.height = t.height;
            std::vector<glm::vec3> rgb(texels);
            for (std::size_t k = 0; k < texels; ++k) rgb[k] = {t.rgba[4 * k], t.rgba[4 * k + 1], t.rgba[4 * k + 2]};
            const std::vector<MipLevel> chain = buildMipChain(t.width, t.height, std::move(rgb));
            d.mean = chain.back().rgb.front();
            d.rgb = packMipChain(chain);
        }
        // A textured plastic steers its samples by the base's mean albedo, as Mitsuba does: kd
        // times the texture's mean (the 1 x 1 top of its mip chain).
        for (ShadingMaterial& sm : materials_) {
            if (sm.model != BsdfModel::Plastic || sm.texture < 0 || static_cast<std::size_t>(sm.texture) >= textures_.size())
                continue;
            const TextureData& d = textures_[static_cast<std::size_t>(sm.texture)];
            if (d.rgb.empty()) continue;
            const glm::vec3 mean = sm.kd * d.mean;
            const float sm3 = (sm.specularTint.x + sm.specularTint.y + sm.specularTint.z) / 3.0f;
            const float dm = (mean.x + mean.y + mean.z) / 3.0f;
            sm.specularWeight = sm3 + dm > 0.0f ? sm3 / (sm3 + dm) : 0.5f;
        }
    }
    // Each mapped material's unlit twin, before the roughness levels copy the pointer.
    unlit_.reserve(materials_.size());
    for (ShadingMaterial& sm : materials_) {
        if (!sm.perturbed()) continue;
        ShadingMaterial u = sm;
        u.kind = MaterialKind::Diffuse;
        u.model = BsdfModel::Classic;
        u.diffuse = u.glossy = u.rough = false;
        u.kd = u.kdOverPi = u.ks = glm::vec3(0.0f);
        u.texture = -1;
        u.blendA = u.blendB = nullptr;
        u.roughnessTexture = -1;
        u.roughnessLevels = nullptr;
        u.unlit = nullptr;
        unlit_.push_back(u);
        sm.unlit = &unlit_.back();
    }
    buildRoughnessLevels(used);
    spdlog::info("tracer features: {}", features_.describe());

    triangles_.reserve(m.triangles.size());
    const bool hasNormals = !m.normals.empty();
    if (hasNormals) vertexNormals_.reserve(3 * m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const glm::uvec3& idx = m.triangles[t];
        Triangle tri;
        tri.v0 = m.positions[idx.x];
        tri.e1 = m.positions[idx.y] - tri.v0;
        tri.e2 = m.positions[idx.z] - tri.v0;
        const glm::vec3 n = glm::cross(tri.e1, tri.e2);
        const float len = glm::length(n);
        tri.normal = len > 0.0f ? n / len : glm::vec3(0.0f);  // degenerate: never hit by Embree
        tri.material = m.materialIds[t];
        tri.vertexScale = 0.0f;
        for (int c = 0; c < 3; ++c) {
            const glm::vec3& p = m.positions[idx[c]];
            tri.vertexScale = std::max({tri.vertexScale, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
        }
        tri.flat = true;
        if (hasNormals)
            for (int c = 0; c < 3; ++c) tri.flat &= glm::dot(m.normals[idx[c]], tri.normal) > 1.0f - 1e-6f;
        triangles_.push_back(tri);
        if (hasNormals)
            for (int c = 0; c < 3; ++c) vertexNormals_.push_back(m.normals[idx[c]]);
        if (needUvs)
            for (int c = 0; c < 3; ++c) vertexUvs_.push_back(m.uvs[idx[c]]);
    }

    device_ = rtcNewDevice(nullptr);
    if (!device_)
        throw EnvironmentError(fmt::format("cannot create an Embree device (error {})",
                                           static_cast<int>(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(device_, onEmbreeError, nullptr);

    const auto start = std::chrono::steady_clock::now();
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    if (!m.triangles.empty()) {
        RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
        // Copied, not shared: Embree reads vertices with 16-byte loads, so the buffer needs
        // padding past the last vertex that a std::vector<glm::vec3> does not promise.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3), m.positions.size()));
        auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(glm::uvec3), m.triangles.size()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geom);
            rtcReleaseScene(scene_);
            rtcReleaseDevice(device_);
            throw EnvironmentError("Embree could not allocate the geometry buffers");
        }
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            for (int c = 0; c < 3; ++c) vertices[3 * i + c] = m.positions[i][c];
        for (std::size_t i = 0; i < m.triangles.size(); ++i)
            for (int c = 0; c < 3; ++c) indices[3 * i + c] = m.triangles[i][c];
        if (features_.alphaMask) {  // only for scenes with holes: filters cost every hit
            rtcSetGeometryUserData(geom, this);
            rtcSetGeometryIntersectFilterFunction(geom, alphaFilter);
            rtcSetGeometryOccludedFilterFunction(geom, alphaFilter);
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene_, geom);  // geometry id 0: primID indexes TriangleMesh::triangles
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(scene_);
    buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    spdlog::debug("embree: {} triangles, BVH built in {:.3f} s", triangles_.size(), buildSeconds_);
}

EmbreeScene::~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

glm::vec3 EmbreeScene::shadingNormal(std::uint32_t id, float u, float v) const {
    const Triangle& tri = triangles_[id];
    if (tri.flat || vertexNormals_.empty()) return tri.normal;  // the common case: planar faces
    const glm::vec3* n = &vertexNormals_[3 * static_cast<std::size_t>(id)];
    const glm::vec3 interp = (1.0f - u - v) * n[0] + u * n[1] + v * n[2];
    const float len2 = glm::dot(interp, interp);
    if (!(len2 > 1e-12f) || !std::isfinite(len2)) return tri.normal;
    return interp / std::sqrt(len2);
}

namespace {
float alphaOf(const glm::vec3& c) { return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z; }  // Mitsuba's eval_1
}  // namespace

void EmbreeScene::buildRoughnessLevels(const std::vector<char>& used) {
    std::vector<std::size_t> textured;
    for (std::size_t i = 0; i < materials_.size(); ++i) {
        const int t = materials_[i].roughnessTexture;
        if (used[i] && t >= 0 && static_cast<std::size_t>(t) < textures_.size() &&
            !textures_[static_cast<std::size_t>(t)].rgb.empty())
            textured.push_back(i);
        else
            materials_[i].roughnessTexture = -1;
    }
    // Reserved whole first: materials point into the vector.
    roughnessLevels_.reserve(textured.size() * ShadingMaterial::kRoughnessLevels);
    for (std::size_t i : textured) {
        ShadingMaterial& m = materials_[i];
        const PackedLevel& level = textures_[static_cast<std::size_t>(m.roughnessTexture)].rgb[0];
        float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
        for (int y = 0; y < level.height(); ++y)
            for (int x = 0; x < level.width(); ++x) {
                const float a = alphaOf(level.texel(static_cast<std::size_t>(x), static_cast<std::size_t>(y)));
                lo = std::min(lo, a);
                hi = std::max(hi, a);
            }
        // Mitsuba clamps alpha to 1e-4: the levels stay rough.
        lo = std::max(lo, 1e-4f);
        hi = std::max(hi, lo);
        const int count = hi > lo ? ShadingMaterial::kRoughnessLevels : 1;
        m.roughnessMin = lo;
        m.roughnessStep = count > 1 ? (hi - lo) / static_cast<float>(count - 1) : 0.0f;
        const std::size_t first = roughnessLevels_.size();
        for (int k = 0; k < count; ++k) {
            ShadingMaterial l = m;
            l.alphaU = l.alphaV = k + 1 == count ? hi : lo + m.roughnessStep * static_cast<float>(k);
            l.roughnessTexture = -1;
            l.roughnessLevels = nullptr;
            bsdf::prepareModel(l);
            roughnessLevels_.push_back(l);
        }
        m.roughnessLevels = &roughnessLevels_[first];
    }
}

const ShadingMaterial& EmbreeScene::roughnessLevel(const ShadingMaterial& m, std::uint32_t id, float u, float v) const {
    const TextureData& t = textures_[static_cast<std::size_t>(m.roughnessTexture)];
    if (!(m.roughnessStep > 0.0f)) return m.roughnessLevels[0];
    const float a = alphaOf(bilinear(t.rgb[0], textureCoordinates(id, u, v)));
    const float k = std::round((a - m.roughnessMin) / m.roughnessStep);
    const int last = ShadingMaterial::kRoughnessLevels - 1;
    return m.roughnessLevels[k >= 0.0f ? (k <= static_cast<float>(last) ? static_cast<int>(k) : last) : 0];
}

glm::vec3 EmbreeScene::perturbedNormal(const ShadingMaterial& m, std::uint32_t id, float u, float v,
                                       const glm::vec3& n) const {
    const int map = m.normalMap >= 0 ? m.normalMap : m.bumpMap;
    if (map < 0 || vertexUvs_.empty()) return n;
    const TextureData& t = textures_[static_cast<std::size_t>(map)];
    if (t.rgb.empty()) return n;
    // dp/du and dp/dv of the triangle's uv parameterisation (Mitsuba's mesh rule).
    const Triangle& tri = triangles_[id];
    const glm::vec2* uv = &vertexUvs_[3 * static_cast<std::size_t>(id)];
    const glm::vec2 duv1 = uv[1] - uv[0], duv2 = uv[2] - uv[0];
    const float det = duv1.x * duv2.y - duv1.y * duv2.x;
    if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) return n;  // degenerate uvs: no tangent frame
    const glm::vec3 dpdu = (duv2.y * tri.e1 - duv1.y * tri.e2) / det;
    const glm::vec3 dpdv = (duv1.x * tri.e2 - duv2.x * tri.e1) / det;
    const glm::vec2 st = textureCoordinates(id, u, v);
    glm::vec3 result;
    if (m.normalMap >= 0) {
        const glm::vec3 c = 2.0f * bilinear(t.rgb[0], st) - 1.0f;
        if (c.x == 0.0f && c.y == 0.0f && c.z > 0.0f) return n;  // the exact untilted case
        const glm::vec3 s = glm::normalize(dpdu - glm::dot(n, dpdu) * n);
        result = glm::normalize(c.x * s + c.y * glm::cross(n, s) + c.z * n);
    } else {
        const glm::vec2 g = m.bumpScale * bilinearLuminanceGradient(t.rgb[0], st);
        // A flat height field leaves the normal as it is, turned to the geometric normal's side.
        if (g.x == 0.0f && g.y == 0.0f) return glm::dot(tri.normal, n) < 0.0f ? -n : n;
        const glm::vec3 pu = dpdu + (g.x - glm::dot(n, dpdu)) * n;
        const glm::vec3 pv = dpdv + (g.y - glm::dot(n, dpdv)) * n;
        result = glm::normalize(glm::cross(pu, pv));
        if (glm::dot(tri.normal, result) < 0.0f) result = -result;  // Mitsuba turns it to the face's side
    }
    const bool finite = std::isfinite(result.x) && std::isfinite(result.y) && std::isfinite(result.z);
    return finite ? result : n;
}

glm::vec2 EmbreeScene::textureCoordinates(std::uint32_t id, float u, float v) const {
    const glm::vec2* uv = &vertexUvs_[3 * static_cast<std::size_t>(id)];
    return (1.0f - u - v) * uv[0] + u * uv[1] + v * uv[2];
}

glm::vec3 EmbreeScene::texel(int texture, std::uint32_t id, float u, float v, const glm::vec3& dir,
                             float footprint) const {
    const TextureData& t = textures_[static_cast<std::size_t>(texture)];
    if (t.rgb.empty()) return glm::vec3(1.0f);
    const glm::vec2 st = textureCoordinates(id, u, v);
    if (!(footprint > 0.0f)) return bilinear(t.rgb[0], st);
    // The cone's footprint on the triangle's plane, carried into uv by the triangle's own mapping.
    const Triangle& tri = triangles_[id];
    const glm::vec2* uv = &vertexUvs_[3 * static_cast<std::size_t>(id)];
    glm::vec3 axisA, axisB;
    coneFootprint(dir, tri.normal, footprint, axisA, axisB);
    const glm::vec2 duv1 = uv[1] - uv[0], duv2 = uv[2] - uv[0];
    return filteredLookup(t.rgb, st, worldToUv(axisA, tri.e1, tri.e2, duv1, duv2),
                          worldToUv(axisB, tri.e1, tri.e2, duv1, duv2));
}

float EmbreeScene::coverage(int texture, std::uint32_t id, float u, float v) const {
    const TextureData& t = textures_[static_cast<std::size_t>(texture)];
    if (t.alpha.empty()) return 1.0f;
    BilinearTaps taps;
    if (!bilinearTaps(textureCoordinates(id, u, v), t.width, t.height, taps)) return 1.0f;
    const std::vector<float>& a = t.alpha;
    const float top = (1.0f - taps.ax) * a[taps.i00] + taps.ax * a[taps.i10];
    const float bottom = (1.0f - taps.ax) * a[taps.i01] + taps.ax * a[taps.i11];
    return (1.0f - taps.ay) * top + taps.ay * bottom;
}

bool EmbreeScene::cutOut(std::uint32_t id, float u, float v) const {
    const ShadingMaterial& m = materials_[triangles_[id].material];
    if (!m.alphaTested) return false;
    const float a = m.alphaTexture < 0 ? m.alpha : m.alpha * coverage(m.alphaTexture, id, u, v);
    return a < m.alphaCutoff;
}

}  // namespace aamap
