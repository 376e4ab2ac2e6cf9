#pragma once
// Image files: EXR for data (linear float), PNG for looking at (8-bit sRGB), and the false-colour
// rendering of rays-per-pixel maps. Every writer goes through writeFileAtomically, so a file under
// its final name is always complete. Writers throw EnvironmentError, readers throw InputError.
#include <cstdint>
#include <filesystem>

#include <glm/vec3.hpp>
#include <glm/ext/vector_uint3_sized.hpp>

#include "core/image.h"

namespace aamap {

using ImageRGB8 = Image<glm::u8vec3>;
using ImageGrey8 = Image<std::uint8_t>;

// Linear float EXR: RGB as channels R, G, B; greyscale maps as the single channel Y.
void writeExr(const std::filesystem::path& path, const ImageRGB& image);
void writeExr(const std::filesystem::path& path, const ImageGrey& image);

// Reads R, G, B (a Y-only file is replicated into all three).
ImageRGB readExr(const std::filesystem::path& path);
// Reads Y (an RGB file is rejected: the caller asked for a map).
ImageGrey readExrGrey(const std::filesystem::path& path);

void writePng(const std::filesystem::path& path, const ImageRGB8& image);
void writePng(const std::filesystem::path& path, const ImageGrey8& image);
// Any PNG, expanded to RGB.
ImageRGB8 readPng(const std::filesystem::path& path);

// Display encoding for radiance: multiply by exposure, clamp to [0,1], sRGB OETF, round.
// Non-finite values become black.
ImageRGB8 toneMap(const ImageRGB& image, float exposure = 1.0f);
// Display encoding for data maps: value * scale clamped to [0,1], linear (no OETF: a map value
// of 0.5 should read back as 128).
ImageGrey8 quantise(const ImageGrey& image, float scale = 1.0f);

float srgbEncode(float linear);  // the sRGB OETF on [0,1]
// The display value of one linear channel, as toneMap() shows it before rounding: exposure,
// non-finite -> 0, clamp to [0,1], sRGB OETF. What the display-space metrics and the Space
// strategy's gradient test compare.
float displayEncode(float linear, float exposure = 1.0f);

// Perceptual colour ramp (viridis) for t in [0,1].
glm::u8vec3 colourRamp(float t);

// Rays-per-pixel map in false colour with a legend strip below it that names the scale
// ("rays/pixel", ticks from 1 to maxRpp). Colour is linear in rays, so it reads as cost.
// 0 rays (an interpolated pixel) is black. The canvas is widened if the image is too narrow for
// the legend; the image sits in the top-left corner.
ImageRGB8 falseColour(const Image<std::uint16_t>& rpp, int maxRpp);

// Height of the legend strip falseColour() appends for an image of the given width (for tests).
int falseColourLegendHeight(int width);

}  // namespace aamap
