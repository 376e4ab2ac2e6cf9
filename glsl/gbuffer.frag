#version 460
// The Snapshot raster's shading without shadows (no lights, or shadows off): see gbuffer.glsl.
#extension GL_GOOGLE_include_directive : require
#include "gbuffer.glsl"
