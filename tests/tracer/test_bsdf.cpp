// The microfacet distributions and Mitsuba's BSDFs (tracer/microfacet.h, tracer/bsdf.h) on their
// own: every sampler against its pdf by a chi-square test over the sphere (as Mitsuba's chi2
// tests), normalisation of D and of the visible-normal pdf, energy (white furnace) bounds,
// reciprocity, and known answers of the Fresnel terms.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tracer/bsdf.h"
#include "tracer/microfacet.h"

namespace aamap {
namespace {

const glm::vec3 kUp(0.0f, 0.0f, 1.0f);

// A fixed-seed generator (splitmix64): the same numbers on every platform.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : state_(seed) {}
    float next() {
        std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        return static_cast<float>(z >> 40) * 0x1.0p-24f;
    }

private:
    std::uint64_t state_;
};

glm::vec3 fromAngles(float cosTheta, float phi) {
    const float s = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    return {s * std::cos(phi), s * std::sin(phi), cosTheta};
}

// Viewer direction at polar angle theta (degrees) and azimuth phi.
glm::vec3 viewAt(float thetaDeg, float phi = 0.3f) { return fromAngles(std::cos(thetaDeg * std::numbers::pi_v<float> / 180.0f), phi); }

// Integral of g over the sphere by the midpoint rule in (cos theta, phi).
template <class G>
double integrateSphere(G&& g, int nCos = 400, int nPhi = 400) {
    double sum = 0.0;
    for (int i = 0; i < nCos; ++i) {
        const float c = -1.0f + 2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(nCos);
        for (int j = 0; j < nPhi; ++j) {
            const float phi = 2.0f * std::numbers::pi_v<float> * (static_cast<float>(j) + 0.5f) / static_cast<float>(nPhi);
            sum += static_cast<double>(g(fromAngles(c, phi)));
        }
    }
    return sum * (2.0 * 2.0 * std::numbers::pi) / (static_cast<double>(nCos) * nPhi);
}

// Upper tail probability of a chi-square statistic with k degrees of freedom (Wilson-Hilferty:
// the cube root of chi2 / k is close to normal; ample for a pass/fail at 1e-3).
double chiSquareTail(double x, int k) {
    const double kk = static_cast<double>(k);
    const double z = (std::cbrt(x / kk) - (1.0 - 2.0 / (9.0 * kk))) / std::sqrt(2.0 / (9.0 * kk));
    return 0.5 * std::erfc(z / std::sqrt(2.0));
}

// Mitsuba's chi2 test: draw `samples` directions, bin them in (theta, phi), and compare the
// counts with the pdf integrated over each bin (sub-sampled midpoint rule in theta and phi, with
// the sin theta Jacobian); cells expecting fewer than 5 samples are pooled. Sample and pdf must
// describe the same density for the test to pass.
template <class Sample, class Pdf>
void expectChiSquareFits(Sample&& sample, Pdf&& pdf, const std::string& what, int samples = 400000) {
    constexpr int nTheta = 40, nPhi = 40, sub = 12;
    std::vector<double> observed(nTheta * nPhi, 0.0), expected(nTheta * nPhi, 0.0);
    const auto cell = [&](const glm::vec3& d) {
        const float theta = std::acos(std::clamp(d.z, -1.0f, 1.0f));
        const int i = std::clamp(static_cast<int>(theta / std::numbers::pi_v<float> * nTheta), 0, nTheta - 1);
        float phi = std::atan2(d.y, d.x);
        if (phi < 0.0f) phi += 2.0f * std::numbers::pi_v<float>;
        const int j = std::clamp(static_cast<int>(phi / (2.0f * std::numbers::pi_v<float>) * nPhi), 0, nPhi - 1);
        return i * nPhi + j;
    };
    Rng rng(0x5eed1234u);
    int valid = 0;
    for (int s = 0; s < samples; ++s) {
        glm::vec3 d;
        if (!sample(rng, d)) continue;
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-3f) << what;
        observed[static_cast<std::size_t>(cell(d))] += 1.0;
        ++valid;
    }
    const double dTheta = std::numbers::pi / (nTheta * sub), dPhi = 2.0 * std::numbers::pi / (nPhi * sub);
    double total = 0.0;
    for (int i = 0; i < nTheta; ++i)
        for (int j = 0; j < nPhi; ++j) {
            double sum = 0.0;
            for (int a = 0; a < sub; ++a) {
                const double theta = (i * sub + a + 0.5) * dTheta;
                const float c = static_cast<float>(std::cos(theta));
                for (int b = 0; b < sub; ++b) {
                    const float phi = static_cast<float>((j * sub + b + 0.5) * dPhi);
                    sum += static_cast<double>(pdf(fromAngles(c, phi))) * std::sin(theta);
                }
            }
            expected[static_cast<std::size_t>(i * nPhi + j)] = sum * dTheta * dPhi * samples;
            total += sum * dTheta * dPhi;
        }
    // The pdf covers what the sampler returns (samples below the surface are rejected, and so
    // missing from both).
    EXPECT_NEAR(total, static_cast<double>(valid) / samples, 0.01) << what << ": pdf mass vs accepted samples";
    std::vector<std::size_t> order(observed.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
    double chi2 = 0.0, pooledObserved = 0.0, pooledExpected = 0.0;
    int dof = -1;
    for (std::size_t idx : order) {
        const double e = expected[idx], o = observed[idx];
        if (e <= 0.0) {
            ASSERT_EQ(o, 0.0) << what << ": samples where the pdf is zero (cell " << idx << ")";
            continue;
        }
        if (e < 5.0 || pooledExpected > 0.0) {  // pool the small cells until they expect 5
            pooledObserved += o;
            pooledExpected += e;
            if (pooledExpected < 5.0) continue;
            chi2 += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
            pooledObserved = pooledExpected = 0.0;
            ++dof;
            continue;
        }
        chi2 += (o - e) * (o - e) / e;
        ++dof;
    }
    ASSERT_GT(dof, 10) << what;
    const double p = chiSquareTail(chi2, dof);
    EXPECT_GT(p, 1e-3) << what << ": chi2 = " << chi2 << " over " << dof << " degrees of freedom";
}

ShadingMaterial conductor(MicrofacetType type, float au, float av, glm::vec3 eta = glm::vec3(0.0f),
                          glm::vec3 k = glm::vec3(1.0f)) {
    ShadingMaterial m;
    m.model = BsdfModel::Conductor;
    m.distribution = type;
    m.alphaU = au;
    m.alphaV = av;
    m.rough = au > 0.0f;
    m.kind = m.rough ? MaterialKind::Diffuse : MaterialKind::Mirror;
    m.glossy = m.rough;
    m.eta = eta;
    m.k = k;
    bsdf::prepareModel(m);
    return m;
}

ShadingMaterial plastic(MicrofacetType type, float alpha, float ior, glm::vec3 kd, bool nonlinear = false) {
    ShadingMaterial m;
    m.model = BsdfModel::Plastic;
    m.distribution = type;
    m.alphaU = m.alphaV = alpha;
    m.rough = alpha > 0.0f;
    m.kind = m.rough ? MaterialKind::Diffuse : MaterialKind::Mirror;
    m.glossy = m.rough;
    m.kd = kd;
    m.diffuse = true;
    m.ior = ior;
    m.nonlinear = nonlinear;
    const float dm = (kd.x + kd.y + kd.z) / 3.0f;
    m.specularWeight = 1.0f / (1.0f + dm);
    bsdf::prepareModel(m);
    return m;
}

// evalSmooth as the path integrator calls it: a smooth (Mirror) model's non-delta lobe is
// sampled with probability 1 - deltaPick.
bsdf::Eval evalAsPath(const ShadingMaterial& m, const glm::vec3& wo, const glm::vec3& wi) {
    const float diffusePick = m.kind == MaterialKind::Mirror ? 1.0f - bsdf::deltaPick(m, wo.z) : 1.0f;
    return bsdf::evalSmooth(m, m.kd, kUp, wo, wi, wi.z, diffusePick);
}

const char* name(MicrofacetType t) { return t == MicrofacetType::GGX ? "ggx" : "beckmann"; }

struct Rough {
    MicrofacetType type;
    float au, av;
};
const Rough kRoughnesses[] = {
    {MicrofacetType::GGX, 0.3f, 0.3f},      {MicrofacetType::GGX, 0.1f, 0.5f},  {MicrofacetType::GGX, 0.8f, 0.8f},
    {MicrofacetType::Beckmann, 0.3f, 0.3f}, {MicrofacetType::Beckmann, 0.5f, 0.15f},
    {MicrofacetType::Beckmann, 0.9f, 0.9f},
};

TEST(Microfacet, DistributionTimesCosineIntegratesToOne) {
    for (const Rough& r : kRoughnesses) {
        const microfacet::Distribution d(r.type, r.au, r.av);
        const double integral = integrateSphere([&](const glm::vec3& m) { return d.D(m) * std::max(m.z, 0.0f); }, 800, 400);
        EXPECT_NEAR(integral, 1.0, 5e-3) << name(r.type) << " " << r.au << " " << r.av;
    }
}

// The visible normals' density D G1 |v.m| / v.z is a density exactly when G1 is Smith's masking
// for D: its integral is 1 for every view.
TEST(Microfacet, VisibleNormalPdfIntegratesToOneForEveryView) {
    for (const Rough& r : kRoughnesses) {
        const microfacet::Distribution d(r.type, r.au, r.av);
        for (float theta : {0.0f, 30.0f, 60.0f, 85.0f}) {
            const glm::vec3 v = viewAt(theta);
            const double integral = integrateSphere([&](const glm::vec3& m) { return d.pdfVisible(v, m); }, 800, 400);
            EXPECT_NEAR(integral, 1.0, 1e-2) << name(r.type) << " alpha " << r.au << "/" << r.av << " theta " << theta;
        }
    }
}

TEST(Microfacet, VisibleNormalSamplingMatchesItsPdf) {
    for (const Rough& r : kRoughnesses) {
        const microfacet::Distribution d(r.type, r.au, r.av);
        for (float theta : {10.0f, 50.0f, 80.0f}) {
            const glm::vec3 v = viewAt(theta);
            expectChiSquareFits(
                [&](Rng& rng, glm::vec3& m) {
                    m = d.sampleVisible(v, {rng.next(), rng.next()});
                    return true;
                },
                [&](const glm::vec3& m) { return d.pdfVisible(v, m); },
                fmt::format("{} alpha {}/{} theta {}", name(r.type), r.au, r.av, theta), 200000);
        }
    }
}

// The sampler a path takes (sampleSmooth) against the pdf MIS uses (evalSmooth), BSDF by BSDF.
void expectBsdfSamplingMatchesPdf(const ShadingMaterial& m, const std::string& what) {
    for (float theta : {5.0f, 45.0f, 75.0f}) {
        const glm::vec3 wo = viewAt(theta, 1.1f);
        expectChiSquareFits(
            [&](Rng& rng, glm::vec3& wi) {
                const float lobe = rng.next();
                const glm::vec2 u(rng.next(), rng.next());
                return bsdf::sampleSmooth(m, kUp, wo, lobe, u, wi) && wi.z > 0.0f;
            },
            [&](const glm::vec3& wi) {
                return wi.z > 0.0f ? evalAsPath(m, wo, wi).pdf : 0.0f;
            },
            fmt::format("{} theta {}", what, theta), 200000);
    }
}

TEST(Bsdf, RoughConductorSamplingMatchesItsPdf) {
    for (const Rough& r : kRoughnesses)
        expectBsdfSamplingMatchesPdf(conductor(r.type, r.au, r.av),
                                     fmt::format("roughconductor {} {}/{}", name(r.type), r.au, r.av));
}

TEST(Bsdf, RoughPlasticSamplingMatchesItsPdf) {
    for (MicrofacetType t : {MicrofacetType::GGX, MicrofacetType::Beckmann})
        for (float alpha : {0.1f, 0.4f})
            expectBsdfSamplingMatchesPdf(plastic(t, alpha, 1.49f, glm::vec3(0.6f, 0.3f, 0.1f)),
                                         fmt::format("roughplastic {} {}", name(t), alpha));
}

// Smooth plastic's non-delta part: the base's cosine lobe, taken with the probability that the
// delta lobe leaves.
TEST(Bsdf, SmoothPlasticDiffuseSamplingMatchesItsPdf) {
    const ShadingMaterial m = plastic(MicrofacetType::Beckmann, 0.0f, 1.5f, glm::vec3(0.5f));
    for (float theta : {5.0f, 60.0f}) {
        const glm::vec3 wo = viewAt(theta);
        const float pick = 1.0f - bsdf::deltaPick(m, wo.z);
        expectChiSquareFits(
            [&](Rng& rng, glm::vec3& wi) { return bsdf::sampleSmooth(m, kUp, wo, rng.next(), {rng.next(), rng.next()}, wi); },
            [&](const glm::vec3& wi) {
                return wi.z > 0.0f ? evalAsPath(m, wo, wi).pdf / pick : 0.0f;
            },
            fmt::format("plastic theta {}", theta), 100000);
    }
}

// Directional albedo: integral of f cos over the sphere for light leaving toward wo (midpoint
// rule in (cos theta, phi) over the upper hemisphere).
glm::vec3 albedo(const ShadingMaterial& m, const glm::vec3& wo, int n = 400) {
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i) {
        const float c = (static_cast<float>(i) + 0.5f) / static_cast<float>(n);
        for (int j = 0; j < 2 * n; ++j) {
            const glm::vec3 wi = fromAngles(c, 2.0f * std::numbers::pi_v<float> * (static_cast<float>(j) + 0.5f) / static_cast<float>(2 * n));
            sum += glm::dvec3(evalAsPath(m, wo, wi).f * wi.z);
        }
    }
    return glm::vec3(sum * (2.0 * std::numbers::pi / (2.0 * n * n)));
}

