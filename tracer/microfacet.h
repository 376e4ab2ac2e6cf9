#pragma once
// Microfacet normal distributions as Mitsuba 3 defines them: Beckmann and GGX (Trowbridge-Reitz),
// anisotropic with roughness alpha_u along the tangent (local x) and alpha_v along the bitangent
// (local y), Smith's separable masking-shadowing, and sampling of the visible normals.
//
// Everything here is in the local shading frame: z is the surface normal. Directions point away
// from the surface. Beckmann's G1 is the exact Smith term (erf), not a rational fit, so the
// visible-normal pdf D G1 |v.m| / v.z integrates to exactly one.
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap::microfacet {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kInvSqrtPi = 0.5641895835477563f;
// Mitsuba clamps roughness to this: an exactly zero alpha has no finite D.
constexpr float kMinAlpha = 1e-4f;

// Inverse error function (Giles 2010, single-precision polynomial fit); |x| < 1.
inline float erfinv(float x) {
    float w = -std::log((1.0f - x) * (1.0f + x));
    float p;
    if (w < 5.0f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

struct Distribution {
    MicrofacetType type = MicrofacetType::Beckmann;
    float alphaU = 0.1f, alphaV = 0.1f;

    Distribution() = default;
    Distribution(MicrofacetType t, float au, float av)
        : type(t), alphaU(std::max(au, kMinAlpha)), alphaV(std::max(av, kMinAlpha)) {}

    // Normal distribution D(m), normalised so that the integral of D(m) m.z over the hemisphere is 1.
    float D(const glm::vec3& m) const {
        if (m.z <= 0.0f) return 0.0f;
        const float cos2 = m.z * m.z;
        const float x = m.x / alphaU, y = m.y / alphaV;
        float d;
        if (type == MicrofacetType::Beckmann) {
            d = std::exp(-(x * x + y * y) / cos2) / (kPi * alphaU * alphaV * cos2 * cos2);
        } else {
            const float s = x * x + y * y + cos2;
            d = 1.0f / (kPi * alphaU * alphaV * s * s);
        }
        // Far in the tail the value is only rounding noise (Mitsuba cuts it too).
        return d * m.z > 1e-20f ? d : 0.0f;
    }

    // Smith's Lambda for direction v (the shadowed fraction's ratio); v.z != 0.
    float lambda(const glm::vec3& v) const {
        const float xy2 = (alphaU * v.x) * (alphaU * v.x) + (alphaV * v.y) * (alphaV * v.y);
        if (xy2 <= 0.0f) return 0.0f;
        const float tan2 = xy2 / (v.z * v.z);  // tan^2(theta) times the projected alpha^2
        if (type == MicrofacetType::GGX) return 0.5f * (std::sqrt(1.0f + tan2) - 1.0f);
        const float a = 1.0f / std::sqrt(tan2);
        return 0.5f * (std::erf(a) - 1.0f) + std::exp(-a * a) * kInvSqrtPi / (2.0f * a);
    }

    // Masking of direction v by microfacets with normal m: 0 where v sees m's back (or the other
    // side of the macro-surface than m's front would need).
    float G1(const glm::vec3& v, const glm::vec3& m) const {
        if (glm::dot(v, m) * v.z <= 0.0f) return 0.0f;
        return 1.0f / (1.0f + lambda(v));
    }

    // Separable masking-shadowing, as Mitsuba's G.
    float G(const glm::vec3& wi, const glm::vec3& wo, const glm::vec3& m) const { return G1(wi, m) * G1(wo, m); }

    // Density of sampleVisible choosing normal m, as seen from v (v.z > 0): D(m) G1(v, m) |v.m| / v.z.
    float pdfVisible(const glm::vec3& v, const glm::vec3& m) const {
        if (v.z <= 0.0f) return 0.0f;
        return D(m) * G1(v, m) * std::abs(glm::dot(v, m)) / v.z;
    }

    // A microfacet normal distributed as the normals visible from v (v.z > 0), density pdfVisible.
    glm::vec3 sampleVisible(const glm::vec3& v, glm::vec2 u) const {
        return type == MicrofacetType::GGX ? sampleVisibleGgx(v, u) : sampleVisibleBeckmann(v, u);
    }

private:
    // Heitz 2018: in the stretched configuration (alpha = 1) the visible normals project to a disk
    // whose far half is squashed by the view's cosine; sample it and lift onto the hemisphere.
    glm::vec3 sampleVisibleGgx(const glm::vec3& v, glm::vec2 u) const {
        const glm::vec3 vh = glm::normalize(glm::vec3(alphaU * v.x, alphaV * v.y, v.z));
        const float len2 = vh.x * vh.x + vh.y * vh.y;
        const glm::vec3 t1 = len2 > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : glm::vec3(1.0f, 0.0f, 0.0f);
        const glm::vec3 t2 = glm::cross(vh, t1);
        const float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
        const float p1 = r * std::cos(phi);
        float p2 = r * std::sin(phi);
        const float s = 0.5f * (1.0f + vh.z);
        p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
        const glm::vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
        return glm::normalize(glm::vec3(alphaU * nh.x, alphaV * nh.y, std::max(1e-6f, nh.z)));
    }

    // Visible slopes of the alpha = 1 Beckmann surface seen at cosine cosTheta: the x slope by
    // inverting its CDF numerically (an analytic first guess, then Newton steps in the erf
    // domain, Jakob 2014), the y slope a plain Gaussian.
    static glm::vec2 sampleSlopesBeckmann(float cosTheta, glm::vec2 u) {
        const float tanTheta = std::max(std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta)) / cosTheta, 1e-7f);
        const float cotTheta = 1.0f / tanTheta;
        const float maxval = std::erf(cotTheta);
        u = glm::clamp(u, glm::vec2(1e-6f), glm::vec2(1.0f - 1e-6f));
        // The guess is exact for grazing views, the hardest case.
        float x = maxval - (maxval + 1.0f) * std::erf(std::sqrt(-std::log(u.x)));
        const float target = u.x * (1.0f + maxval + kInvSqrtPi * tanTheta * std::exp(-cotTheta * cotTheta));
        for (int i = 0; i < 3; ++i) {
            const float slope = erfinv(x);
            const float value = 1.0f + x + kInvSqrtPi * tanTheta * std::exp(-slope * slope) - target;
            const float derivative = 1.0f - slope * tanTheta;
            x = std::clamp(x - value / derivative, -1.0f + 1e-7f, 1.0f - 1e-7f);
        }
        return {erfinv(x), erfinv(2.0f * u.y - 1.0f)};
    }

    glm::vec3 sampleVisibleBeckmann(const glm::vec3& v, glm::vec2 u) const {
        // Stretch the view to the alpha = 1 configuration, sample slopes there, rotate them to the
        // view's azimuth and unstretch.
        const glm::vec3 vs = glm::normalize(glm::vec3(alphaU * v.x, alphaV * v.y, v.z));
        const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - vs.z * vs.z));
        const float cosPhi = sinTheta > 0.0f ? std::clamp(vs.x / sinTheta, -1.0f, 1.0f) : 1.0f;
        const float sinPhi = sinTheta > 0.0f ? std::clamp(vs.y / sinTheta, -1.0f, 1.0f) : 0.0f;
        const glm::vec2 s = sampleSlopesBeckmann(vs.z, u);
        const float sx = (cosPhi * s.x - sinPhi * s.y) * alphaU;
        const float sy = (sinPhi * s.x + cosPhi * s.y) * alphaV;
        return glm::normalize(glm::vec3(-sx, -sy, 1.0f));
    }
};

