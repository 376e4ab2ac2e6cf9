#version 460
// The Snapshot raster's shading, and the greyscale of step 1 of the aamap: see gbuffer.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_GREY 1
#include "gbuffer.glsl"