// The same by importance sampling the BSDF (an independent estimate: f cos / pdf per sample).
glm::vec3 albedoSampled(const ShadingMaterial& m, const glm::vec3& wo, int n = 200000) {
    Rng rng(77);
    glm::vec3 sum(0.0f);
    for (int i = 0; i < n; ++i) {
        glm::vec3 wi;
        const float lobe = rng.next();
        const glm::vec2 u(rng.next(), rng.next());
        if (!bsdf::sampleSmooth(m, kUp, wo, lobe, u, wi) || wi.z <= 0.0f) continue;
        const bsdf::Eval e = evalAsPath(m, wo, wi);
        if (e.pdf > 0.0f) sum += e.f * (wi.z / e.pdf);
    }
    return sum / static_cast<float>(n);
}

// A rough conductor with Fresnel 1 (eta 0, k 1) only loses what single-scattering microfacets
// lose: its albedo is at most 1, near 1 for a smooth-ish surface, falls as roughness and the
// view's angle grow, and the quadrature and importance-sampled estimates agree.
TEST(Bsdf, WhiteRoughConductorLosesOnlyMultipleScattering) {
    for (MicrofacetType t : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
        float previous = 1.0f;
        for (float alpha : {0.05f, 0.2f, 0.5f, 1.0f}) {
            const ShadingMaterial m = conductor(t, alpha, alpha);
            const glm::vec3 wo = viewAt(30.0f);
            const float a = albedoSampled(m, wo).x;
            EXPECT_LE(a, 1.0f + 2e-3f) << name(t) << " alpha " << alpha;
            EXPECT_LE(a, previous + 2e-3f) << name(t) << " alpha " << alpha << ": rougher must not reflect more";
            if (alpha >= 0.2f) {
                EXPECT_NEAR(albedo(m, wo).x, a, 0.01f) << name(t) << " alpha " << alpha;
            }
            previous = a;
            if (alpha <= 0.05f) {
                EXPECT_GT(a, 0.99f) << name(t);
            }
            if (alpha >= 1.0f) {
                EXPECT_LT(a, 0.9f) << name(t) << ": single scattering must lose energy when rough";
            }
            EXPECT_GT(a, 0.2f) << name(t) << " alpha " << alpha;
        }
    }
}

