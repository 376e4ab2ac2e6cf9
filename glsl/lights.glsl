// The light list as the lit fragment shaders see it (gbuffer.glsl, geometry_buffer.glsl): its
// specialisation constants (snapshot_interface.h, LIGHTING_SPEC_*) and each light's angular
// factor. Include after snapshot_interface.h.

layout(constant_id = LIGHTING_SPEC_LIGHT_COUNT) const uint kLightCount = 0u;
layout(constant_id = LIGHTING_SPEC_SHADOW_PCF) const uint kShadowPcf = 1u;
layout(constant_id = LIGHTING_SPEC_LIGHT_KINDS) const uint kLightKinds =
    LIGHT_KIND_ISOTROPIC | LIGHT_KIND_LOBE | LIGHT_KIND_SPOT;

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
