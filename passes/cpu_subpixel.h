#pragma once
// CPU reference of the sub-pixel aamap (glsl/shared/subpixel_map.h) from the same k x k samples
// per pixel the Snapshot rasterises: the GPU pass is tested against it. No Vulkan.
#include "core/image.h"
#include "passes/cpu_geometric.h"

namespace aamap::cpu {

struct SubpixelImages {
    ImageGrey error;  // E: the predicted display error of a one-ray pixel (after the geometry floor)
    ImageGrey map;    // a = 0 where E <= tau, else 1 - tau / E
};

// geometry: k W x k H (as the geometry raster writes them, geometric_edges.h); colour: the same,
// or W x H with shared shading (one shade per pixel, rule 2'); the result W x H. Throws
// std::invalid_argument on mismatched sizes, a size that is not a multiple of k, or k outside
// [SUBPIXEL_MIN_K, SUBPIXEL_MAX_K].
SubpixelImages subpixelMap(const ImageRGB& colour, const GeometryImages& geometry, int k, float exposure,
                           float tolerance, bool shared);

}  // namespace aamap::cpu