// Mitsuba's blendbsdf: a Lambert and a rough conductor mixed by the weight. Its value and pdf
// are the weighted sums of the components' (so its albedo is theirs mixed, exactly), sampling
// picks a component with its weight (the chi-square test of the mixed pdf), and the quadrature
// and importance-sampled albedos agree.
ShadingMaterial blendOf(const ShadingMaterial& a, const ShadingMaterial& b, float w) {
    ShadingMaterial m;
    m.model = BsdfModel::Blend;
    m.diffuse = true;
    m.blendA = &a;
    m.blendB = &b;
    m.blendWeight = w;
    return m;
}

TEST(Bsdf, BlendIsTheWeightedMixOfItsComponents) {
    ShadingMaterial lambert;
    lambert.kd = glm::vec3(0.8f, 0.5f, 0.2f);
    lambert.diffuse = true;
    const ShadingMaterial metal = conductor(MicrofacetType::GGX, 0.2f, 0.2f);
    for (float w : {0.0f, 0.3f, 1.0f}) {
        const ShadingMaterial m = blendOf(lambert, metal, w);
        for (float theta : {10.0f, 50.0f, 80.0f}) {
            const glm::vec3 wo = viewAt(theta, 0.7f);
            for (int i = 0; i < 16; ++i) {
                const glm::vec3 wi = fromAngles((static_cast<float>(i) + 0.5f) / 16.0f, 0.9f * static_cast<float>(i));
                const bsdf::Eval a = evalAsPath(lambert, wo, wi), b = evalAsPath(metal, wo, wi), e = evalAsPath(m, wo, wi);
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.f[c], (1.0f - w) * a.f[c] + w * b.f[c], 1e-5f * (1.0f + b.f[c]));
                EXPECT_NEAR(e.pdf, (1.0f - w) * a.pdf + w * b.pdf, 1e-5f * (1.0f + b.pdf));
            }
            const glm::vec3 mixed = albedo(m, wo, 150), parts = (1.0f - w) * albedo(lambert, wo, 150) + w * albedo(metal, wo, 150);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(mixed[c], parts[c], 1e-4f);
            const glm::vec3 sampled = albedoSampled(m, wo, 100000);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(sampled[c], mixed[c], 0.01f) << "w " << w << " theta " << theta;
            EXPECT_LE(mixed.x, 1.0f);
        }
    }
}

