#pragma once
// The aamap filter chain on the CPU: the reference the GPU passes are tested against, the
// fallback when no Vulkan device is usable, and the CPU side of the filter benchmark.
// Each stage exists as a scalar single-threaded version (the reference) and a TBB-parallel,
// vectorised version that gives bit-identical results; both follow glsl/shared/aamap_filter.h
// (the Laplacian summed exactly in fixed point or double: see cpu_aamap.cpp).
#include "core/image.h"
#include "passes/filter_params.h"

namespace aamap::cpu {

enum class Mode { Scalar, Parallel };

ImageGrey greyscale(const ImageRGB& rgb, float exposure, Mode mode = Mode::Parallel);
ImageGrey laplacianMagnitude(const ImageGrey& grey, Mode mode = Mode::Parallel);  // e = |L|
// The flat gate (aamap_filter.h step 2): zeroes edges wherever the 3x3 window of grey around the
// texel spans less than flatRange; flatRange <= 0 leaves edges as they are. Same size, finite grey.
void flatGate(const ImageGrey& grey, ImageGrey& edges, float flatRange, Mode mode = Mode::Parallel);
ImageGrey boxBlur(const ImageGrey& edges, int radius, Mode mode = Mode::Parallel);
// The same, into `out` (resized only when its size differs, so a kept image costs no allocation
// or zero-fill; it must not be the input). Identical results.
void laplacianMagnitudeInto(const ImageGrey& grey, ImageGrey& out, Mode mode = Mode::Parallel);
void boxBlurInto(const ImageGrey& edges, int radius, ImageGrey& out, Mode mode = Mode::Parallel);
ImageGrey deadZone(const ImageGrey& blurred, float noiseFloor, float gain, Mode mode = Mode::Parallel);
ImageGrey reduceMax(const ImageGrey& map, int width, int height, Mode mode = Mode::Parallel);

struct AamapImages {
    ImageGrey grey;       // snapshot resolution
    ImageGrey laplacian;  // |L| after the flat gate, snapshot resolution
    ImageGrey aamap;      // render resolution, in [0,1]
};
AamapImages buildAamap(const ImageRGB& snapshot, int width, int height, const FilterParams& params,
                       Mode mode = Mode::Parallel);

}  // namespace aamap::cpu
