#version 460
// The Snapshot raster's shading with textures and shadow cube maps: see gbuffer.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_TEXTURED 1
#define GBUFFER_SHADOWS 1
#include "gbuffer.glsl"