TEST(Bsdf, BlendSamplingMatchesItsPdf) {
    ShadingMaterial lambert;
    lambert.kd = glm::vec3(0.6f);
    lambert.diffuse = true;
    const ShadingMaterial metal = conductor(MicrofacetType::Beckmann, 0.15f, 0.4f);
    const ShadingMaterial coat = plastic(MicrofacetType::GGX, 0.1f, 1.5f, glm::vec3(0.2f, 0.4f, 0.6f));
    expectBsdfSamplingMatchesPdf(blendOf(lambert, metal, 0.35f), "blend lambert/roughconductor 0.35");
    expectBsdfSamplingMatchesPdf(blendOf(metal, coat, 0.8f), "blend roughconductor/roughplastic 0.8");
}

TEST(Bsdf, WhiteLambertLosesNothing) {
    ShadingMaterial m;
    m.kd = glm::vec3(1.0f);
    m.diffuse = true;
    for (float theta : {0.0f, 70.0f}) EXPECT_NEAR(albedo(m, viewAt(theta)).x, 1.0f, 2e-3f);
}

// Smooth plastic over a white base (linear) conserves energy exactly: what the coating reflects
// plus what the base sends out through it is 1, since the internal and external diffuse Fresnel
// reflectances satisfy 1 - Fdr_int = (1 - Fdr_ext) / eta^2.
TEST(Bsdf, WhiteSmoothPlasticConservesEnergy) {
    for (float ior : {1.3f, 1.5f, 2.0f}) {
        const ShadingMaterial m = plastic(MicrofacetType::Beckmann, 0.0f, ior, glm::vec3(1.0f));
        for (float theta : {0.0f, 45.0f, 80.0f}) {
            const glm::vec3 wo = viewAt(theta);
            const float total = bsdf::deltaReflectance(m, wo.z).x + albedo(m, wo).x;
            EXPECT_NEAR(total, 1.0f, 5e-3f) << "ior " << ior << " theta " << theta;
        }
    }
}

