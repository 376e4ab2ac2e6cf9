#version 460
// Shadow cube maps of a scene with alpha masks: see shadow_cube_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#define SHADOW_MASKED 1
#include "shadow_cube_vertex.glsl"
