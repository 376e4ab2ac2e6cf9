#pragma once
// What the tracer sees inside each pixel (computed by tracer/pixel_facts.cpp), to explain where
// the aamap missed aliasing or spent rays for nothing (eval/metrics/pixel_causes.h): a fixed 4 x 4
// grid of primary rays per pixel, their first hits, and the light each hit receives from every
// point and area light, as one set of bits per pixel. No shading and no random numbers: the facts
// depend on the scene and the view only. Cost: about that of a 16-ray render of shadow rays alone.
#include <cstdint>

#include "core/image.h"

namespace aamap::pixel_fact {

// Bits of a pixel's facts. Several can hold at once; the classifier decides which one explains
// an error (eval/metrics/pixel_causes.cpp).
enum Bit : std::uint16_t {
    Background = 1u << 0,      // a sub-ray left the scene
    Emitter = 1u << 1,         // a sub-ray hit an emitter
    Glass = 1u << 2,           // a sub-ray hit glass (refraction)
    PlanarMirror = 1u << 3,    // a sub-ray hit a flat mirror
    CurvedMirror = 1u << 4,    // a sub-ray hit a mirror with interpolated normals, or mirror normals differ
    Silhouette = 1u << 5,      // the sub-rays hit different objects, or some hit and some escaped
    Crease = 1u << 6,          // one object, but normals differing by more than 30 degrees
    ShadowBoundary = 1u << 7,  // a point light reaches some sub-hits and not others
    Penumbra = 1u << 8,        // an area light is partly hidden from a sub-hit, or unequally across them
    Texture = 1u << 9,         // a sub-ray hit a textured material
    Glossy = 1u << 10,         // a sub-ray hit a glossy (Phong) material
};

constexpr int kGrid = 4;  // sub-rays per axis

}  // namespace aamap::pixel_fact

namespace aamap {
using PixelFacts = Image<std::uint16_t>;
}  // namespace aamap
