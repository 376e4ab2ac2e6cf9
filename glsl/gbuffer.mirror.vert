#version 460
// The reflected view of a planar mirror: see gbuffer_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_MIRROR 1
#include "gbuffer_vertex.glsl"
