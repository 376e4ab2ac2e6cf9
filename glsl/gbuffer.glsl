// The Snapshot's shading, included by gbuffer.frag (no shadows) and gbuffer.shadowed.frag
// (GBUFFER_SHADOWS: per-light visibility from the shadow cube maps), and by their textured
// variants gbuffer.textured*.frag (GBUFFER_TEXTURED: atlas lookup and alpha test), and the mirror
// variants gbuffer.mirror*.frag (GBUFFER_MIRROR: the clip plane of a reflected view), and the
// variants *.grey.frag (GBUFFER_GREY: also the greyscale of step 1 of the aamap, a second
// attachment, so that the luminance pass is not needed), and gbuffer.glass.frag (GBUFFER_GLASS:
// glass drawn over what it shows, see main). Variants rather than branches, so that
// a scene without lights or textures has no binding to fill for them.
//
// Local illumination as the paper's snapshot: Lambert from point lights (cosine lobes for the
// point samples of area lights) and directional lights (the scene's and the environment's
// brightest regions), the environment's SH ambient term, plus the emission of emissive
// surfaces, in linear radiance.
// Surfaces are two-sided: the normal is flipped towards the camera, as the tracer does.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "snapshot_interface.h"
#include "lights.glsl"
#include "shadow_cube.glsl"
#include "microfacet.glsl"

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) flat in vec3 vertexKd;
layout(location = 3) flat in vec3 ke;
layout(location = 7) flat in vec4 specular;  // ks, ns (gbuffer_vertex.glsl); a microfacet lobe: its tint
layout(location = 8) flat in vec4 lobe;       // GBUFFER_LOBE_* model, alpha_u, alpha_v, distribution
layout(location = 9) flat in vec4 lobeEta;    // conductor eta, plastic ior in w
layout(location = 10) flat in vec4 lobeK;     // conductor k
#ifdef GBUFFER_TEXTURED
// kd times the base-colour texture (filtered over the pixel's footprint); alpha-tested materials
// discard where the level-0 coverage < threshold.
#include "gbuffer_texture.glsl"
layout(location = 4) in vec2 uv;
layout(location = 5) flat in uvec4 texRect;
layout(location = 6) flat in vec2 texParams;  // layer, alpha threshold
#ifdef GBUFFER_SHADOWS
layout(binding = GBUFFER_BINDING_ATLAS_SHADOWED) uniform texture2DArray atlas;
#else
layout(binding = GBUFFER_BINDING_ATLAS_UNSHADOWED) uniform texture2DArray atlas;
#endif
#endif

layout(location = 0) out vec4 outColour;
#ifdef GBUFFER_GREY
#include "aamap_filter.h"
#include "display_luma.glsl"
layout(location = 1) out float outGrey;
#endif

layout(push_constant) uniform Push { GBufferPush pc; };
layout(std140, binding = GBUFFER_BINDING_LIGHTS) uniform Lights { GpuLight lights[GBUFFER_MAX_LIGHTS]; };

const float kInvPi = 0.31830988618379067;
// Whether any drawn material has a microfacet lobe (LIGHTING_SPEC_MICROFACET): without one the
// lobe's code folds away. Unset (1): evaluated where a vertex says so.
layout(constant_id = LIGHTING_SPEC_MICROFACET) const uint kMicrofacet = 1u;

#ifdef GBUFFER_SHADOWS
layout(binding = GBUFFER_BINDING_SHADOW) uniform texture2DArray shadowCubes;

#include "shadow_visibility.glsl"

// pc.shadow, read once at the top of main: lavapipe gathers each uniform load lane by lane, and
// re-reads it after every shadow-map fetch otherwise.
vec4 shadowParams;

// Area-light samples (a patch in cone.w) cast soft shadows; point and spot lights hard ones. For
// the inline lights the test folds, and without patches (kSoftShadows 0) so does the soft code.
// Each light's faces have their own size (GpuLight::position.w), in w of the parameters.
float visibility(GpuLight l, uint light, vec3 r, vec3 n) {
    const vec4 params = vec4(shadowParams.xyz, l.position.w);
    if (kSoftShadows != 0u && l.cone.w > 0.0)
        return softShadowVisibility(shadowCubes, light, r, n, params, l.cone.w, int(kShadowPcf));
    return shadowVisibility(shadowCubes, light, r, n, params, int(kShadowPcf));
}
#endif

// The glossy lobe's direction (the view reflected about n) and the tracer's modified Phong
// normalisation (ns + 2) / (2 pi), set in main for materials with ks > 0; for a microfacet lobe
// the view in the shading frame of n (the tracer's frame, so anisotropic lobes align).
vec3 mirrorOfView = vec3(0.0);
vec3 phongKs = vec3(0.0);
MicrofacetFrame lobeFrame;
vec3 lobeView = vec3(0.0, 0.0, 1.0);

// kd / pi plus the glossy lobe for light direction wi: the tracer's Phong ks (ns + 2) / (2 pi)
// cos^ns(alpha), or its microfacet lobe (glsl/microfacet.glsl) with a plastic's base through the
// coating.
vec3 brdf(vec3 kd, vec3 wi) {
    if (kMicrofacet != 0u && lobe.x != float(GBUFFER_LOBE_PHONG)) {
        const vec3 li = toLocal(lobeFrame, wi);
        if (li.z <= 0.0 || lobeView.z <= 0.0) return vec3(0.0);
        return microfacetLobe(lobeView, li, lobe, lobeEta, lobeK, specular.xyz, kd);
    }
    vec3 f = kd * kInvPi;
    if (specular.x > 0.0 || specular.y > 0.0 || specular.z > 0.0) {
        const float c = dot(mirrorOfView, wi);
        if (c > 0.0) f += phongKs * pow(c, specular.w);
    }
    return f;
}

