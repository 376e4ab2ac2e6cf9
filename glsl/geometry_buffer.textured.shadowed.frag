#version 460
// The geometric aamap's raster (textured.shadowed variant): see geometry_buffer.glsl.
#extension GL_GOOGLE_include_directive : require
#define GEOMETRY_TEXTURED 1
#define GEOMETRY_SHADOWS 1
#include "geometry_buffer.glsl"
