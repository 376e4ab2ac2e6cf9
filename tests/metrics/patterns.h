#pragma once
// Deterministic test images for the metrics tests (values in [0,1]).
#include <cmath>
#include <cstdint>

#include "core/image.h"

namespace aamap::test {

// A small xorshift generator: same sequence on every platform.
class Rng {
public:
    explicit Rng(std::uint32_t seed) : s_(seed ? seed : 1u) {}
    float next() {  // [0,1)
        s_ ^= s_ << 13;
        s_ ^= s_ >> 17;
        s_ ^= s_ << 5;
        return float(s_ >> 8) / float(1u << 24);
    }

private:
    std::uint32_t s_;
};

inline ImageRGB randomImage(int w, int h, std::uint32_t seed) {
    Rng rng(seed);
    ImageRGB img(w, h);
    for (auto& p : img.pixels()) p = {rng.next(), rng.next(), rng.next()};
    return img;
}

// Coloured gradient with a few discs and stripes: edges, flat areas and texture.
inline ImageRGB scene(int w, int h, float shiftX = 0.0f) {
    ImageRGB img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float fx = float(x) - shiftX;
            glm::vec3 c{0.2f + 0.6f * float(x) / float(w), 0.3f + 0.4f * float(y) / float(h), 0.5f};
            if (std::hypot(fx - 0.3f * float(w), float(y) - 0.4f * float(h)) < 0.2f * float(h)) c = {0.9f, 0.15f, 0.1f};
            if (std::hypot(fx - 0.7f * float(w), float(y) - 0.6f * float(h)) < 0.15f * float(h)) c = {0.05f, 0.1f, 0.8f};
            if (fx > 0.1f * float(w) && fx < 0.9f * float(w) && y > 3 * h / 4 && (int(std::floor(fx)) / 2) % 2 == 0)
                c = {0.95f, 0.95f, 0.9f};
            img.at(x, y) = c;
        }
    return img;
}

}  // namespace aamap::test
