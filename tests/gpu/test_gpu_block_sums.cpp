// The GPU block-sum pass (passes/block_sums.h) against the CPU BlockSums: same block sums to
// ~1e-6 relative, exact non-zero counts, and the same adaptive-subsampling plans, on random and
// adversarial maps and odd sizes. Also: the Snapshot builds the tables only when asked.
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "gpu_fixture.h"
#include "passes/block_sums.h"
#include "passes/snapshot.h"
#include "scene/builtin_scenes.h"
#include "tracer/block_sums.h"
#include "tracer/strategies/subsample.h"

namespace aamap::test {
namespace {

ImageGrey filled(int w, int h, float v) { return ImageGrey(w, h, v); }

ImageGrey randomMap(int w, int h, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    ImageGrey m(w, h);
    // Half the texels exactly zero, as on the flat regions of a real aamap.
    for (float& v : m.pixels()) v = u(rng) < 0.5f ? 0.0f : u(rng);
    return m;
}

// Values the tables must clamp or count specially, and tiny values next to large ones.
ImageGrey adversarialMap(int w, int h) {
    const float specials[] = {1e-20f, 1.0f, 0.0f, -0.5f, 7.0f, std::numeric_limits<float>::quiet_NaN(),
                              -0.0f,  1e-30f, 0.5f, std::numeric_limits<float>::infinity()};
    ImageGrey m(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) m.at(x, y) = specials[static_cast<std::size_t>(x * 7 + y * 3) % 10];
    return m;
}

// The count table, computed directly: texels in [0, x) x [0, y) with v > 0 or NaN.
std::uint32_t directCount(const ImageGrey& m, int x1, int y1) {
    std::uint32_t n = 0;
    for (int y = 0; y < y1; ++y)
        for (int x = 0; x < x1; ++x) n += (m.at(x, y) > 0.0f || std::isnan(m.at(x, y))) ? 1u : 0u;
    return n;
}

class BlockSumTest : public GpuTest {
protected:
    // Every rectangle of small maps; random rectangles plus every grid block of larger ones.
    void expectAgreement(const ImageGrey& map, const std::string& label) {
        const passes::BlockSumTables t = gpu_.compute(map);
        ASSERT_EQ(t.width, map.width());
        ASSERT_EQ(t.height, map.height());
        const int W = map.width(), H = map.height();
        for (int y = 0; y <= H; y += std::max(1, H / 7))
            for (int x = 0; x <= W; x += std::max(1, W / 7))
                ASSERT_EQ(t.counts[static_cast<std::size_t>(y) * (W + 1) + x], directCount(map, x, y))
                    << label << " count table at " << x << "," << y;
        const BlockSums cpu(map);
        const BlockSums gpu = BlockSums::fromTables(W, H, t.sums, t.counts);
        // Cancellation in a summed-area table scales with the entries, so near-zero blocks inside
        // a large map carry an absolute error of order total * eps in either table.
        const double total = cpu.sum(0, 0, W - 1, H - 1);
        auto check = [&](int x0, int y0, int x1, int y1) {
            const double c = cpu.sum(x0, y0, x1, y1), g = gpu.sum(x0, y0, x1, y1);
            EXPECT_EQ(c == 0.0, g == 0.0) << label << " zero test, block " << x0 << "," << y0 << "-" << x1 << "," << y1;
            EXPECT_NEAR(g, c, 1e-6 * c + 1e-11 * total)
                << label << " block " << x0 << "," << y0 << "-" << x1 << "," << y1;
        };
        if (static_cast<long>(W) * W * H * H <= 40000) {
            for (int y0 = 0; y0 < H; ++y0)
                for (int y1 = y0; y1 < H; ++y1)
                    for (int x0 = 0; x0 < W; ++x0)
                        for (int x1 = x0; x1 < W; ++x1) check(x0, y0, x1, y1);
        } else {
            std::mt19937 rng(static_cast<std::uint32_t>(W * 131 + H));
            for (int i = 0; i < 4000; ++i) {
                int x0 = static_cast<int>(rng() % W), x1 = static_cast<int>(rng() % W);
                int y0 = static_cast<int>(rng() % H), y1 = static_cast<int>(rng() % H);
                check(std::min(x0, x1), std::min(y0, y1), std::max(x0, x1), std::max(y0, y1));
            }
        }
        // The same plans: identical traced pixels and interpolated blocks.
        for (int spacing : {1, 2, 8, 16, 64})
            for (double threshold : {0.0, 0.5, 3.0, 1e9}) {
                const SubsamplePlan a = planSubsampling(cpu, spacing, threshold);
                const SubsamplePlan b = planSubsampling(gpu, spacing, threshold);
                EXPECT_TRUE(a.traced.pixels() == b.traced.pixels()) << label << " s=" << spacing << " t=" << threshold;
                ASSERT_EQ(a.interpolated.size(), b.interpolated.size()) << label << " s=" << spacing;
                for (std::size_t i = 0; i < a.interpolated.size(); ++i) {
                    EXPECT_EQ(a.interpolated[i].x0, b.interpolated[i].x0);
                    EXPECT_EQ(a.interpolated[i].y0, b.interpolated[i].y0);
                    EXPECT_EQ(a.interpolated[i].x1, b.interpolated[i].x1);
                    EXPECT_EQ(a.interpolated[i].y1, b.interpolated[i].y1);
                }
            }
    }

