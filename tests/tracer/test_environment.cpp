// Importance sampling of environment maps (tracer/environment.h, tracer/distribution_2d.h): the
// solid-angle pdf integrates to 1 over the sphere, sample() and pdf() agree, and sampled
// directions land in each map cell in proportion to its luminance times its solid angle
// (chi-square). The map convention is checked against the formula of scene/scene.h, written out
// here independently.
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/light_file.h"
#include "scene/scene.h"
#include "tracer/distribution_2d.h"
#include "tracer/environment.h"
#include "tracer/sampler.h"

namespace aamap {
namespace {


// A W x H map with varied, strictly positive radiance and one bright cell.
EnvironmentLight variedMap(int w, int h) {
    EnvironmentLight env;
    env.name = "varied";
    env.mapWidth = w;
    env.mapHeight = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float base = 0.1f + static_cast<float>((mix64(static_cast<std::uint64_t>(y * w + x)) >> 40) % 1000) / 250.0f;
            env.map.push_back(glm::vec3(base, 0.5f * base, 2.0f * base));
        }
    env.map[static_cast<std::size_t>(h / 3) * w + w / 4] = glm::vec3(40.0f);
    return env;
}

// The map direction of cell centre (column, row) by scene/scene.h's convention, in the map frame.
glm::vec3 cellCentre(int column, int row, int w, int h) {
    const double theta = (row + 0.5) / h * std::numbers::pi, phi = (column + 0.5) / w * 2.0 * std::numbers::pi;
    return glm::vec3(glm::dvec3(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)));
}

TEST(EnvironmentSampling, MapConventionIsMitsubas) {
    EnvironmentLight env = variedMap(16, 8);
    const EnvironmentSampler s(env);
    for (int row = 0; row < 8; ++row)
        for (int column = 0; column < 16; ++column) {
            const glm::vec3 d = cellCentre(column, row, 16, 8);
            // u = atan2(x, -z) / (2 pi), v = acos(y) / pi (Mitsuba's envmap.cpp, direction_to_uv).
            const double u = std::atan2(d.x, -d.z) / (2 * std::numbers::pi), v = std::acos(d.y) / std::numbers::pi;
            EXPECT_NEAR(s.toMap(d).x, u - std::floor(u), 1e-5);
            EXPECT_NEAR(s.toMap(d).y, v, 1e-5);
            EXPECT_EQ(s.radiance(d), env.map[static_cast<std::size_t>(row) * 16 + column]);
        }
    // The sky above (+Y) is row 0 (its column is atan2's at the pole: u = 0.5, as Mitsuba's).
    EXPECT_EQ(s.toMap({0, 1, 0}).y, 0.0f);
    EXPECT_EQ(s.radiance({0, 1, 0}), env.map[static_cast<std::size_t>(s.toMap({0, 1, 0}).x * 16)]);
    // On the horizon, -Z is the left edge, +X a quarter across and +Z the centre (Mitsuba 3 puts
    // these texels there; bench/peers/mitsuba_conformance.py compares whole renders).
    EXPECT_EQ(s.radiance(glm::normalize(glm::vec3(1e-3f, 0.01f, -1.0f))), env.map[3 * 16 + 0]);
    EXPECT_EQ(s.radiance(glm::vec3(1, 0.01f, 0)), env.map[3 * 16 + 4]);
    EXPECT_EQ(s.radiance(glm::vec3(0, 0.01f, 1)), env.map[3 * 16 + 8]);
}

