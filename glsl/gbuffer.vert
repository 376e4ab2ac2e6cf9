#version 460
// The Snapshot raster's vertex stage without textures: see gbuffer_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#include "gbuffer_vertex.glsl"
