// Common declarations of the filter compute shaders (GLSL only).
#extension GL_GOOGLE_include_directive : require
#include "aamap_filter.h"
#include "snapshot_interface.h"

layout(local_size_x = AAMAP_FILTER_GROUP_X, local_size_y = AAMAP_FILTER_GROUP_Y) in;
layout(push_constant) uniform Push { FilterPush pc; };

ivec2 clampToImage(ivec2 p, ivec2 size) { return clamp(p, ivec2(0), size - 1); }
