#version 460
// Glass in the camera's view, drawn over the opaque surfaces it shows: see gbuffer.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_GLASS 1
#include "gbuffer.glsl"
