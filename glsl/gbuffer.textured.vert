#version 460
// The Snapshot raster's vertex stage with uv and atlas entry: see gbuffer_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_TEXTURED 1
#include "gbuffer_vertex.glsl"
