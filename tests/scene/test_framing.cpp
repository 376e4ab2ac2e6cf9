// Views without a view file: lookAtView's angles, and framingView keeping the whole scene in view.
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "scene/camera.h"
#include "scene/framing.h"
#include "scene/view_file.h"

namespace aamap {
namespace {

TEST(LookAtView, FovIsHorizontalAndPixelsAreSquare) {
    const View v = lookAtView({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60.0f, 300, 150);
    EXPECT_FLOAT_EQ(v.horizontalFovDeg, 60.0f);
    EXPECT_NEAR(std::tan(glm::radians(v.verticalFovDeg) / 2), std::tan(glm::radians(30.0f)) / 2, 1e-6f);
    EXPECT_EQ(fitResolution(v, 300, 150), std::make_pair(300, 150));
    EXPECT_NEAR(v.direction.z, -1.0f, 1e-6f);
}

TEST(LookAtView, RejectsDegenerateCameras) {
    EXPECT_THROW(lookAtView({1, 1, 1}, {1, 1, 1}, {0, 1, 0}, 45, 10, 10), std::invalid_argument);
    EXPECT_THROW(lookAtView({0, 5, 0}, {0, 0, 0}, {0, 1, 0}, 45, 10, 10), std::invalid_argument);
    EXPECT_THROW(lookAtView({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 180, 10, 10), std::invalid_argument);
}

// Every corner of the bounds lands inside the image, for wide, tall and square images and for
// scenes of very different sizes and places (millimetres, far from the origin).
TEST(FramingView, EveryCornerIsInView) {
    const Bounds cases[] = {{{-1, -1, -1}, {1, 1, 1}},
                            {{0, 0, 0}, {556, 548.8f, 559.2f}},
                            {{1000, -3, 20}, {1010, 40, 21}},
                            {{-0.01f, 0, 0}, {0.01f, 0.001f, 0.3f}}};
    const std::pair<int, int> sizes[] = {{512, 512}, {640, 360}, {300, 600}};
    for (const Bounds& b : cases) {
        for (const auto& [w, h] : sizes) {
            const View v = framingView(b, w, h);
            const PinholeCamera cam = PinholeCamera::fromView(v);
            for (int i = 0; i < 8; ++i) {
                const glm::vec3 p(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z);
                const glm::vec3 d = p - cam.origin;
                const float z = glm::dot(d, cam.forward);
                ASSERT_GT(z, 0.0f);
                EXPECT_LE(std::abs(glm::dot(d, cam.right) / z), cam.tanHalfH * 1.0001f) << w << "x" << h;
                EXPECT_LE(std::abs(glm::dot(d, cam.up) / z), cam.tanHalfV * 1.0001f) << w << "x" << h;
            }
            EXPECT_EQ(fitResolution(v, w, h), std::make_pair(w, h));
        }
    }
}

}  // namespace
}  // namespace aamap