// Lambert (and the glossy lobe) from light i (its shadow-map layers are 6i..6i+5), emission excluded.
vec3 lightContribution(GpuLight light, uint i, vec3 n, vec3 kd) {
    if (isDirectional(light)) {  // irradiance E from direction normal.xyz
        float weight = max(dot(n, light.normal.xyz), 0.0);
#ifdef GBUFFER_SHADOWS
        if (weight > 0.0)
            weight *= directionalShadowVisibility(shadowCubes, i, light, worldPosition, n,
                                                  vec4(shadowParams.xyz, light.position.w), int(kShadowPcf));
#endif
        return brdf(kd, light.normal.xyz) * light.intensity.rgb * weight;
    }
    const vec3 toLight = light.position.xyz - worldPosition;
    const float d2 = dot(toLight, toLight);
    if (d2 <= 0.0) return vec3(0.0);
    const vec3 wi = toLight * inversesqrt(d2);
    const float cosSurface = max(dot(n, wi), 0.0);
    const float lobe = angularFactor(light.normal.xyz, light.cone, wi);
    float weight = cosSurface * lobe / d2;
#ifdef GBUFFER_SHADOWS
    if (weight > 0.0) weight *= visibility(light, i, -toLight, n);  // no lookups for unlit sides
#endif
    return brdf(kd, wi) * light.intensity.rgb * weight;
}

// Every light's contribution (lightContribution), emission and the ambient term excluded: the
// inlined lights from specialisation constants, then the rest from the uniform buffer.
vec3 lighting(vec3 n, vec3 kd) {
    vec3 sum = vec3(0.0);
#define ADD_INLINE_LIGHT(k) \
    if (uint(k) < kLightCount) sum += lightContribution(INLINE_LIGHT(k), uint(k), n, kd);
    FOR_EACH_INLINE_LIGHT(ADD_INLINE_LIGHT)
    for (uint i = LIGHTING_INLINE_LIGHTS; i < kLightCount; ++i) sum += lightContribution(lights[i], i, n, kd);
    return sum;
}

void main() {
#ifdef GBUFFER_TEXTURED
    // The pixel's footprint in uv, before any discard (derivatives need the whole quad). The
    // unwrapped uv, so a repeating texture's seam is no wide footprint.
    const vec2 duvA = dFdx(uv), duvB = dFdy(uv);
#endif
#ifdef GBUFFER_MIRROR
    // Only what lies on the viewer's side of the mirror is seen in it. A discard rather than
    // gl_ClipDistance: the context does not enable shaderClipDistance; the pixels are the same.
    if (dot(pc.clipPlane.xyz, worldPosition) < pc.clipPlane.w) discard;
#endif
#ifdef GBUFFER_TEXTURED
    vec3 kd = vertexKd;
    if (texRect.z > 0u) {
        // Coverage from level 0, unfiltered: a cut-out is the tracer's hit/miss test, texel for texel.
        if (texParams.y > 0.0 && atlasBilinear(atlas, uv, texRect, texParams.x).a < texParams.y) discard;
        kd *= atlasFiltered(atlas, uv, duvA, duvB, texRect, texParams.x);
    }
#else
    const vec3 kd = vertexKd;
#endif
    vec3 n = normalize(worldNormal);
#ifdef GBUFFER_SHADOWS
    shadowParams = pc.shadow;
#endif
    const vec3 toCamera = pc.cameraPos.xyz - worldPosition;
    const bool front = dot(n, toCamera) >= 0.0;
    if (!front) n = -n;

#ifdef GBUFFER_GLASS
    // Glass over what the camera sees through it (already in the target): premultiplied
    // F * reflected + (1 - F) * behind, F by Schlick from the normal-incidence reflectance that
    // glass vertices carry in kd (a dielectric has no diffuse albedo). The reflected radiance is
    // estimated as a white Lambert surface's under the same lights, unshadowed: no reflected
    // geometry, but F -> 1 at grazing angles, so silhouettes and rims show where the tracer's do.
    const float f0 = vertexKd.x;
    const float cosView = clamp(dot(n, normalize(toCamera)), 0.0, 1.0);
    const float fresnel = f0 + (1.0 - f0) * pow(1.0 - cosView, 5.0);
    const vec3 reflected = lighting(n, vec3(1.0)) + kInvPi * ambientIrradiance(n);
    outColour = vec4(fresnel * reflected, fresnel);
    return;
#endif
    mirrorOfView = reflect(-normalize(toCamera), n);
    phongKs = specular.xyz * ((specular.w + 2.0) * 0.5 * kInvPi);
    if (kMicrofacet != 0u && lobe.x != float(GBUFFER_LOBE_PHONG)) {
        lobeFrame = microfacetFrame(n);
        lobeView = toLocal(lobeFrame, normalize(toCamera));
    }
    // Emitters are one-sided along their normal.
    vec3 colour = (front ? ke : vec3(0.0)) + lighting(n, kd);
    colour += kd * kInvPi * ambientIrradiance(n);  // the environment's remainder (unshadowed)
    outColour = vec4(colour, 1.0);
#ifdef GBUFFER_GREY
    outGrey = displayLuma(colour, pc.exposure);
#endif
}
