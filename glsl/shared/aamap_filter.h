// The aamap filter chain's definition, shared by the GLSL compute passes and the CPU reference
// (passes/cpu_aamap.cpp) so both compute the same thing. Plain C/GLSL: no C++ in here.
//
// At snapshot resolution (Ws x Hs), every neighbourhood clamped to the image edge:
//   1. grey  g = luma of the display encoding:  dot(LUMA, srgbEncode(clamp(exposure * rgb, 0, 1)))
//   2. edges e = |L|,  L = sum over the 24 off-centre taps o of the 5x5 window of (g(p+o) - g(p)),
//      accumulated in row-major order (dy, then dx, from -2 to 2). Written as differences so a
//      constant image gives exactly 0 (24*g - sum(g) would not, in floating point).
//      Flat gate: e = 0 where max(g) - min(g) over the 3x3 window around p is below flatRange
//      (default 1/255, one 8-bit code value). The 5x5 Laplacian still answers two texels from an
//      edge, where the pixel itself is flat and one ray already shows it; the gate keeps the
//      response on the texels that touch the edge. flatRange 0 keeps every texel (the paper's chain).
//   3. blur  b = mean of e over the (2r+1)^2 box around p (r = blur radius, 0 = no blur), summed in
//      row-major order and divided once by (2r+1)^2.
//   4. map   m = clamp(gain * (b - noiseFloor), 0, 1): the dead zone removes the tiny responses of
//      smooth shading, so flat regions are exactly 0.
// Then reduce to the render resolution (W x H): aamap(x, y) = max of m over every snapshot texel
// whose footprint overlaps pixel (x, y)'s footprint (conservative: an edge is never lost).
#ifndef AAMAP_FILTER_H
#define AAMAP_FILTER_H

#define AAMAP_LUMA_R 0.2126
#define AAMAP_LUMA_G 0.7152
#define AAMAP_LUMA_B 0.0722
#define AAMAP_LAPLACIAN_RADIUS 2
#define AAMAP_FLAT_GATE_RADIUS 1
#define AAMAP_DEFAULT_FLAT_RANGE (1.0 / 255.0)
#define AAMAP_DEFAULT_BLUR_RADIUS 1
#define AAMAP_DEFAULT_NOISE_FLOOR 0.02
#define AAMAP_DEFAULT_GAIN 1.0

// Compute workgroup size of the filter passes.
#define AAMAP_FILTER_GROUP_X 16
#define AAMAP_FILTER_GROUP_Y 16
// Output rows per invocation of the Laplacian and the blur (a strip of one column;
// glsl/laplacian.comp, glsl/blur.comp).
#define AAMAP_FILTER_ROWS 4

#endif
