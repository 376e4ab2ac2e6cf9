#version 460
// The geometric aamap's vertex stage: see geometry_buffer_vertex.glsl.
#extension GL_GOOGLE_include_directive : require
#include "geometry_buffer_vertex.glsl"
