// Test images for the CPU filter chain: seeded random images and bit-for-bit comparison.
#pragma once

#include <cstdint>
#include <cstring>
#include <random>

#include <glm/vec3.hpp>

#include "core/image.h"

namespace aamap::cpu::test_images {

inline ImageRGB randomRgb(int w, int h, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.2f);  // some values above 1 exercise the clamp
    ImageRGB img(w, h);
    for (auto& p : img.pixels()) p = glm::vec3(u(rng), u(rng), u(rng));
    return img;
}

inline ImageGrey randomGrey(int w, int h, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    ImageGrey img(w, h);
    for (float& v : img.pixels()) v = u(rng);
    return img;
}

inline bool bitIdentical(const ImageGrey& a, const ImageGrey& b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

}  // namespace aamap::cpu::test_images
