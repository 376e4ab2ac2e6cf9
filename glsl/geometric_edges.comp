#version 460
// The geometric aamap's edge image (see geometric_edges.glsl).
#extension GL_GOOGLE_include_directive : require
#include "geometric_edges.glsl"
