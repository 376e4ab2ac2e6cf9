#pragma once
// Factories for the multi-pass strategies (parameters already validated by makeStrategy).
#include <memory>

#include "tracer/strategy.h"

namespace aamap {

std::unique_ptr<SamplingStrategy> makeSubsampleStrategy(int n, StrataMapping mapping, int spacing, double threshold,
                                                        const ImageGrey& map);
std::unique_ptr<SamplingStrategy> makeRpictStrategy(int spacing, double threshold);
std::unique_ptr<SamplingStrategy> makeSupersampleStrategy(int n, int factor, DownFilter filter, double radius);
std::unique_ptr<SamplingStrategy> makeVarianceStrategy(int n, double noiseThreshold, int minSamples, int sampleStep);
std::unique_ptr<SamplingStrategy> makeShapeIdStrategy(int n, int minSamples);

}  // namespace aamap