// A rough plastic never reflects more than the smooth one's exact 1 (its coating loses what
// single scattering loses, both ways through it: a lot when very rough, as in Mitsuba), and with
// a black base it reflects at most what its coating does not let through.
TEST(Bsdf, RoughPlasticReflectsAtMostOne) {
    for (MicrofacetType t : {MicrofacetType::GGX, MicrofacetType::Beckmann})
        for (float alpha : {0.05f, 0.3f, 0.7f})
            for (float theta : {0.0f, 60.0f}) {
                const glm::vec3 wo = viewAt(theta);
                const ShadingMaterial white = plastic(t, alpha, 1.5f, glm::vec3(1.0f));
                const float a = albedoSampled(white, wo).x;
                EXPECT_LE(a, 1.0f + 5e-3f) << name(t) << " alpha " << alpha << " theta " << theta;
                const ShadingMaterial black = plastic(t, alpha, 1.5f, glm::vec3(0.0f));
                const float coating = albedo(black, wo).x;
                EXPECT_LE(coating, 1.0f - bsdf::coatingTransmittance(black, wo.z) + 2e-3f)
                    << name(t) << " alpha " << alpha << " theta " << theta;
                EXPECT_GT(coating, 0.02f) << name(t) << " alpha " << alpha << " theta " << theta;
                EXPECT_GT(a, coating) << name(t) << " alpha " << alpha << " theta " << theta << ": a white base adds light";
            }
}

