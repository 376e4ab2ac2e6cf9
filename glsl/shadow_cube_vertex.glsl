// Shadow cube maps of every light in one instanced draw: instance 6i+f is face f of light i and
// goes to layer 6i+f (gl_Layer from the vertex shader, shaderOutputLayer). Clip position
// (sc, tc, near, ma): x/w, y/w are the face coordinates and depth z/w = near/ma (reversed,
// infinite far plane); points behind the face have w < 0 and are clipped. A directional light's
// instance 6i draws its orthographic map instead (directionalMapCoords).
// Included by shadow_cube.vert and shadow_cube.masked.vert (SHADOW_MASKED: also passes the uv and
// atlas entry on to the alpha test).
#extension GL_GOOGLE_include_directive : require
#extension GL_ARB_shader_viewport_layer_array : require
#include "snapshot_interface.h"
#include "shadow_cube.glsl"

layout(location = SHADOW_LOCATION_POSITION) in vec3 inPosition;
#ifdef SHADOW_MASKED
layout(location = SHADOW_LOCATION_UV) in vec2 inUv;
layout(location = SHADOW_LOCATION_TEX_RECT) in uvec4 inTexRect;
layout(location = SHADOW_LOCATION_TEX_PARAMS) in vec2 inTexParams;
layout(location = 0) out vec2 uv;
layout(location = 1) flat out uvec4 texRect;
layout(location = 2) flat out vec2 texParams;
#endif

layout(push_constant) uniform Push { ShadowPush pc; };
layout(std140, binding = SHADOW_BINDING_LIGHTS) uniform Lights { GpuLight lights[GBUFFER_MAX_LIGHTS]; };

void main() {
    const uint instance = uint(gl_InstanceIndex);
    const GpuLight light = lights[instance / 6u];
    if (light.cone.z > 1.5) {  // directional: its orthographic map on face 0 (the CPU draws no other face)
        const vec3 o = directionalMapCoords(inPosition, light.normal.xyz, light.position.xyz, light.cone.x);
        gl_Position = vec4(o.xy, o.z, 1.0);
    } else {
        const vec3 r = inPosition - light.position.xyz;
        const vec3 f = cubeFaceCoords(r, instance % 6u);
        gl_Position = vec4(f.x, f.y, pc.nearPlane, f.z);
    }
    gl_Layer = int(instance);
#ifdef SHADOW_MASKED
    uv = inUv;
    texRect = inTexRect;
    texParams = inTexParams;
#endif
}
