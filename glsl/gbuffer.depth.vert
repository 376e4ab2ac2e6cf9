#version 460
// Depth pre-pass of the Snapshot raster (passes/gbuffer.cpp): the distinct positions only, so
// that the shading pass after it runs the fragment shader once per pixel (depth test
// GREATER_OR_EQUAL against this pass's depth) instead of once per overlapping surface.
// gl_Position is precise (no fused multiply-adds) here and in gbuffer_vertex.glsl: the same
// expression on the same bits must give the same depth in both passes. (`invariant` would say so
// too, but glslang puts it on a gl_PerVertex member, which the validation layer warns about.)
#extension GL_GOOGLE_include_directive : require
#include "snapshot_interface.h"

layout(location = GBUFFER_LOCATION_POSITION) in vec3 inPosition;
layout(push_constant) uniform Push { GBufferPush pc; };

precise gl_Position;

void main() { gl_Position = pc.viewProj * vec4(inPosition, 1.0); }