// The smooth dielectric's reflectance and its transmittance computed independently from the
// transmitted amplitudes (flux through the interface: eta cosT / cosI |t|^2) sum to 1.
TEST(Bsdf, SmoothDielectricReflectedPlusTransmittedIsOne) {
    for (float eta : {1.33f, 1.5f, 2.4f, 1.0f / 1.5f})
        for (float c = 0.05f; c <= 1.0f; c += 0.05f) {
            float cosT = 0.0f;
            const float R = bsdf::fresnelDielectric(c, eta, cosT);
            if (R >= 1.0f) continue;  // total internal reflection
            const float ts = 2.0f * c / (c + eta * cosT), tp = 2.0f * c / (eta * c + cosT);
            const float T = eta * cosT / c * 0.5f * (ts * ts + tp * tp);
            EXPECT_NEAR(R + T, 1.0f, 1e-5f) << "eta " << eta << " cos " << c;
        }
}

TEST(Bsdf, ReflectionIsReciprocal) {
    const ShadingMaterial materials[] = {
        conductor(MicrofacetType::GGX, 0.3f, 0.3f, {0.2f, 0.9f, 1.1f}, {3.9f, 2.4f, 2.1f}),
        conductor(MicrofacetType::Beckmann, 0.1f, 0.6f, {1.6f, 0.9f, 0.5f}, {9.2f, 6.3f, 4.8f}),
        plastic(MicrofacetType::GGX, 0.2f, 1.49f, {0.7f, 0.2f, 0.1f}),
        plastic(MicrofacetType::Beckmann, 0.4f, 1.6f, {0.3f, 0.5f, 0.9f}, true),
        plastic(MicrofacetType::Beckmann, 0.0f, 1.5f, {0.5f, 0.5f, 0.5f}),
    };
    Rng rng(99);
    for (const ShadingMaterial& m : materials)
        for (int i = 0; i < 2000; ++i) {
            const glm::vec3 a = fromAngles(rng.next(), 2.0f * std::numbers::pi_v<float> * rng.next());
            const glm::vec3 b = fromAngles(rng.next(), 2.0f * std::numbers::pi_v<float> * rng.next());
            if (a.z < 0.02f || b.z < 0.02f) continue;
            const glm::vec3 fab = evalAsPath(m, a, b).f;
            const glm::vec3 fba = evalAsPath(m, b, a).f;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(fab[c], fba[c], 1e-4f * std::max(1.0f, fab[c])) << "model " << static_cast<int>(m.model);
        }
}

TEST(Bsdf, PdfIntegratesToAtMostOne) {
    const ShadingMaterial materials[] = {
        conductor(MicrofacetType::GGX, 0.5f, 0.5f),
        conductor(MicrofacetType::Beckmann, 0.2f, 0.7f),
        plastic(MicrofacetType::GGX, 0.3f, 1.49f, glm::vec3(0.5f)),
        plastic(MicrofacetType::Beckmann, 0.0f, 1.49f, glm::vec3(0.5f)),
    };
    for (const ShadingMaterial& m : materials)
        for (float theta : {0.0f, 50.0f, 85.0f}) {
            const glm::vec3 wo = viewAt(theta);
            const double mass = integrateSphere(
                [&](const glm::vec3& wi) {
                    return wi.z > 0.0f ? evalAsPath(m, wo, wi).pdf : 0.0f;
                },
                600, 600);
            EXPECT_LE(mass, 1.0 + 5e-3) << "model " << static_cast<int>(m.model) << " theta " << theta;
            EXPECT_GT(mass, 0.05) << "model " << static_cast<int>(m.model) << " theta " << theta;
        }
}

ShadingMaterial roughGlass(MicrofacetType type, float au, float av, float ior) {
    ShadingMaterial m;
    m.kind = MaterialKind::Glass;
    m.model = BsdfModel::Dielectric;
    m.distribution = type;
    m.alphaU = au;
    m.alphaV = av;
    m.rough = true;
    m.ior = ior;
    m.ks = glm::vec3(1.0f);
    return m;
}

