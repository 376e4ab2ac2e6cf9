#version 460
// The geometric aamap's raster: see geometry_buffer.glsl.
#extension GL_GOOGLE_include_directive : require
#include "geometry_buffer.glsl"
