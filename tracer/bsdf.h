#pragma once
// Scattering at a surface, in world space with unit vectors pointing away from the surface (wo to
// the viewer, wi to the light). Lambert + modified Phong (energy-normalised, Lafortune & Willems
// 1994) for Diffuse materials; ideal reflection for mirrors; Fresnel dielectric for glass. Kept
// inline and branch-light: it runs at every path vertex.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "tracer/embree_scene.h"

namespace aamap::bsdf {

constexpr float kInvPi = std::numbers::inv_pi_v<float>;

inline float maxComponent(const glm::vec3& c) { return std::max(c.x, std::max(c.y, c.z)); }
inline float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Orthonormal basis around unit n (Duff et al. 2017, branchless).
inline void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

// Cosine-weighted direction around n; pdf = cos / pi.
inline glm::vec3 sampleCosine(const glm::vec3& n, glm::vec2 u) {
    const float r = std::sqrt(u.x), phi = 2.0f * std::numbers::pi_v<float> * u.y;
    glm::vec3 t, b;
    basis(n, t, b);
    const float z = std::sqrt(std::max(0.0f, 1.0f - u.x));
    return (r * std::cos(phi)) * t + (r * std::sin(phi)) * b + z * n;
}

inline glm::vec3 reflect(const glm::vec3& wo, const glm::vec3& n) { return (2.0f * glm::dot(wo, n)) * n - wo; }

// Unpolarised Fresnel reflectance for light arriving at cosine cosI (> 0) on the side with index
// 1, going into relative index eta = n_other / n_this. Sets cosT (the refracted cosine, >= 0);
// returns 1 on total internal reflection.
inline float fresnelDielectric(float cosI, float eta, float& cosT) {
    const float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) {
        cosT = 0.0f;
        return 1.0f;
    }
    cosT = std::sqrt(1.0f - sin2T);
    const float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    const float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5f * (rs * rs + rp * rp);
}

// Reflectance of a thin dielectric sheet (Mitsuba's thindielectric): the interface's R, plus what
// the inter-reflections between the two faces send back, R + T^2 R / (1 - R^2) = 2R / (1 + R).
// The rest crosses straight through (no refraction: the two faces undo each other's bending).
inline float thinDielectricReflectance(float cosI, float ior) {
    float cosT = 0.0f;
    const float R = fresnelDielectric(cosI, ior, cosT);
    return R < 1.0f ? 2.0f * R / (1.0f + R) : 1.0f;
}

// Refracted direction of wo through a surface with normal n on wo's side.
inline glm::vec3 refract(const glm::vec3& wo, const glm::vec3& n, float eta, float cosI, float cosT) {
    return (-1.0f / eta) * wo + (cosI / eta - cosT) * n;
}

// Phong lobe value cos(alpha)^ns around the mirror direction of wo; 0 behind it.
inline float phongLobe(const ShadingMaterial& m, const glm::vec3& wo, const glm::vec3& n, const glm::vec3& wi) {
    const float c = glm::dot(reflect(wo, n), wi);
    return c > 0.0f ? std::pow(c, m.ns) : 0.0f;
}

// BRDF of the non-delta lobes (Lambert with `albedo`, plus Phong for glossy materials) and the
// pdf of sample() choosing wi, for MIS. cosI = dot(n, wi) must be > 0.
struct Eval {
    glm::vec3 f;
    float pdf;
};
inline Eval evalSmooth(const ShadingMaterial& m, const glm::vec3& albedo, const glm::vec3& n, const glm::vec3& wo,
                       const glm::vec3& wi, float cosI, float diffusePick) {
    Eval e{albedo * kInvPi, diffusePick * cosI * kInvPi};
    if (m.glossy) {
        const float lobe = phongLobe(m, wo, n, wi);
        e.f += m.ks * (m.phongNorm * lobe);
        e.pdf += (1.0f - diffusePick) * m.phongPdfNorm * lobe;
    }
    return e;
}

// Samples the smooth lobes: u.x picks the lobe (and is reused), u.y/uz place the direction.
// Returns false for directions below the surface. pdf as in evalSmooth.
inline bool sampleSmooth(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float lobeU, glm::vec2 u,
                         glm::vec3& wi) {
    if (!m.glossy || lobeU < m.diffuseWeight) {
        wi = sampleCosine(n, u);
        return true;
    }
    // Around the mirror direction: cos(alpha) = u^(1 / (ns + 1)).
    const glm::vec3 r = reflect(wo, n);
    const float cosA = std::pow(u.x, 1.0f / (m.ns + 1.0f));
    const float sinA = std::sqrt(std::max(0.0f, 1.0f - cosA * cosA));
    const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
    glm::vec3 t, b;
    basis(r, t, b);
    wi = (sinA * std::cos(phi)) * t + (sinA * std::sin(phi)) * b + cosA * r;
    return glm::dot(wi, n) > 0.0f;
}

}  // namespace aamap::bsdf