// Reflection and refraction through sampled microfacets against their density, entering
// (relative index ior) and leaving (1 / ior, with total internal reflection).
TEST(Bsdf, RoughDielectricSamplingMatchesItsPdf) {
    const Rough cases[] = {{MicrofacetType::GGX, 0.3f, 0.3f}, {MicrofacetType::Beckmann, 0.2f, 0.5f}};
    for (const Rough& r : cases)
        for (float eta : {1.5f, 1.0f / 1.5f}) {
            const ShadingMaterial m = roughGlass(r.type, r.au, r.av, 1.5f);
            for (float theta : {10.0f, 60.0f}) {
                const glm::vec3 wo = viewAt(theta, 0.7f);
                expectChiSquareFits(
                    [&](Rng& rng, glm::vec3& wi) {
                        glm::vec3 weight;
                        bool refracted = false;
                        const float lobe = rng.next();
                        const glm::vec2 u(rng.next(), rng.next());
                        return bsdf::sampleRoughDielectric(m, kUp, wo, eta, lobe, u, wi, weight, refracted);
                    },
                    [&](const glm::vec3& wi) { return bsdf::pdfRoughDielectric(m, kUp, wo, eta, wi); },
                    fmt::format("roughdielectric {} {}/{} eta {} theta {}", name(r.type), r.au, r.av, eta, theta),
                    200000);
            }
        }
}

// White furnace for the rough dielectric: reflected plus refracted energy (the 1 / eta^2 radiance
// scaling undone) is at most 1, and close to the smooth interface's R + T = 1 when nearly smooth.
TEST(Bsdf, RoughDielectricConservesEnergy) {
    for (MicrofacetType t : {MicrofacetType::GGX, MicrofacetType::Beckmann})
        for (float alpha : {0.02f, 0.3f, 0.7f})
            for (float eta : {1.5f, 1.0f / 1.5f})
                for (float theta : {0.0f, 40.0f, 75.0f}) {
                    const ShadingMaterial m = roughGlass(t, alpha, alpha, 1.5f);
                    const glm::vec3 wo = viewAt(theta);
                    Rng rng(5);
                    double sum = 0.0;
                    const int n = 50000;
                    for (int i = 0; i < n; ++i) {
                        glm::vec3 wi, weight;
                        bool refracted = false;
                        const float lobe = rng.next();
                        const glm::vec2 u(rng.next(), rng.next());
                        if (!bsdf::sampleRoughDielectric(m, kUp, wo, eta, lobe, u, wi, weight, refracted)) continue;
                        sum += static_cast<double>(weight.x * (refracted ? eta * eta : 1.0f));
                    }
                    const double e = sum / n;
                    EXPECT_LE(e, 1.0 + 1e-3) << name(t) << " alpha " << alpha << " eta " << eta << " theta " << theta;
                    if (alpha <= 0.02f) {
                        EXPECT_GT(e, 0.99) << name(t) << " eta " << eta << " theta " << theta;
                    }
                    EXPECT_GT(e, 0.3) << name(t) << " alpha " << alpha << " eta " << eta << " theta " << theta;
                }
}

// The rough dielectric's BSDF against its sampler: f |cos| / pdf is the sample's weight, the pdf
// is the sampler's density, reflection is reciprocal, and refraction (with radiance's 1 / eta^2
// in f) obeys the generalised reciprocity f(wo, wi; eta) eta^2 = f(wi, wo; 1 / eta).
TEST(Bsdf, RoughDielectricEvalMatchesItsSampler) {
    const ShadingMaterial m = roughGlass(MicrofacetType::GGX, 0.3f, 0.2f, 1.5f);
    Rng rng(11);
    int checked = 0;
    for (float eta : {1.5f, 1.0f / 1.5f})
        for (int i = 0; i < 4000; ++i) {
            const glm::vec3 wo = fromAngles(0.05f + 0.95f * rng.next(), 2.0f * std::numbers::pi_v<float> * rng.next());
            glm::vec3 wi, weight;
            bool refracted = false;
            const float lobe = rng.next();
            const glm::vec2 u(rng.next(), rng.next());
            if (!bsdf::sampleRoughDielectric(m, kUp, wo, eta, lobe, u, wi, weight, refracted)) continue;
            if (std::abs(wi.z) < 0.02f) continue;
            const bsdf::Eval e = bsdf::evalRoughDielectric(m, kUp, wo, eta, wi);
            ASSERT_GT(e.pdf, 0.0f);
            EXPECT_NEAR(e.pdf, bsdf::pdfRoughDielectric(m, kUp, wo, eta, wi), 1e-4f * e.pdf);
            EXPECT_NEAR(e.f.x * std::abs(wi.z) / e.pdf, weight.x, 2e-3f * std::max(1.0f, weight.x)) << refracted;
            if (refracted) {
                // wi lies below; seen from there (flip the frame), wo is the refracted direction.
                const bsdf::Eval back = bsdf::evalRoughDielectric(m, -kUp, wi, 1.0f / eta, wo);
                EXPECT_NEAR(e.f.x * eta * eta, back.f.x, 2e-3f * std::max(1.0f, back.f.x));
            } else {
                EXPECT_NEAR(e.f.x, bsdf::evalRoughDielectric(m, kUp, wi, eta, wo).f.x, 2e-3f * std::max(1.0f, e.f.x));
            }
            ++checked;
        }
    EXPECT_GT(checked, 5000);
}

