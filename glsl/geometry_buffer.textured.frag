#version 460
// The geometric aamap's raster (textured variant): see geometry_buffer.glsl.
#extension GL_GOOGLE_include_directive : require
#define GEOMETRY_TEXTURED 1
#include "geometry_buffer.glsl"
