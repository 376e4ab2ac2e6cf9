#pragma once
// Scattering at a surface, in world space with unit vectors pointing away from the surface (wo to
// the viewer, wi to the light). Classic materials: Lambert + modified Phong (energy-normalised,
// Lafortune & Willems 1994) for Diffuse; ideal reflection for mirrors; Fresnel dielectric for glass.
// Mitsuba's conductor, roughconductor, plastic and roughplastic (model != Classic) go through the
// same entry points: evalSmooth / sampleSmooth for the non-delta lobes, deltaPick /
// deltaReflectance for the delta one. Kept inline and branch-light: it runs at every path vertex.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "tracer/embree_scene.h"
#include "tracer/microfacet.h"

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

struct Eval {
    glm::vec3 f;
    float pdf;
};

// A glossy lobe's width as a GGX alpha: a microfacet lobe's own (the geometric mean of alpha_u and
// alpha_v), a Phong exponent n as sqrt(2 / (n + 2)) (the correspondence of Walter et al. 2007).
inline float lobeAlpha(const ShadingMaterial& m) {
    if (m.model == BsdfModel::Classic) return std::sqrt(2.0f / (std::max(m.ns, 0.0f) + 2.0f));
    return std::sqrt(m.alphaU * m.alphaV);
}

// ---- Mitsuba's BSDFs (model != Classic), in the shading frame of n ----

