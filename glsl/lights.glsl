// The light list as the lit fragment shaders see it (gbuffer.glsl, geometry_buffer.glsl): its
// specialisation constants (snapshot_interface.h, LIGHTING_SPEC_*), the first lights inline, and
// each light's angular factor. Include after snapshot_interface.h.

layout(constant_id = LIGHTING_SPEC_LIGHT_COUNT) const uint kLightCount = 0u;
layout(constant_id = LIGHTING_SPEC_SHADOW_PCF) const uint kShadowPcf = 1u;
layout(constant_id = LIGHTING_SPEC_LIGHT_KINDS) const uint kLightKinds =
    LIGHT_KIND_ISOTROPIC | LIGHT_KIND_LOBE | LIGHT_KIND_SPOT;
// 0: every light is a point (hard shadows only, the soft-shadow code folds away).
layout(constant_id = LIGHTING_SPEC_SOFT_SHADOWS) const uint kSoftShadows = 0u;

// Light k < LIGHTING_INLINE_LIGHTS as constants kLight<k>_<field> (field 0..13 as
// LIGHTING_SPEC_LIGHT_DATA says), and INLINE_LIGHT(k) its GpuLight.
#define LIGHT_CONSTANT(k, f)                                                                        \
    layout(constant_id = LIGHTING_SPEC_LIGHT_DATA + LIGHTING_SPEC_FLOATS_PER_LIGHT * k + f) const float \
        kLight##k##_##f = 0.0;
#define DECLARE_INLINE_LIGHT(k)                                                                     \
    LIGHT_CONSTANT(k, 0) LIGHT_CONSTANT(k, 1) LIGHT_CONSTANT(k, 2) LIGHT_CONSTANT(k, 3)             \
    LIGHT_CONSTANT(k, 4) LIGHT_CONSTANT(k, 5) LIGHT_CONSTANT(k, 6) LIGHT_CONSTANT(k, 7)             \
    LIGHT_CONSTANT(k, 8) LIGHT_CONSTANT(k, 9) LIGHT_CONSTANT(k, 10) LIGHT_CONSTANT(k, 11) LIGHT_CONSTANT(k, 12) \
    LIGHT_CONSTANT(k, 13)
#define INLINE_LIGHT(k)                                                                             \
    GpuLight(vec4(kLight##k##_0, kLight##k##_1, kLight##k##_2, kLight##k##_13),                      \
             vec4(kLight##k##_3, kLight##k##_4, kLight##k##_5, 0.0),                                 \
             vec4(kLight##k##_6, kLight##k##_7, kLight##k##_8, 0.0),                                 \
             vec4(kLight##k##_9, kLight##k##_10, kLight##k##_11, kLight##k##_12))
// APPLY(k) for k = 0 .. LIGHTING_INLINE_LIGHTS - 1: the callers unroll their light loop with it,
// guarding each with k < kLightCount (folded), then loop over lights[] from LIGHTING_INLINE_LIGHTS.
#define FOR_EACH_INLINE_LIGHT(APPLY) APPLY(0) APPLY(1) APPLY(2) APPLY(3) APPLY(4) APPLY(5) APPLY(6) APPLY(7)
FOR_EACH_INLINE_LIGHT(DECLARE_INLINE_LIGHT)

// The ambient SH irradiance (LIGHTING_SPEC_AMBIENT_SH): coefficient i as kAmbient<i>.
layout(constant_id = LIGHTING_SPEC_AMBIENT) const uint kAmbient = 0u;
#define AMBIENT_CONSTANT(i, c) layout(constant_id = LIGHTING_SPEC_AMBIENT_SH + 3 * i + c) const float kAmbient##i##_##c = 0.0;
#define AMBIENT_COEFFICIENT(i) AMBIENT_CONSTANT(i, 0) AMBIENT_CONSTANT(i, 1) AMBIENT_CONSTANT(i, 2)
AMBIENT_COEFFICIENT(0) AMBIENT_COEFFICIENT(1) AMBIENT_COEFFICIENT(2) AMBIENT_COEFFICIENT(3) AMBIENT_COEFFICIENT(4)
AMBIENT_COEFFICIENT(5) AMBIENT_COEFFICIENT(6) AMBIENT_COEFFICIENT(7) AMBIENT_COEFFICIENT(8)
#define AMBIENT_RGB(i) vec3(kAmbient##i##_0, kAmbient##i##_1, kAmbient##i##_2)

// Irradiance of the environment's ambient part on a surface with unit normal n (passes/
// environment_lighting.cpp shBasis and ambientIrradiance are the CPU twins).
vec3 ambientIrradiance(vec3 n) {
    if (kAmbient == 0u) return vec3(0.0);
    const float x = n.x, y = n.y, z = n.z;
    return AMBIENT_RGB(0) * 0.282095 + AMBIENT_RGB(1) * (0.488603 * y) + AMBIENT_RGB(2) * (0.488603 * z) +
           AMBIENT_RGB(3) * (0.488603 * x) + AMBIENT_RGB(4) * (1.092548 * x * y) + AMBIENT_RGB(5) * (1.092548 * y * z) +
           AMBIENT_RGB(6) * (0.315392 * (3.0 * z * z - 1.0)) + AMBIENT_RGB(7) * (1.092548 * x * z) +
           AMBIENT_RGB(8) * (0.546274 * (x * x - y * y));
}

// Whether light `light` of the list is directional; folds to false without directional lights.
bool isDirectional(GpuLight light) {
    return (kLightKinds & LIGHT_KIND_DIRECTIONAL) != 0u && light.cone.z > 1.5;
}

// scene/lights.h spotFalloff: 1 inside the inner cone, 0 outside the outer, t^2 between with t
// linear in the cosine (glTF's recommended falloff).
float spotFalloff(float cosAngle, float cosInner, float cosOuter) {
    if (cosAngle >= cosInner) return 1.0;
    if (cosAngle <= cosOuter) return 0.0;
    const float t = (cosAngle - cosOuter) / (cosInner - cosOuter);
    return t * t;
}

// The emission towards -wi relative to the light's peak, as the tracer's
// PointLightSource::angular: 1 for an isotropic light, the cosine lobe about `axis`, or the spot
// cone about it (cone as GpuLight::cone). Each test below folds away when the kinds it tells
// apart are not all in the list.
float angularFactor(vec3 axis, vec4 cone, vec3 wi) {
    const uint kinds = kLightKinds;
    if (kinds == LIGHT_KIND_ISOTROPIC) return 1.0;
    const float cosAngle = dot(axis, -wi);
    float factor;
    if ((kinds & LIGHT_KIND_SPOT) == 0u) factor = max(cosAngle, 0.0);
    else if ((kinds & LIGHT_KIND_LOBE) == 0u) factor = spotFalloff(cosAngle, cone.x, cone.y);
    else factor = cone.z > 0.0 ? spotFalloff(cosAngle, cone.x, cone.y) : max(cosAngle, 0.0);
    if ((kinds & LIGHT_KIND_ISOTROPIC) != 0u && !(dot(axis, axis) > 0.0)) factor = 1.0;
    return factor;
}