// Unpolarised Fresnel reflectance of a conductor with complex relative index eta + i k, for light
// at cosine cosI (> 0) on the outside. Exact (complex refraction angle), not Schlick.
inline float fresnelConductor(float cosI, float eta, float k) {
    using C = std::complex<float>;
    cosI = std::clamp(cosI, 0.0f, 1.0f);
    const C n(eta, k);
    const float sin2 = 1.0f - cosI * cosI;
    const C cosT = std::sqrt(C(1.0f) - C(sin2) / (n * n));
    const C rs = (C(cosI) - n * cosT) / (C(cosI) + n * cosT);
    const C rp = (n * C(cosI) - cosT) / (n * C(cosI) + cosT);
    return 0.5f * (std::norm(rs) + std::norm(rp));
}

inline glm::vec3 fresnelConductor(float cosI, const glm::vec3& eta, const glm::vec3& k) {
    return {fresnelConductor(cosI, eta.x, k.x), fresnelConductor(cosI, eta.y, k.y), fresnelConductor(cosI, eta.z, k.z)};
}

// Dielectric Fresnel reflectance for either side: cosI < 0 means the light arrives from inside
// (relative index 1 / eta). Sets cosT to the refracted cosine, signed opposite to cosI (0 on total
// internal reflection). eta = interior / exterior index.
inline float fresnelDielectricSigned(float cosI, float eta, float& cosT) {
    const bool outside = cosI >= 0.0f;
    const float e = outside ? eta : 1.0f / eta;
    const float c = std::min(std::abs(cosI), 1.0f);
    const float sin2T = (1.0f - c * c) / (e * e);
    if (sin2T >= 1.0f) {
        cosT = 0.0f;
        return 1.0f;
    }
    const float ct = std::sqrt(1.0f - sin2T);
    const float rs = (c - e * ct) / (c + e * ct);
    const float rp = (e * c - ct) / (e * c + ct);
    cosT = outside ? -ct : ct;
    return 0.5f * (rs * rs + rp * rp);
}