// The local frame: x along the tangent (alpha_u), y the bitangent (alpha_v), z = n.
struct Frame {
    glm::vec3 t, b, n;
    explicit Frame(const glm::vec3& normal) : n(normal) { basis(normal, t, b); }
    glm::vec3 toLocal(const glm::vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
    glm::vec3 toWorld(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

inline microfacet::Distribution distributionOf(const ShadingMaterial& m) {
    return {m.distribution, m.alphaU, m.alphaV};
}

inline float dielectricReflectance(float cosI, float eta) {
    float cosT = 0.0f;
    return microfacet::fresnelDielectricSigned(cosI, eta, cosT);
}

// Rough plastic: the coating's transmittance at view cosine c, interpolated in the table.
inline float coatingTransmittance(const ShadingMaterial& m, float c) {
    constexpr int n = ShadingMaterial::kTransmittanceRes;
    const float x = std::clamp(c, 0.0f, 1.0f) * static_cast<float>(n - 1);
    const int i = std::min(static_cast<int>(x), n - 2);
    const float f = x - static_cast<float>(i);
    return m.transmittance[i] * (1.0f - f) + m.transmittance[i + 1] * f;
}

// Plastic: the probability of sampling the coating's reflection rather than the base, for a view
// at cosine cosO: what each would return, weighted by specular vs diffuse albedo (as Mitsuba).
inline float plasticSpecularPick(const ShadingMaterial& m, float cosO) {
    const float t = m.rough ? coatingTransmittance(m, cosO) : 1.0f - dielectricReflectance(cosO, m.ior);
    const float ps = (1.0f - t) * m.specularWeight, pd = t * (1.0f - m.specularWeight);
    return ps + pd > 0.0f ? ps / (ps + pd) : 0.0f;
}

// Plastic: the diffuse base's albedo after the light it sends up and the coating reflects back
// down (a geometric series in the coating's internal reflectance); `nonlinear` lets the base's
// colour take part in every bounce, which saturates it.
inline glm::vec3 plasticBase(const ShadingMaterial& m, const glm::vec3& albedo) {
    return m.nonlinear ? albedo / (1.0f - albedo * m.internalReflectance) : albedo / (1.0f - m.internalReflectance);
}

inline Eval evalBlend(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi);
inline bool sampleBlend(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float lobeU, glm::vec2 u,
                        glm::vec3& wi);

// The non-delta lobes split in two, the one interface every mode evaluates: `diffuse` (Lambert,
// a plastic's base, a blend as a whole) and `glossy` (Phong, the microfacet lobes of a rough
// conductor or a rough plastic's coating) with glossyPdf, the density of sampleGlossy choosing wi
// (solid angle). Direct and cache modes light-sample both and BSDF-sample the glossy one
// (docs/tracer.md, "Glossy lobes in direct and cache modes"); path mode sums them (evalSmooth).
struct Lobes {
    glm::vec3 diffuse{0.0f}, glossy{0.0f};
    float glossyPdf = 0.0f;
};

inline Lobes evalLobes(const ShadingMaterial& m, const glm::vec3& albedo, const glm::vec3& n, const glm::vec3& wo,
                       const glm::vec3& wi) {
    Lobes e;
    if (m.model == BsdfModel::Classic) {
        e.diffuse = albedo * kInvPi;
        if (m.glossy) {
            const float lobe = phongLobe(m, wo, n, wi);
            e.glossy = m.ks * (m.phongNorm * lobe);
            e.glossyPdf = m.phongPdfNorm * lobe;
        }
        return e;
    }
    if (m.model == BsdfModel::Blend) {
        e.diffuse = evalBlend(m, n, wo, wi).f;
        return e;
    }
    const Frame frame(n);
    const glm::vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
    if (!(lo.z > 0.0f) || !(li.z > 0.0f)) return e;
    const bool plastic = m.model == BsdfModel::Plastic;
    if (m.rough) {
        const microfacet::Distribution dist = distributionOf(m);
        const glm::vec3 h = glm::normalize(lo + li);
        const float D = dist.D(h);
        const float g1o = dist.G1(lo, h);
        const float G = g1o * dist.G1(li, h);
        const float cosH = glm::dot(lo, h);
        const glm::vec3 F = plastic ? glm::vec3(dielectricReflectance(cosH, m.ior)) : microfacet::fresnelConductor(cosH, m.eta, m.k);
        e.glossy = m.specularTint * F * (D * G / (4.0f * lo.z * li.z));
        e.glossyPdf = D * g1o / (4.0f * lo.z);
    }
    if (plastic) {
        const float tO = m.rough ? coatingTransmittance(m, lo.z) : 1.0f - dielectricReflectance(lo.z, m.ior);
        const float tI = m.rough ? coatingTransmittance(m, li.z) : 1.0f - dielectricReflectance(li.z, m.ior);
        e.diffuse = plasticBase(m, albedo) * (kInvPi * tO * tI / (m.ior * m.ior));
    }
    return e;
}

// Samples the glossy lobe alone (Lobes::glossyPdf): the Phong lobe about the mirror direction
// (cos(alpha) = u^(1 / (ns + 1))), or a visible microfacet normal. False where there is none or
// the direction is lost below the surface.
inline bool sampleGlossy(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, glm::vec2 u, glm::vec3& wi) {
    if (!m.glossy) return false;
    if (m.model == BsdfModel::Classic) {
        const glm::vec3 r = reflect(wo, n);
        const float cosA = std::pow(u.x, 1.0f / (m.ns + 1.0f));
        const float sinA = std::sqrt(std::max(0.0f, 1.0f - cosA * cosA));
        const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
        glm::vec3 t, b;
        basis(r, t, b);
        wi = (sinA * std::cos(phi)) * t + (sinA * std::sin(phi)) * b + cosA * r;
        return glm::dot(wi, n) > 0.0f;
    }
    const Frame frame(n);
    const glm::vec3 lo = frame.toLocal(wo);
    if (!(lo.z > 0.0f) || !m.rough) return false;
    const glm::vec3 h = distributionOf(m).sampleVisible(lo, u);
    const glm::vec3 li = (2.0f * glm::dot(lo, h)) * h - lo;
    if (!(li.z > 0.0f)) return false;
    wi = frame.toWorld(li);
    return true;
}

// The Mitsuba models' non-delta lobes (evalLobes summed) and the pdf of sampleModel choosing wi.
// A smooth plastic's only non-delta lobe is its base: its pdf is diffusePick cos / pi,
// diffusePick the caller's probability of sampling it (path mode: 1 - deltaPick).
inline Eval evalModel(const ShadingMaterial& m, const glm::vec3& albedo, const glm::vec3& n, const glm::vec3& wo,
                      const glm::vec3& wi, float diffusePick = 1.0f) {
    if (m.model == BsdfModel::Blend) return evalBlend(m, n, wo, wi);
    const Lobes lobes = evalLobes(m, albedo, n, wo, wi);
    const float cosO = glm::dot(n, wo), cosI = glm::dot(n, wi);
    Eval e{glm::vec3(0.0f), 0.0f};
    if (!(cosO > 0.0f) || !(cosI > 0.0f)) return e;
    const bool plastic = m.model == BsdfModel::Plastic;
    const float pickSpecular = !plastic ? 1.0f : m.rough ? plasticSpecularPick(m, cosO) : 1.0f - diffusePick;
    e.f = lobes.glossy + lobes.diffuse;
    e.pdf = pickSpecular * lobes.glossyPdf;
    if (plastic) e.pdf += (1.0f - pickSpecular) * cosI * kInvPi;
    return e;
}

// Samples evalModel's lobes: lobeU picks coating or base (plastic), u places the direction.
inline bool sampleModel(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float lobeU, glm::vec2 u,
                        glm::vec3& wi) {
    if (m.model == BsdfModel::Blend) return sampleBlend(m, n, wo, lobeU, u, wi);
    const float cosO = glm::dot(n, wo);
    if (!(cosO > 0.0f)) return false;
    const bool specular = m.rough && (m.model != BsdfModel::Plastic || lobeU < plasticSpecularPick(m, cosO));
    if (!specular) {
        wi = sampleCosine(n, u);
        return true;
    }
    return sampleGlossy(m, n, wo, u, wi);
}

// The delta lobe: the probability that a path takes it (the rest goes to the non-delta lobes)
// and its reflectance (to be divided by that probability). cosO = dot(n, wo).
inline float deltaPick(const ShadingMaterial& m, float cosO) {
    switch (m.model) {
        case BsdfModel::Conductor: return 1.0f;
        case BsdfModel::Plastic: return plasticSpecularPick(m, cosO);
        default: {
            const float sp = luminance(m.ks), dl = m.diffuse ? luminance(m.kd) : 0.0f;
            return sp + dl > 0.0f ? sp / (sp + dl) : 1.0f;
        }
    }
}
inline glm::vec3 deltaReflectance(const ShadingMaterial& m, float cosO) {
    switch (m.model) {
        case BsdfModel::Conductor: return m.specularTint * microfacet::fresnelConductor(cosO, m.eta, m.k);
        case BsdfModel::Plastic: return m.specularTint * dielectricReflectance(cosO, m.ior);
        default: return m.ks;
    }
}

// The albedo a Lambert surface would need to send the same light toward wo under uniform
// irradiance (for the irradiance cache, which stores irradiance only): the base's light through
// the coating at wo and, averaged, at arrival. Classic: the albedo itself.
inline glm::vec3 lambertEquivalent(const ShadingMaterial& m, const glm::vec3& albedo, float cosO) {
    if (m.model != BsdfModel::Plastic) return albedo;
    cosO = std::clamp(cosO, 0.0f, 1.0f);  // an interpolated normal may face slightly away
    const float tO = m.rough ? coatingTransmittance(m, cosO) : 1.0f - dielectricReflectance(cosO, m.ior);
    return plasticBase(m, albedo) * (tO * m.meanExitTransmittance / (m.ior * m.ior));
}

// Fills the plastic coating's tables from its distribution and ior (once per material): the
// transmittance into the base by view angle and the base's internal reflectance, both with
// single-scattering microfacets as Mitsuba's roughplastic has them (quadrature over the
// visible-normal sample square).
inline void prepareModel(ShadingMaterial& m) {
    if (m.model != BsdfModel::Plastic) return;
    constexpr int res = ShadingMaterial::kTransmittanceRes;
    if (!m.rough) {
        m.internalReflectance = microfacet::fresnelDiffuseReflectance(1.0f / m.ior);
        m.meanExitTransmittance = 1.0f - microfacet::fresnelDiffuseReflectance(m.ior);
        return;
    }
    const microfacet::Distribution dist = distributionOf(m);
    const auto integrate = [&](float mu, bool inside) { return microfacet::coatingScattering(dist, m.ior, mu, inside); };
    double inside = 0.0, outside = 0.0;
    for (int i = 0; i < res; ++i) {
        const float mu = std::max(1e-6f, static_cast<float>(i) / static_cast<float>(res - 1));
        m.transmittance[static_cast<std::size_t>(i)] = integrate(mu, false);
        inside += static_cast<double>(integrate(mu, true) * mu);
        outside += static_cast<double>(m.transmittance[static_cast<std::size_t>(i)] * mu);
    }
    m.internalReflectance = static_cast<float>(2.0 * inside / res);
    m.meanExitTransmittance = static_cast<float>(2.0 * outside / res);
}

// ---- Rough dielectric (Mitsuba's roughdielectric): microfacet reflection and refraction ----
// In the frame of n on the viewer's side (so wo.z > 0); etaRel is the index across the surface
// over the index on wo's side (ior from the front, 1 / ior from the back).

// Samples a direction as Mitsuba's sampler does: a visible normal m, then reflection with the
// Fresnel probability F(wo.m), else refraction through m. weight = f cos / pdf: G1(wi, m) times
// the lobe's tint, and 1 / etaRel^2 on refraction (radiance is compressed into the denser medium,
// as the smooth dielectric). Returns false where the direction is lost (below / above the surface).
inline bool sampleRoughDielectric(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float etaRel,
                                  float lobeU, glm::vec2 u, glm::vec3& wi, glm::vec3& weight, bool& refracted) {
    const Frame frame(n);
    const glm::vec3 lo = frame.toLocal(wo);
    if (!(lo.z > 0.0f)) return false;
    const microfacet::Distribution dist = distributionOf(m);
    const glm::vec3 h = dist.sampleVisible(lo, u);
    const float c = glm::dot(lo, h);
    float cosT = 0.0f;
    const float F = microfacet::fresnelDielectricSigned(c, etaRel, cosT);
    glm::vec3 li;
    refracted = !(lobeU < F);
    if (!refracted) {
        li = (2.0f * c) * h - lo;
        if (!(li.z > 0.0f)) return false;
        weight = m.specularTint * dist.G1(li, h);
    } else {
        const float e = 1.0f / etaRel;
        li = h * (c * e + cosT) - lo * e;
        if (!(li.z < 0.0f)) return false;
        weight = m.ks * (dist.G1(li, h) / (etaRel * etaRel));
    }
    wi = frame.toWorld(glm::normalize(li));
    return true;
}

// The density of sampleRoughDielectric choosing wi (solid angle), in the same frame.
inline float pdfRoughDielectric(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float etaRel,
                                const glm::vec3& wi) {
    const Frame frame(n);
    const glm::vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
    if (!(lo.z > 0.0f) || li.z == 0.0f) return 0.0f;
    const microfacet::Distribution dist = distributionOf(m);
    const bool reflected = li.z > 0.0f;
    // The (generalised) half vector, on the viewer's side.
    glm::vec3 h = reflected ? lo + li : lo + etaRel * li;
    const float len = glm::length(h);
    if (!(len > 0.0f)) return 0.0f;
    h /= len;
    if (h.z < 0.0f) h = -h;
    const float co = glm::dot(lo, h), ci = glm::dot(li, h);
    if (!(co > 0.0f) || (reflected ? !(ci > 0.0f) : !(ci < 0.0f))) return 0.0f;
    float cosT = 0.0f;
    const float F = microfacet::fresnelDielectricSigned(co, etaRel, cosT);
    const float visible = dist.D(h) * dist.G1(lo, h) * co / lo.z;
    if (reflected) return F * visible / (4.0f * ci);
    const float d = co + etaRel * ci;
    return (1.0f - F) * visible * etaRel * etaRel * std::abs(ci) / (d * d);
}

// The rough dielectric's BSDF (reflection for wi on wo's side, refraction through it, the
// latter with the 1 / etaRel^2 radiance scaling) and pdfRoughDielectric, so that
// f |cos_i| / pdf is sampleRoughDielectric's weight.
inline Eval evalRoughDielectric(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float etaRel,
                                const glm::vec3& wi) {
    const Frame frame(n);
    const glm::vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
    Eval e{glm::vec3(0.0f), 0.0f};
    if (!(lo.z > 0.0f) || li.z == 0.0f) return e;
    const microfacet::Distribution dist = distributionOf(m);
    const bool reflected = li.z > 0.0f;
    glm::vec3 h = reflected ? lo + li : lo + etaRel * li;
    const float len = glm::length(h);
    if (!(len > 0.0f)) return e;
    h /= len;
    if (h.z < 0.0f) h = -h;
    const float co = glm::dot(lo, h), ci = glm::dot(li, h);
    if (!(co > 0.0f) || (reflected ? !(ci > 0.0f) : !(ci < 0.0f))) return e;
    float cosT = 0.0f;
    const float F = microfacet::fresnelDielectricSigned(co, etaRel, cosT);
    const float D = dist.D(h), g1o = dist.G1(lo, h), G = g1o * dist.G1(li, h);
    const float visible = D * g1o * co / lo.z;
    if (reflected) {
        e.f = m.specularTint * (F * D * G / (4.0f * lo.z * li.z));
        e.pdf = F * visible / (4.0f * ci);
    } else {
        const float d = co + etaRel * ci;
        e.f = m.ks * ((1.0f - F) * D * G * co * std::abs(ci) / (d * d * lo.z * std::abs(li.z)));
        e.pdf = (1.0f - F) * visible * etaRel * etaRel * std::abs(ci) / (d * d);
    }
    return e;
}

// BRDF of the non-delta lobes (Lambert with `albedo`, plus Phong for glossy materials; the
// Mitsuba models' own lobes) and the pdf of sampleSmooth choosing wi, for MIS. cosI = dot(n, wi)
// must be > 0.
inline Eval evalSmooth(const ShadingMaterial& m, const glm::vec3& albedo, const glm::vec3& n, const glm::vec3& wo,
                       const glm::vec3& wi, float cosI, float diffusePick) {
    if (m.model != BsdfModel::Classic) return evalModel(m, albedo, n, wo, wi, diffusePick);
    const Lobes lobes = evalLobes(m, albedo, n, wo, wi);
    return {lobes.diffuse + lobes.glossy, diffusePick * cosI * kInvPi + (1.0f - diffusePick) * lobes.glossyPdf};
}

// Samples the smooth lobes: lobeU picks the lobe (Lambert or glossy), u places the direction.
// Returns false for directions below the surface. pdf as in evalSmooth.
inline bool sampleSmooth(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float lobeU, glm::vec2 u,
                         glm::vec3& wi) {
    if (m.model != BsdfModel::Classic) return sampleModel(m, n, wo, lobeU, u, wi);
    if (!m.glossy || lobeU < m.diffuseWeight) {
        wi = sampleCosine(n, u);
        return true;
    }
    return sampleGlossy(m, n, wo, u, wi);
}

// ---- Blend (Mitsuba's blendbsdf): the components' BSDFs and pdfs mixed by the weight, and
// sampling that picks a component with its weight (so the mixed pdf is sampleBlend's density).

// A component's own choice between its Lambert and Phong lobes (Classic glossy), else 1.
inline float componentDiffusePick(const ShadingMaterial& c) {
    return c.model == BsdfModel::Classic && c.glossy ? c.diffuseWeight : 1.0f;
}

inline Eval evalBlend(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, const glm::vec3& wi) {
    Eval e{glm::vec3(0.0f), 0.0f};
    const float cosI = glm::dot(n, wi);
    if (!(cosI > 0.0f) || !(glm::dot(n, wo) > 0.0f)) return e;
    const float w = m.blendWeight;
    const ShadingMaterial* parts[2] = {m.blendA, m.blendB};
    const float weights[2] = {1.0f - w, w};
    for (int k = 0; k < 2; ++k) {
        if (!(weights[k] > 0.0f)) continue;
        const ShadingMaterial& c = *parts[k];
        if (!c.diffuse && !c.glossy) continue;  // black
        const Eval ec = evalSmooth(c, c.kd, n, wo, wi, cosI, componentDiffusePick(c));
        e.f += weights[k] * ec.f;
        e.pdf += weights[k] * ec.pdf;
    }
    return e;
}

inline bool sampleBlend(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& wo, float lobeU, glm::vec2 u,
                        glm::vec3& wi) {
    const float w = m.blendWeight;
    // lobeU picks the component, then, rescaled to [0, 1), the component's own lobe.
    const bool second = lobeU >= 1.0f - w;
    const float rest = second ? (lobeU - (1.0f - w)) / w : lobeU / (1.0f - w);
    const ShadingMaterial& c = second ? *m.blendB : *m.blendA;
    if (!c.diffuse && !c.glossy) return false;
    if (!sampleSmooth(c, n, wo, std::min(rest, 0.99999994f), u, wi)) return false;
    return glm::dot(wi, n) > 0.0f;
}

}  // namespace aamap::bsdf
