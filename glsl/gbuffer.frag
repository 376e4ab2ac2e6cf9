#version 460
// Local illumination as the paper's snapshot: Lambert from point lights (cosine lobes for the
// point samples of area lights) plus the emission of emissive surfaces, in linear radiance.
// Surfaces are two-sided: the normal is flipped towards the camera, as the tracer does.
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) flat in vec3 kd;
layout(location = 3) flat in vec3 ke;

layout(location = 0) out vec4 outColour;

layout(push_constant) uniform Push { GBufferPush pc; };
layout(std140, binding = GBUFFER_BINDING_LIGHTS) uniform Lights { GpuLight lights[GBUFFER_MAX_LIGHTS]; };

const float kInvPi = 0.31830988618379067;

void main() {
    vec3 n = normalize(worldNormal);
    const vec3 toCamera = pc.cameraPos.xyz - worldPosition;
    const bool front = dot(n, toCamera) >= 0.0;
    if (!front) n = -n;

    // Emitters are one-sided along their normal.
    vec3 colour = front ? ke : vec3(0.0);
    for (uint i = 0u; i < pc.lightCount; ++i) {
        const vec3 toLight = lights[i].position.xyz - worldPosition;
        const float d2 = dot(toLight, toLight);
        if (d2 <= 0.0) continue;
        const vec3 wi = toLight * inversesqrt(d2);
        const float cosSurface = max(dot(n, wi), 0.0);
        float lobe = 1.0;
        const vec3 axis = lights[i].normal.xyz;
        if (dot(axis, axis) > 0.0) lobe = max(dot(axis, -wi), 0.0);
        colour += kd * kInvPi * lights[i].intensity.rgb * (cosSurface * lobe / d2);
    }
    outColour = vec4(colour, 1.0);
}
