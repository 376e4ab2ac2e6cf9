#pragma once
// Spectral values to the linear RGB the scene model holds. Mitsuba scenes (the Cornell box among
// them) give reflectances and radiances as sampled spectra; aamap renders RGB.
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace aamap {

// What a spectrum describes: RGB rendering multiplies a reflectance's RGB by the light's, so the
// two are projected differently. Both as Mitsuba 3's RGB modes read a <spectrum> (Mitsuba is the
// reference renderer of the conformance suite): 0 outside the samples, and no per-channel rescaling.
enum class SpectrumUse {
    // Seen under the D65 illuminant: XYZ = integral of rho(lambda) D65(lambda) times the matching
    // functions over the integral of D65 y-bar, then linear sRGB clamped to [0, 1]. A constant c
    // over 360-830 nm is grey c (to the fit's error); over 400-700 nm, as scene files often give
    // it, about 0.995 c, as in Mitsuba.
    Reflectance,
    // A material constant that is not bounded by 1 (a conductor's eta and k): as a reflectance,
    // but clamped at 0 only, as Mitsuba reads its unbounded spectra.
    Unbounded,
    // Absolute: XYZ = integral of L(lambda) times the matching functions over the integral of
    // y-bar, then linear sRGB, so an equal-energy spectrum is (1.20, 0.95, 0.91) as a spectral
    // renderer shows it on an sRGB (D65) display; 0 outside the samples, as Mitsuba reads them.
    Emission,
};

// A piecewise-linear spectrum through (wavelength nm, value) samples, projected on the CIE 1931
// colour matching functions (the multi-lobe Gaussian fit of Wyman, Sloan and Shirley 2013) over
// 360-830 nm and converted to linear sRGB, as `use` says. Samples need not be sorted; an empty
// list gives 0.
glm::vec3 spectrumToRgb(std::vector<std::pair<double, double>> samples, SpectrumUse use = SpectrumUse::Reflectance);

}  // namespace aamap
