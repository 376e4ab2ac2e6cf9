#pragma once
// Scene pieces for the material, path-tracing and robustness tests (on top of SceneBuilder).
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "tests/tracer/scene_builder.h"
#include "tracer/tracer.h"

namespace aamap::testing {

inline std::uint32_t addMaterial(SceneBuilder& b, Material m) {
    b.scene().materials.push_back(std::move(m));
    return static_cast<std::uint32_t>(b.scene().materials.size() - 1);
}

inline Material mirrorMaterial(glm::vec3 ks) {
    Material m;
    m.name = "mirror";
    m.kind = MaterialKind::Mirror;
    m.kd = glm::vec3(0.0f);
    m.ks = ks;
    return m;
}

inline Material glassMaterial(float ior) {
    Material m;
    m.name = "glass";
    m.kind = MaterialKind::Glass;
    m.kd = glm::vec3(0.0f);
    m.ks = glm::vec3(1.0f);
    m.ior = ior;
    return m;
}

// A UV sphere of `rings` x `segments` quads; `inward`: front sides (and normals) face the centre.
// Returns the triangle indices.
inline std::vector<std::uint32_t> sphere(SceneBuilder& b, glm::vec3 c, float r, std::uint32_t material, bool inward,
                                         int rings = 24, int segments = 48) {
    TriangleMesh& m = b.scene().mesh;
    const auto at = [&](int i, int j) {
        const float th = std::numbers::pi_v<float> * static_cast<float>(i) / static_cast<float>(rings);
        const float ph = 2.0f * std::numbers::pi_v<float> * static_cast<float>(j) / static_cast<float>(segments);
        return glm::vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
    };
    std::vector<std::uint32_t> tris;
    const auto tri = [&](glm::vec3 a, glm::vec3 p, glm::vec3 q) {
        const glm::vec3 n = glm::cross(p - a, q - a);
        if (glm::length(n) < 1e-9f) return;
        if ((glm::dot(n, a + p + q) < 0.0f) != inward) std::swap(p, q);
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const glm::vec3& v : {a, p, q}) {
            m.positions.push_back(c + r * v);
            m.normals.push_back(inward ? -v : v);
        }
        tris.push_back(static_cast<std::uint32_t>(m.triangles.size()));
        m.triangles.push_back({base, base + 1, base + 2});
        m.materialIds.push_back(material);
        m.objectIds.push_back(1000);
    };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            tri(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            tri(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    return tris;
}

// A furnace: a closed sphere (12 x 24 quads, fronts inward) of albedo rho emitting le everywhere,
// one area light. Inside it radiance is le (1 + rho + rho^2 + ...) in every direction.
inline void furnaceSphere(SceneBuilder& b, glm::vec3 centre, float rho, float le) {
    const auto mat = b.material("furnace", glm::vec3(rho), glm::vec3(le));
    AreaLight light;
    light.name = "furnace";
    light.radiance = glm::vec3(le);
    light.triangles = sphere(b, centre, 1.0f, mat, /*inward=*/true, 12, 24);
    b.scene().areaLights.push_back(light);
}

// Fills uvs with zeros for vertices added without them (the mesh needs one per position).
inline void padUvs(Scene& s) { s.mesh.uvs.resize(s.mesh.positions.size(), glm::vec2(0.0f)); }

inline View lookAt(glm::vec3 from, glm::vec3 to, float fovDeg, glm::vec3 up = {0, 1, 0}) {
    View v;
    v.position = from;
    v.direction = glm::normalize(to - from);
    v.up = up;
    v.horizontalFovDeg = v.verticalFovDeg = fovDeg;
    return v;
}

inline TraceResult renderScene(const Scene& scene, const View& view, const ShadingSettings& shading, int size,
                               int strata, int threads = 0, std::uint64_t seed = 5) {
    const Tracer tracer(scene);
    TraceSettings settings;
    settings.width = settings.height = size;
    settings.seed = seed;
    settings.threads = threads;
    settings.shading = shading;
    StrategySettings strategy;
    strategy.strata = strata;
    return tracer.render(view, settings, strategy);
}

// Mean and standard error of the mean of a set of independent estimates.
struct MeanError {
    double mean = 0.0, error = 0.0;
};
template <class Values>
MeanError meanError(const Values& values) {
    double s = 0.0, s2 = 0.0, n = 0.0;
    for (double v : values) {
        s += v;
        s2 += v * v;
        n += 1.0;
    }
    const double mean = s / n;
    const double var = std::max(0.0, s2 / n - mean * mean) * n / (n - 1.0);
    return {mean, std::sqrt(var / n)};
}

}  // namespace aamap::testing
