#version 460
// Shadow cube maps, depth only: see shadow_cube_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#include "shadow_cube_vertex.glsl"
