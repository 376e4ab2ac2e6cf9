#pragma once
// What the Snapshot's raster can afford of the environment (scene/scene.h EnvironmentLight),
// prepared on the CPU once per scene:
// - its brightest regions as directional lights (a sun in a sky map), which the G-buffer shades
//   and shadows like the scene's own directional lights;
// - the rest as an ambient term: the irradiance of the remaining radiance, projected on the
//   order-2 real spherical harmonics (9 coefficients per channel) and convolved with the cosine
//   lobe (Ramamoorthi & Hanrahan 2001: A0 = pi, A1 = 2 pi / 3, A2 = pi / 4), so that
//   E(n) = sum_i coefficient_i Y_i(n) (glsl/gbuffer.glsl, ambientIrradiance). No occlusion: the
//   ambient light reaches every surface.
// Extracted lights and the residual together hold the map's whole radiance: nothing is counted
// twice, nothing dropped (beyond what 9 coefficients cannot represent).
#include <array>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace aamap::passes {

struct EnvironmentLighting {
    std::array<glm::vec3, 9> irradianceSH{};  // E(n) = sum_i irradianceSH[i] * Y_i(n), in shYlm order
    std::vector<DirectionalLight> lights;     // the extracted regions, brightest first
    // The ambient part's mean radiance (the SH's Y_0 term): the Snapshot's background where no
    // surface is drawn, a flat stand-in for the sky the renders see (exact for a constant one).
    glm::vec3 background{0.0f};
};

// The real SH basis Y_0..Y_8 at unit n: (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1),
// (2,2) with the usual constants (mirrored in glsl/gbuffer.glsl).
std::array<float, 9> shBasis(const glm::vec3& n);

// Up to `maxLights` (>= 0) regions: each grows from the brightest remaining pixel, if that is at
// least 8 times the map's mean luminance (an overcast sky's brightest patch casts no sharp
// shadow, so it stays ambient), over its 8-neighbours (wrapping around in longitude) while they
// are at least a quarter of that pixel's luminance and within 15 degrees of it; its light has the
// region's irradiance (sum of radiance times pixel solid angle) from its luminance-weighted mean
// direction. A constant environment gives no lights and E = pi L.
EnvironmentLighting prepareEnvironmentLighting(const EnvironmentLight& env, int maxLights);

// The ambient irradiance E(n) of the coefficients (the CPU twin of the shader's evaluation).
glm::vec3 ambientIrradiance(const std::array<glm::vec3, 9>& irradianceSH, const glm::vec3& n);

}  // namespace aamap::passes
