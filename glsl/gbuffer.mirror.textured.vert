#version 460
// The reflected view of a planar mirror, textured: see gbuffer_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_MIRROR 1
#define GBUFFER_TEXTURED 1
#include "gbuffer_vertex.glsl"