// Gold at normal incidence: the complex Fresnel term reduces to ((n-1)^2 + k^2) / ((n+1)^2 + k^2),
// reflects red more than blue, and every conductor reflects everything at grazing incidence.
TEST(Bsdf, ConductorFresnelKnownAnswers) {
    const glm::vec3 eta(0.143036f, 0.375307f, 1.442045f), k(3.982997f, 2.385556f, 1.603359f);  // Au, rgb
    const glm::vec3 f0 = microfacet::fresnelConductor(1.0f, eta, k);
    for (int c = 0; c < 3; ++c) {
        const float n = eta[c], kk = k[c];
        EXPECT_NEAR(f0[c], ((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk), 1e-5f);
        EXPECT_NEAR(microfacet::fresnelConductor(1e-4f, eta[c], k[c]), 1.0f, 1e-2f);
    }
    EXPECT_GT(f0.x, f0.y);
    EXPECT_GT(f0.y, f0.z);
    // With k = 0 it is the dielectric's Fresnel term, at every angle.
    for (float c = 0.05f; c <= 1.0f; c += 0.05f) {
        float cosT = 0.0f;
        EXPECT_NEAR(microfacet::fresnelConductor(c, 1.5f, 0.0f), bsdf::fresnelDielectric(c, 1.5f, cosT), 1e-5f);
    }
    // eta 0, k 1: a perfect mirror at every angle (Mitsuba's material "none").
    for (float c = 0.05f; c <= 1.0f; c += 0.05f) EXPECT_NEAR(microfacet::fresnelConductor(c, 0.0f, 1.0f), 1.0f, 1e-5f);
}

// A rough conductor's lobe at normal view and light is F0 D(n) / (4 cos^2) with G = 1.
TEST(Bsdf, RoughConductorKnownAnswerAtNormalIncidence) {
    const glm::vec3 eta(0.2f, 0.9f, 1.1f), k(3.9f, 2.4f, 2.1f);
    for (MicrofacetType t : {MicrofacetType::GGX, MicrofacetType::Beckmann}) {
        const float alpha = 0.25f;
        const ShadingMaterial m = conductor(t, alpha, alpha, eta, k);
        const glm::vec3 f = bsdf::evalSmooth(m, glm::vec3(0.0f), kUp, kUp, kUp, 1.0f, 0.0f).f;
        const float d = 1.0f / (std::numbers::pi_v<float> * alpha * alpha);  // both distributions peak at 1 / (pi alpha^2)
        const glm::vec3 f0 = microfacet::fresnelConductor(1.0f, eta, k);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], f0[c] * d / 4.0f, 1e-4f * f[c]) << name(t);
    }
}

// The diffuse Fresnel reflectance by quadrature: 0 for index 1, the known limits, and the
// relation between the two sides.
TEST(Bsdf, DiffuseFresnelReflectance) {
    EXPECT_NEAR(microfacet::fresnelDiffuseReflectance(1.0f), 0.0f, 1e-6f);
    for (float eta : {1.2f, 1.5f, 2.0f}) {
        const float outside = microfacet::fresnelDiffuseReflectance(eta);
        const float inside = microfacet::fresnelDiffuseReflectance(1.0f / eta);
        EXPECT_NEAR(1.0f - inside, (1.0f - outside) / (eta * eta), 1e-3f) << eta;
        EXPECT_GT(inside, 1.0f - 1.0f / (eta * eta) - 1e-3f) << eta;  // at least the totally reflected cone
    }
}

}  // namespace
}  // namespace aamap
