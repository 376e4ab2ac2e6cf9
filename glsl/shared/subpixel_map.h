// The sub-pixel aamap's predictor, shared by the GLSL pass (subpixel_map.comp) and the CPU
// reference (passes/cpu_subpixel.cpp) so both compute the same thing. Plain C/GLSL: no C++ in here.
//
// The Snapshot rasterises k x k samples per render pixel (geometry at k times the render
// resolution; sample (i, j) of pixel (x, y) is texel (k x + i, k y + j)). With a shade per sample
// (snapshot.subpixel_shading: sample) the colour is rasterised alike, and for each render pixel:
//   1. display values, as the metrics see a pixel (core displayEncode, toneMap without rounding):
//      d_s = srgbEncode(clamp(exposure * rgb_s, 0, 1)) per channel for each sample s, and
//      m   = srgbEncode(clamp(exposure * mean_s(rgb_s), 0, 1)), the pixel's converged value
//      (radiance is averaged before the display transform, as a many-ray pixel is).
//   2. colour error: E = mean over the pixel's samples of max over channels of |d_s - m|, the
//      expected error of a one-ray pixel whose ray lands anywhere in the pixel (an edge that
//      leaves a share f of the pixel on one side gives 2 f (1 - f) times its contrast; a linear
//      gradient g per pixel about g / 4); and over the boundary pairs (s, r), r the 4-neighbour
//      of an own sample s just outside the pixel (inside the image), E = max(E, |d_r - d_s| / 2):
//      an edge between two samples of different pixels lies in this pixel or the neighbour, so a
//      sliver narrower than the sample spacing is still seen (both pixels get it). Sums run
//      row-major (j, then i).
//   3. geometry the colour may not show: if for a 4-adjacent pair of samples with at least one
//      in the pixel (the pairs inside it and the boundary pairs), coverage, object id or material
//      id differ, or the normals turn by more than the crease angle (dot < SUBPIXEL_CREASE_COS), or
//      inverse depth jumps by more than SUBPIXEL_DEPTH_TOLERANCE of the larger one, then
//      E = max(E, SUBPIXEL_GEOMETRY_ERROR * tau). Adjacent pairs only: a curved surface whose
//      normal turns smoothly across the pixel is not an edge. Sub-pixel geometry (a wire thinner
//      than a pixel) enters here and through step 2 whenever one sample sees it.
//   4. map a = 0 where E <= tau, else 1 - tau / E: the share of the one-ray pixel's error that
//      has to go for the pixel to fall below the threshold, in [0, 1) and increasing in E. tau is
//      the display-value difference at which FLIP's colour error reaches the metrics' FLIP
//      threshold t (see below), so a pixel is flagged exactly when its predicted error exceeds
//      what the metrics count as an error, and smooth shading (a wide penumbra, a highlight, a hot
//      spot: gradients far below tau across one pixel) gives 0.
//
// Shared shading (snapshot.subpixel_shading: pixel, SUBPIXEL_SPEC_SHARED = 1): the colour is shaded
// once per render pixel (W x H, at the pixel's centre) and shared by its k x k geometry samples,
// so shading costs what a render-resolution raster costs. Step 3 is unchanged (the geometry
// samples are still k x k); steps 1-2 become, with d(q) the display value of pixel q's shade
// (a neighbour outside the image counts as p itself):
//   2'. own(q): some inside pair of q's samples differs in geometry (step 3's test); border(p, q):
//      some boundary pair between p and its 4-neighbour q does. The shading step between p and q,
//      d(q) - d(p), belongs to both pixels, except to p when own(q) and not own(p) and not
//      border(p, q): a geometric edge inside q, none in p, makes the step q's. Per axis, with
//      a = d(p+) - d(p) and b = d(p) - d(p-) (0 for a step p does not own), per channel
//      e = |a - b| / 2 + (a b > 0 ? min(|a|, |b|) / 4 : 0), and E = max over axes and channels:
//      a step between p and a neighbour gives both its owners half its contrast (the edge lies
//      in one of them, as a boundary pair above), a linear gradient g per pixel gives g / 4 (the
//      one-ray error of a pixel that a linear ramp crosses), so smooth shading stays unflagged.
// Shading detail smaller than a pixel (a shadow edge or texture inside one triangle) is seen only
// through the shades of neighbouring pixels; geometry at any scale down to 1/k pixel is seen
// through step 3.
//
// tau from t (FLIP's colour pipeline, eval/metrics/flip_color.h, below its knee): a HyAB distance
// D gives t = pt * D^qc / (pc * cmax), so D(t) = (t * pc * cmax / pt)^(1/qc); a grey step of D in
// L* is about D / 100 in sRGB-encoded display value (L* is within about 15 % of 100 x the encoded
// value over [0.1, 1]). tau = D(t) / SUBPIXEL_LSTAR_PER_DISPLAY; t = 0.1 gives tau = 0.022 (5.6
// 8-bit code values). FLIP's spatial filter, which lowers an isolated pixel's error, is left out:
// the prediction errs towards flagging.
#ifndef AAMAP_SUBPIXEL_MAP_H
#define AAMAP_SUBPIXEL_MAP_H