// A rough dielectric coating (relative index eta, the distribution's roughness) seen along a
// direction at cosine mu, single scattering: from outside, the share it lets through; from inside
// (inside = true; relative index 1 / eta, total internal reflection), the share it reflects back
// down. By quadrature over the visible-normal sample square (32 x 32: within 0.2 % of 64,
// tests/tracer/test_bsdf.cpp checks the energy it implies). Rough plastic's tables (tracer/bsdf.h
// prepareModel) and the Snapshot's plastic base (passes/scene_gpu.cpp) are built from it.
inline float coatingScattering(const Distribution& dist, float eta, float mu, bool inside) {
    constexpr int q = 32;
    const glm::vec3 v(std::sqrt(std::max(0.0f, 1.0f - mu * mu)), 0.0f, mu);
    const float e = inside ? 1.0f / eta : eta;
    double sum = 0.0;
    for (int j = 0; j < q; ++j)
        for (int i = 0; i < q; ++i) {
            const glm::vec2 u((static_cast<float>(i) + 0.5f) / q, (static_cast<float>(j) + 0.5f) / q);
            const glm::vec3 h = dist.sampleVisible(v, u);
            const float c = glm::dot(v, h);
            float cosT = 0.0f;
            const float F = fresnelDielectricSigned(c, e, cosT);
            if (inside) {  // what the coating reflects back down
                const glm::vec3 r = (2.0f * c) * h - v;
                if (r.z > 0.0f) sum += static_cast<double>(F * dist.G1(r, h));
            } else {  // what it lets through
                const float ie = 1.0f / e;
                const glm::vec3 t = h * (c * ie + cosT) - v * ie;
                if (t.z < 0.0f && F < 1.0f) sum += static_cast<double>((1.0f - F) * dist.G1(t, h));
            }
        }
    return static_cast<float>(sum / (q * q));
}

// The hemispherical average 2 * integral of coatingScattering(mu) mu dmu over res cosines
// i / (res - 1) (the tables' points), e.g. a rough coating's internal reflectance (inside).
inline float coatingHemisphericalAverage(const Distribution& dist, float eta, bool inside, int res = 64) {
    double sum = 0.0;
    for (int i = 0; i < res; ++i) {
        const float mu = std::max(1e-6f, static_cast<float>(i) / static_cast<float>(res - 1));
        sum += static_cast<double>(coatingScattering(dist, eta, mu, inside) * mu);
    }
    return static_cast<float>(2.0 * sum / res);
}

// Hemispherical average 2 * integral of F(mu) mu dmu of the dielectric Fresnel reflectance, for
// light arriving from the side where the relative index is eta (Mitsuba's fresnel_diffuse_
// reflectance; here by quadrature instead of its polynomial fit).
inline float fresnelDiffuseReflectance(float eta) {
    constexpr int kSteps = 2048;
    double sum = 0.0;
    for (int i = 0; i < kSteps; ++i) {
        const float mu = (static_cast<float>(i) + 0.5f) / kSteps;
        float cosT = 0.0f;
        sum += static_cast<double>(fresnelDielectricSigned(mu, eta, cosT)) * mu;
    }
    return static_cast<float>(2.0 * sum / kSteps);
}

}  // namespace aamap::microfacet
