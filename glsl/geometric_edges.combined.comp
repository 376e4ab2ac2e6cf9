#version 460
// The combined map's edge image: max(geometric edge, luminance |L|). See geometric_edges.glsl.
#define GEOMETRIC_COMBINED
#extension GL_GOOGLE_include_directive : require
#include "geometric_edges.glsl"