    passes::GpuBlockSums gpu_{context()};
};

TEST_F(BlockSumTest, RandomMapsMatchCpu) {
    for (auto [w, h] : {std::pair{1, 1}, std::pair{3, 7}, std::pair{1000, 3}, std::pair{67, 45}, std::pair{256, 256}})
        expectAgreement(randomMap(w, h, static_cast<std::uint32_t>(w * 7 + h)), "random " + std::to_string(w) + "x" +
                                                                                      std::to_string(h));
}

TEST_F(BlockSumTest, AdversarialMapsMatchCpu) {
    for (auto [w, h] : {std::pair{1, 1}, std::pair{3, 7}, std::pair{1000, 3}, std::pair{129, 65}}) {
        const std::string size = std::to_string(w) + "x" + std::to_string(h);
        expectAgreement(filled(w, h, 0.0f), "zeros " + size);
        expectAgreement(filled(w, h, 1.0f), "ones " + size);
        expectAgreement(adversarialMap(w, h), "specials " + size);
    }
}

TEST_F(BlockSumTest, AllOnesSumsAreExactAreas) {
    // Integers up to 2^24 are exact in the high float: every block sum is its pixel count.
    const ImageGrey ones = filled(300, 200, 1.0f);
    const passes::BlockSumTables t = gpu_.compute(ones);
    const BlockSums gpu = BlockSums::fromTables(300, 200, t.sums, t.counts);
    EXPECT_EQ(gpu.sum(0, 0, 299, 199), 60000.0);
    EXPECT_EQ(gpu.sum(10, 20, 17, 20), 8.0);
}

TEST_F(BlockSumTest, SnapshotBuildsTablesOnlyWhenAsked) {
    const Scene scene = builtinScene("cornell");
    SnapshotRenderer renderer(context(), scene);
    SnapshotSettings settings;
    settings.keepDebugImages = false;
    const SnapshotResult without = renderer.render(scene.views.at(0), 40, 30, settings);
    EXPECT_TRUE(without.blockSums.empty());
    EXPECT_NE(without.explain.find("block_sum_rows"), std::string::npos) << without.explain;
    for (const PassTiming& p : without.passTimes) EXPECT_EQ(p.pass.find("block_sum"), std::string::npos) << p.pass;

    settings.blockSums = true;
    const SnapshotResult with = renderer.render(scene.views.at(0), 40, 30, settings);
    ASSERT_FALSE(with.blockSums.empty());
    bool ran = false;
    for (const PassTiming& p : with.passTimes) ran = ran || p.pass == "block_sum_columns";
    EXPECT_TRUE(ran);
    const BlockSums cpu(with.aamap);
    const BlockSums gpu = BlockSums::fromTables(40, 30, with.blockSums.sums, with.blockSums.counts);
    for (int s : {2, 8}) {
        EXPECT_TRUE(planSubsampling(cpu, s, 0.0).traced.pixels() == planSubsampling(gpu, s, 0.0).traced.pixels());
        for (int y = 0; y + s <= 30; y += s)
            for (int x = 0; x + s <= 40; x += s)
                EXPECT_NEAR(gpu.sum(x, y, x + s - 1, y + s - 1), cpu.sum(x, y, x + s - 1, y + s - 1), 1e-6);
    }
}

}  // namespace
}  // namespace aamap::test
