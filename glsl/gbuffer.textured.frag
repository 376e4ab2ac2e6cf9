#version 460
// The Snapshot raster's shading with textures, without shadows: see gbuffer.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_TEXTURED 1
#include "gbuffer.glsl"