#define SUBPIXEL_MIN_K 2
#define SUBPIXEL_MAX_K 4
#define SUBPIXEL_DEFAULT_K 2

// FLIP's colour redistribution (eval/metrics/flip_color.cpp; cmax = HyAB(green, blue)^qc).
#define SUBPIXEL_FLIP_QC 0.7
#define SUBPIXEL_FLIP_PC 0.4
#define SUBPIXEL_FLIP_PT 0.95
#define SUBPIXEL_FLIP_CMAX 41.27522
#define SUBPIXEL_LSTAR_PER_DISPLAY 100.0

// Geometry within the pixel: as the geometric map's thresholds (geometric_edges.h), and the
// predicted error it implies, in units of tau (2: map value 1/2).
#define SUBPIXEL_CREASE_COS 0.8660254   // 30 degrees
#define SUBPIXEL_DEPTH_TOLERANCE 0.05
#define SUBPIXEL_GEOMETRY_ERROR 2.0

#define SUBPIXEL_SPEC_K 0       // specialisation constants of subpixel_map.comp: k,
#define SUBPIXEL_SPEC_SHARED 1  // and 1 for shared shading (colour W x H); a pipeline per pair
#define SUBPIXEL_GROUP_X 8
#define SUBPIXEL_GROUP_Y 8

// Step 3 runs first, once per pixel, in its own pass (subpixel_geometry.comp): it writes the
// pixel's geometry flags, which subpixel_map.comp reads for the pixel and its neighbours, so that
// no sample pair is tested twice. A sum of these bits, stored exactly in an r32f texel:
#define SUBPIXEL_FLAG_OWN 1u    // an inside pair of the pixel's samples differs: own(p)
#define SUBPIXEL_FLAG_RIGHT 2u  // a boundary pair with the pixel to the right differs
#define SUBPIXEL_FLAG_DOWN 4u   // a boundary pair with the pixel below differs

// Bindings of subpixel_geometry.comp.
#define SUBPIXEL_GEOMETRY_BINDING_NORMAL_DEPTH 0  // rgba32f storage image (geometric_edges.h layout), k W x k H, read
#define SUBPIXEL_GEOMETRY_BINDING_IDS 1           // rgba32f storage image, k W x k H, read
#define SUBPIXEL_GEOMETRY_BINDING_OUTPUT 2        // r32f storage image, W x H, the flags, written

// Bindings of subpixel_map.comp.
#define SUBPIXEL_BINDING_COLOUR 0    // rgba32f storage image, k W x k H (shared shading: W x H), read
#define SUBPIXEL_BINDING_GEOMETRY 1  // r32f storage image, W x H, the geometry flags, read
#define SUBPIXEL_BINDING_OUTPUT 2    // r32f storage image, W x H, written

#ifdef __cplusplus
#include <cmath>
namespace aamap {
// tau (step 4 above) for the FLIP threshold t: the display-value error at which a one-ray pixel
// starts to count as an error. Host only: the passes hand it to the shader as a push constant.
inline float subpixelTolerance(float flipThreshold) {
    const double hyab = std::pow(static_cast<double>(flipThreshold) * SUBPIXEL_FLIP_PC * SUBPIXEL_FLIP_CMAX /
                                     SUBPIXEL_FLIP_PT,
                                 1.0 / SUBPIXEL_FLIP_QC);
    return static_cast<float>(hyab / SUBPIXEL_LSTAR_PER_DISPLAY);
}
}  // namespace aamap
#endif

#endif
