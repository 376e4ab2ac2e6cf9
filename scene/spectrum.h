#pragma once
// Spectral values to the linear RGB the scene model holds. Mitsuba scenes (the Cornell box among
// them) give reflectances and radiances as sampled spectra; aamap renders RGB.
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace aamap {

// A piecewise-linear spectrum through (wavelength nm, value) samples, held at its end values
// outside their range, projected on the CIE 1931 colour matching functions (the multi-lobe
// Gaussian fit of Wyman, Sloan and Shirley 2013) over 360-830 nm and converted to linear sRGB.
// Normalised per channel so that a constant spectrum c gives exactly (c, c, c): reflectances
// keep their albedo, and a flat emitter stays grey. Samples need not be sorted; an empty list
// gives 0.
glm::vec3 spectrumToRgb(std::vector<std::pair<double, double>> samples);

}  // namespace aamap