TEST(EnvironmentSampling, PdfIntegratesToOneOverTheSphere) {
    EnvironmentLight env = variedMap(32, 16);
    env.toLocal = environmentToLocal({0.3, 1.0, -0.2}, 37.0);  // any rotation
    const EnvironmentSampler s(env);
    // Midpoint rule in (theta, phi) on a grid much finer than the map.
    const int nt = 1024, np = 2048;
    double integral = 0.0;
    for (int i = 0; i < nt; ++i) {
        const double theta = (i + 0.5) / nt * std::numbers::pi;
        for (int j = 0; j < np; ++j) {
            const double phi = (j + 0.5) / np * 2.0 * std::numbers::pi;
            const glm::vec3 d(glm::dvec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
            integral += s.pdf(d) * std::sin(theta) * (std::numbers::pi / nt) * (2.0 * std::numbers::pi / np);
        }
    }
    EXPECT_NEAR(integral, 1.0, 2e-3);
}

TEST(EnvironmentSampling, SampleReportsThePdfOfItsDirectionAndItsRadiance) {
    EnvironmentLight env = variedMap(32, 16);
    env.toLocal = environmentToLocal({0.0, 0.0, 1.0}, -80.0);
    const EnvironmentSampler s(env);
    const Sampler rng(7, 0, 1);
    int checked = 0;
    for (int i = 0; i < 4000; ++i) {
        const EnvironmentSampler::Sample x = s.sample(rng.get2D(2 * static_cast<std::uint64_t>(i)));
        ASSERT_GT(x.pdf, 0.0f);
        EXPECT_NEAR(glm::length(x.direction), 1.0f, 1e-5f);
        // Away from cell borders (float round trip), pdf() and radiance() see the same cell.
        const glm::vec2 uv = s.toMap(x.direction);
        const float fx = uv.x * 32.0f - std::floor(uv.x * 32.0f), fy = uv.y * 16.0f - std::floor(uv.y * 16.0f);
        if (fx < 1e-3f || fx > 1 - 1e-3f || fy < 1e-3f || fy > 1 - 1e-3f) continue;
        EXPECT_NEAR(s.pdf(x.direction), x.pdf, 1e-4f * x.pdf);
        EXPECT_EQ(s.radiance(x.direction), x.radiance);
        ++checked;
    }
    EXPECT_GT(checked, 3900);
}

// Cell counts of N samples against N * luminance * solid angle / sum: Pearson's chi-square with
// W H - 1 degrees of freedom. The 0.1% critical value of chi-square(127) is 181.99; the samples
// are deterministic (counter-based), so the test cannot flake.
TEST(EnvironmentSampling, DirectionsFollowLuminanceTimesSolidAngle) {
    const int w = 16, h = 8;
    EnvironmentLight env = variedMap(w, h);
    env.toLocal = environmentToLocal({1.0, 1.0, 0.0}, 10.0);
    const EnvironmentSampler s(env);
    std::vector<double> expected(static_cast<std::size_t>(w) * h);
    double total = 0.0;
    for (int row = 0; row < h; ++row) {
        const double solidAngle = (2 * std::numbers::pi / w) * (std::cos(row * std::numbers::pi / h) - std::cos((row + 1) * std::numbers::pi / h));
        for (int column = 0; column < w; ++column) {
            const glm::vec3 c = env.map[static_cast<std::size_t>(row) * w + column];
            const double lum = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
            expected[static_cast<std::size_t>(row) * w + column] = lum * solidAngle;
            total += lum * solidAngle;
        }
    }
    const int n = 400000;
    std::vector<double> counts(expected.size(), 0.0);
    const Sampler rng(3, 0, 9);
    const glm::mat3 toLocal = env.toLocal;
    for (int i = 0; i < n; ++i) {
        const EnvironmentSampler::Sample x = s.sample(rng.get2D(2 * static_cast<std::uint64_t>(i)));
        // The cell from the direction by the convention itself, not by the sampler's cell.
        const glm::vec3 d = toLocal * x.direction;
        double u = std::atan2(d.x, -d.z) / (2 * std::numbers::pi);
        u -= std::floor(u);
        const double v = std::acos(std::clamp(static_cast<double>(d.y), -1.0, 1.0)) / std::numbers::pi;
        const int column = std::min(static_cast<int>(u * w), w - 1), row = std::min(static_cast<int>(v * h), h - 1);
        counts[static_cast<std::size_t>(row) * w + column] += 1.0;
    }
    double chi2 = 0.0;
    for (std::size_t i = 0; i < counts.size(); ++i) {
        const double e = n * expected[i] / total;
        chi2 += (counts[i] - e) * (counts[i] - e) / e;
    }
    EXPECT_LT(chi2, 181.99);
}

TEST(EnvironmentSampling, BlackCellsAreNeverSampledAndABlackMapGivesNoSamples) {
    std::vector<float> weights(8 * 4, 0.0f);
    weights[9] = 1.0f;
    weights[22] = 3.0f;
    const Distribution2D d(weights, 8, 4);
    const Sampler rng(1, 0, 2);
    int in22 = 0;
    for (int i = 0; i < 10000; ++i) {
        const Distribution2D::Sample x = d.sample(rng.get2D(2 * static_cast<std::uint64_t>(i)));
        const int cell = x.row * 8 + x.column;
        ASSERT_TRUE(cell == 9 || cell == 22) << cell;
        in22 += cell == 22 ? 1 : 0;
        EXPECT_FLOAT_EQ(x.pdf, weights[static_cast<std::size_t>(cell)] / 4.0f * 32.0f);
    }
    EXPECT_NEAR(in22 / 10000.0, 0.75, 0.02);
    // The extremes of [0,1)^2 stay on sampleable cells.
    for (const glm::vec2 u : {glm::vec2(0.0f), glm::vec2(Sampler::kOneMinusUlp), glm::vec2(0.0f, Sampler::kOneMinusUlp)}) {
        const Distribution2D::Sample x = d.sample(u);
        EXPECT_GT(x.pdf, 0.0f);
    }

    EnvironmentLight black;
    black.mapWidth = 4;
    black.mapHeight = 2;
    black.map.assign(8, glm::vec3(0.0f));
    const EnvironmentSampler s(black);
    EXPECT_FALSE(s.constant());
    EXPECT_EQ(s.sample({0.5f, 0.5f}).pdf, 0.0f);
    EXPECT_EQ(s.pdf({0, 0, 1}), 0.0f);
}

TEST(EnvironmentSampling, GuidedInversionPicksTheCellsOfABinarySearch) {
    // The guide tables only choose where the search starts: every u maps to the cell a binary
    // search over the same CDFs finds (the last cdf[i] <= u, empty intervals skipped backwards),
    // on a map with empty cells, an empty row, a spike and runs of equal CDF values.
    const int w = 37, h = 11;
    std::vector<float> weights(static_cast<std::size_t>(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            weights[i] = y == 4 || (x % 5 == 2) || x > 33 ? 0.0f : static_cast<float>((x * 7 + y * 3) % 11);
        }
    weights[static_cast<std::size_t>(6) * w + 10] = 1e6f;
    const Distribution2D d(weights, w, h);
    // The reference: cumulative sums in double, stored in float, as the class documents.
    const auto cdfOf = [](const float* v, int n) {
        std::vector<float> c(n + 1, 0.0f);
        double total = 0.0, running = 0.0;
        for (int i = 0; i < n; ++i) total += v[i];
        for (int i = 0; i < n; ++i) {
            running += v[i];
            c[i + 1] = total > 0.0 ? static_cast<float>(running / total) : static_cast<float>(i + 1) / n;
        }
        c[n] = 1.0f;
        return c;
    };
    const auto search = [](const std::vector<float>& c, float u) {
        const int n = static_cast<int>(c.size()) - 1;
        int i = std::clamp(static_cast<int>(std::upper_bound(c.begin(), c.end(), u) - c.begin()) - 1, 0, n - 1);
        while (i > 0 && !(c[i + 1] > c[i])) --i;
        return i;
    };
    std::vector<float> rows(h);
    for (int y = 0; y < h; ++y) {
        double t = 0.0;
        for (int x = 0; x < w; ++x) t += weights[static_cast<std::size_t>(y) * w + x];
        rows[y] = static_cast<float>(t);
    }
    const std::vector<float> marginal = cdfOf(rows.data(), h);
    const Sampler rng(3, 0, 2);
    std::vector<float> us = {0.0f, Sampler::kOneMinusUlp, 0.5f};
    for (float c : marginal) us.insert(us.end(), {c, std::nextafter(c, 0.0f), std::nextafter(c, 1.0f)});
    for (int i = 0; i < 20000; ++i) us.push_back(rng.get2D(static_cast<std::uint64_t>(i)).x);
    for (const float uy : us) {
        if (!(uy >= 0.0f && uy < 1.0f)) continue;
        const int row = search(marginal, uy);
        const std::vector<float> conditional = cdfOf(&weights[static_cast<std::size_t>(row) * w], w);
        for (const float ux : {uy, 1.0f - uy, conditional[static_cast<std::size_t>(row % w)], Sampler::kOneMinusUlp}) {
            if (!(ux >= 0.0f && ux < 1.0f)) continue;
            const Distribution2D::Sample s = d.sample({ux, uy});
            ASSERT_EQ(s.row, row) << "u.y " << uy;
            ASSERT_EQ(s.column, search(conditional, ux)) << "u " << ux << ", " << uy;
        }
    }
}

TEST(EnvironmentSampling, RotationTurnsTheMapAboutItsUp) {
    // A map bright only in the cell towards local +X: rotated 90 degrees about +Y
    // (right-handed), that cell is seen towards world -Z.
    const int w = 64, h = 32;
    EnvironmentLight env;
    env.mapWidth = w;
    env.mapHeight = h;
    env.map.assign(static_cast<std::size_t>(w) * h, glm::vec3(0.0f));
    // Local +X: atan2(1, 0) = pi/2, u = 0.25; y = 0, v = 0.5.
    env.map[static_cast<std::size_t>(h / 2) * w + w / 4] = glm::vec3(1.0f);
    env.toLocal = environmentToLocal({0, 1, 0}, 90.0);
    const EnvironmentSampler s(env);
    const glm::vec3 probe = glm::normalize(glm::vec3(0.01f, -0.02f, -1.0f));  // inside the cell, off its borders
    EXPECT_EQ(s.radiance(probe), glm::vec3(1.0f));
    EXPECT_EQ(s.radiance(glm::normalize(glm::vec3(1.0f, -0.02f, 0.01f))), glm::vec3(0.0f));
    // A Z-up frame: the map's +Y (row 0) is world +Z.
    env.map.assign(env.map.size(), glm::vec3(0.0f));
    for (int x = 0; x < w; ++x) env.map[static_cast<std::size_t>(x)] = glm::vec3(2.0f);
    env.toLocal = environmentToLocal({0, 0, 1}, 0.0);
    const EnvironmentSampler z(env);
    EXPECT_EQ(z.radiance({0, 0, 1}), glm::vec3(2.0f));
    EXPECT_EQ(z.radiance({0, 1, 0}), glm::vec3(0.0f));
}

}  // namespace
}  // namespace aamap
