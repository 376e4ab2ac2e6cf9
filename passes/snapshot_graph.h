#pragma once
// Every pass and every resource (pin) of the Snapshot's render graph, by name, in one place.
// Passes take their inputs and outputs as names where a caller may wire them differently (the
// stand-alone GPU filter runners, the tests), and use these names for what they own. A name is
// what --explain, the DOT graph, pass timings and results.json show, so these strings are part
// of the output format: rename with care.
//
// Resources (format; written by -> read by):
//   snapshot              RGBA32F, linear colour       gbuffer (v0), mirror.composite and
//                                                      mirror.probes.composite (each the next
//                                                      version, in that order) -> luminance
//   depth                 D32, reversed                gbuffer -> mirror.mask
//   shadow.cubes          D32 array, 6 layers a light  shadow -> gbuffer, mirror, geometry_buffer
//   mirror.colour/.depth  RGBA32F/D32, layer a mirror  mirror -> mirror.composite
//   mirror.mask           RGBA32F (reflectance, layer) mirror.mask -> mirror.composite
//   grey                  R32F, display grey           gbuffer or luminance -> laplacian
//   laplacian             R32F, |L|                    laplacian -> blur, geometric_edges (combined)
//   geometry_normal_depth RGBA32F                      geometry_buffer -> geometric_edges
//   geometry_ids          RGBA32F                      geometry_buffer -> geometric_edges
//   geometry_depth        D32, the raster's z-buffer   geometry_buffer
//   edges                 R32F                         geometric_edges -> blur (geometric, combined)
//   map                   R32F, snapshot resolution    blur -> reduce
//   subpixel.geometry     R32F, render resolution      subpixel_geometry (the subpixel map's step 3
//                                                      per pixel, from the geometry images at k x k
//                                                      texels a pixel) -> subpixel_map
//   aamap                 R32F, render resolution      reduce, or subpixel_map (subpixel map: reads
//                                                      snapshot and subpixel.geometry)
//                                                      -> block_sum_rows; an output
//   block_sums/_counts    (W+1) x (H+1) prefix tables  block_sum_columns; outputs
// The graph culls what the scene and the requested outputs do not need, and says why.
#include <string>

namespace aamap::passes {

// Resources.
inline const std::string kSnapshot = "snapshot";
inline const std::string kDepth = "depth";
inline const std::string kShadowCubes = "shadow.cubes";
inline const std::string kMirrorColour = "mirror.colour";
inline const std::string kMirrorDepth = "mirror.depth";
inline const std::string kMirrorMask = "mirror.mask";
inline const std::string kGrey = "grey";
inline const std::string kLaplacian = "laplacian";
inline const std::string kGeometryNormalDepth = "geometry_normal_depth";
inline const std::string kGeometryIds = "geometry_ids";
inline const std::string kGeometryDepth = "geometry_depth";
inline const std::string kEdges = "edges";
inline const std::string kMap = "map";
inline const std::string kSubpixelGeometry = "subpixel.geometry";
inline const std::string kAamap = "aamap";
inline const std::string kBlockSumRowPrefixes = "block_sum_row_prefixes";    // transient
inline const std::string kBlockCountRowPrefixes = "block_count_row_prefixes";  // transient
inline const std::string kBlockSums = "block_sums";      // float pairs (hi, lo)
inline const std::string kBlockCounts = "block_counts";  // uint

// Passes.
inline const std::string kShadowPass = "shadow";
inline const std::string kGBufferPass = "gbuffer";
inline const std::string kMirrorPass = "mirror";
inline const std::string kMirrorMaskPass = "mirror.mask";
inline const std::string kMirrorCompositePass = "mirror.composite";
inline const std::string kLuminancePass = "luminance";
inline const std::string kLaplacianPass = "laplacian";
inline const std::string kGeometryBufferPass = "geometry_buffer";
inline const std::string kGeometricEdgesPass = "geometric_edges";
inline const std::string kSubpixelGeometryPass = "subpixel_geometry";
inline const std::string kSubpixelMapPass = "subpixel_map";
inline const std::string kBlurPass = "blur";
inline const std::string kReducePass = "reduce";
inline const std::string kBlockSumRowsPass = "block_sum_rows";
inline const std::string kBlockSumColumnsPass = "block_sum_columns";

}  // namespace aamap::passes
