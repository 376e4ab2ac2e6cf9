#version 460
// The geometric aamap's vertex stage with uv and atlas entry: see geometry_buffer_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#define GEOMETRY_TEXTURED 1
#include "geometry_buffer_vertex.glsl"
