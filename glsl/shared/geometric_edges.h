// The geometric aamap's edge rule, shared by the GLSL edge pass (geometric_edges.comp) and the
// CPU reference (passes/cpu_geometric.cpp). Plain C/GLSL: no C++ in here.
//
// Input, at snapshot resolution, from the geometry raster (geometry_buffer.vert/.frag):
//   normal-depth texel: xyz = unit world normal turned towards the camera, w = view depth z > 0
//                       (distance along the camera axis); w = 0: nothing covers the texel.
//   ids texel:          x = object id, y = material id (as floats, exact below 2^24); z, w = low
//                       and high 16 bits of the shadow occlusion mask (bit i mod 32: light i
//                       would light the texel but the shadow maps block it; 0 without shadows).
// Texel p is an edge (value GEOMETRIC_EDGE_VALUE, else 0) when, for a 4-neighbour q (clamped to
// the image, so a border texel compares with itself on that side):
//   1. coverage differs (exactly one of p, q is covered), or, both covered:
//   2. the object id, the material id or the occlusion mask differs (shadow boundaries, also
//      between surfaces of equal colour and lighting), or
//   3. the normals differ by more than the crease angle: dot(n_p, n_q) < GEOMETRIC_CREASE_COS, or
//   4. depth is discontinuous along q's axis: with a and b the two neighbours of p on that axis
//      (both covered), |1/z_a + 1/z_b - 2/z_p| > GEOMETRIC_DEPTH_TOLERANCE * (1/z_p). Inverse depth
//      is affine in screen space on any plane, so this second difference is 0 (up to rounding) on
//      planar and slanted surfaces alike, and the ratio is scale-free: scaling the scene and the
//      camera together changes nothing.
// Combined map: max(|L|, geometric edge) per texel, then the luminance chain's blur, dead zone and
// reduction (aamap_filter.h) follow unchanged.
#ifndef AAMAP_GEOMETRIC_EDGES_H
#define AAMAP_GEOMETRIC_EDGES_H

#define GEOMETRIC_CREASE_COS 0.8660254   // 30 degrees
#define GEOMETRIC_DEPTH_TOLERANCE 0.05
// After the default radius-1 box blur a one-texel edge line gives 3 * 3/9 = 1: full strata.
#define GEOMETRIC_EDGE_VALUE 3.0

#endif
