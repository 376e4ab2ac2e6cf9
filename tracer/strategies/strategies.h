#pragma once
// Factories for the multi-pass strategies (parameters already validated by makeStrategy).
#include <memory>

#include "tracer/strategy.h"

namespace aamap {

// sums: precomputed block sums of `map` (null: built on the CPU at render time).
std::unique_ptr<SamplingStrategy> makeSubsampleStrategy(int n, StrataMapping mapping, int spacing, double threshold,
                                                        const ImageGrey& map, const BlockSums* sums);
std::unique_ptr<SamplingStrategy> makeRpictStrategy(int spacing, double threshold);
std::unique_ptr<SamplingStrategy> makeSupersampleStrategy(int n, int factor, DownFilter filter, double radius);
std::unique_ptr<SamplingStrategy> makeVarianceStrategy(int n, double noiseThreshold, int minSamples, int sampleStep);
std::unique_ptr<SamplingStrategy> makeShapeIdStrategy(int n, int minSamples);
std::unique_ptr<SamplingStrategy> makeHybridStrategy(int n, StrataMapping mapping, double noiseThreshold,
                                                     int sampleStep, const ImageGrey& map);

}  // namespace aamap
