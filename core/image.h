#pragma once
// A plain row-major image, the one pixel container shared by the snapshot, tracer and metrics.
#include <cassert>
#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

namespace aamap {

template <class Pixel>
class Image {
public:
    Image() = default;
    Image(int width, int height, Pixel fill = Pixel{})
        : width_(width), height_(height), pixels_(static_cast<std::size_t>(width) * height, fill) {}

    int width() const { return width_; }
    int height() const { return height_; }
    std::size_t size() const { return pixels_.size(); }
    bool empty() const { return pixels_.empty(); }

    Pixel& at(int x, int y) {
        assert(x >= 0 && x < width_ && y >= 0 && y < height_);
        return pixels_[static_cast<std::size_t>(y) * width_ + x];
    }
    const Pixel& at(int x, int y) const {
        assert(x >= 0 && x < width_ && y >= 0 && y < height_);
        return pixels_[static_cast<std::size_t>(y) * width_ + x];
    }
    Pixel* data() { return pixels_.data(); }
    const Pixel* data() const { return pixels_.data(); }
    std::vector<Pixel>& pixels() { return pixels_; }
    const std::vector<Pixel>& pixels() const { return pixels_; }

    friend bool operator==(const Image&, const Image&) = default;

private:
    int width_ = 0;
    int height_ = 0;
    std::vector<Pixel> pixels_;
};

using ImageRGB = Image<glm::vec3>;  // linear radiance, row 0 at the top
using ImageGrey = Image<float>;

}  // namespace aamap
