#version 460
// The shading of a planar mirror's reflected view, textured, with shadows: see gbuffer.glsl.
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_MIRROR 1
#define GBUFFER_TEXTURED 1
#define GBUFFER_SHADOWS 1
#include "gbuffer.glsl"
