#pragma once
// CPU reference of the geometric aamap's edge rule (glsl/shared/geometric_edges.h): the GPU edge
// pass is tested against it. No Vulkan.
#include <glm/vec4.hpp>

#include "core/image.h"

namespace aamap::cpu {

// The geometry raster's two images (layout in geometric_edges.h).
struct GeometryImages {
    Image<glm::vec4> normalDepth;
    Image<glm::vec4> ids;
};

// GEOMETRIC_EDGE_VALUE where the rule fires, else 0.
ImageGrey geometricEdges(const GeometryImages& geometry);
// Per texel max of the two (the combined map's edge image).
ImageGrey maxEdges(const ImageGrey& a, const ImageGrey& b);

}  // namespace aamap::cpu
