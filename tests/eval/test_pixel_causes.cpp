// Causes of missed and wasted pixels (eval/metrics/pixel_causes.h): the classifier's priorities,
// the counts against synthetic error maps, and the runner putting them into results and report.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "eval/config.h"
#include "eval/metrics/pixel_causes.h"
#include "eval/report.h"
#include "eval/results.h"
#include "eval/runner.h"
#include "tests/eval/fake_backend.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;
using namespace metrics;
using namespace pixel_fact;

TEST(PixelCauses, OneCausePerPixelByPriority) {
    EXPECT_EQ(classify(0, false), PixelCause::Other);
    EXPECT_NE(classify(0xffff, false), PixelCause::BesideError) << "facts alone never say 'beside an error'";
    EXPECT_EQ(classify(Silhouette | pixel_fact::Texture, true), PixelCause::Interpolated) << "no ray looked at it";
    EXPECT_EQ(classify(Silhouette | pixel_fact::Texture | ShadowBoundary, false), PixelCause::Silhouette);
    EXPECT_EQ(classify(Glass | Silhouette, false), PixelCause::Glass);
    EXPECT_EQ(classify(Emitter | Glass, false), PixelCause::Emitter);
    EXPECT_EQ(classify(PlanarMirror | Silhouette, false), PixelCause::PlanarMirror);
    EXPECT_EQ(classify(CurvedMirror, false), PixelCause::CurvedMirror);
    EXPECT_EQ(classify(ShadowBoundary | Penumbra | pixel_fact::Texture, false), PixelCause::ShadowBoundary);
    EXPECT_EQ(classify(Penumbra | pixel_fact::Texture, false), PixelCause::Penumbra);
    EXPECT_EQ(classify(pixel_fact::Texture | Glossy, false), PixelCause::Texture);
    EXPECT_EQ(classify(Glossy | Crease, false), PixelCause::Highlight);
    EXPECT_EQ(classify(Crease, false), PixelCause::Crease);
    EXPECT_EQ(classify(Background, false), PixelCause::Other) << "plain sky";
    // Names and keys are distinct, so tables and JSON never merge two causes.
    for (int i = 0; i < kPixelCauses; ++i)
        for (int j = i + 1; j < kPixelCauses; ++j) {
            EXPECT_STRNE(toString(static_cast<PixelCause>(i)), toString(static_cast<PixelCause>(j)));
            EXPECT_STRNE(key(static_cast<PixelCause>(i)), key(static_cast<PixelCause>(j)));
        }
}

TEST(PixelCauses, RenderAndMapCountsFollowTheirDefinitions) {
    // 4 x 1 pixels: silhouette, texture, plain, plain.
    PixelFacts facts(4, 1, 0);
    facts.at(0, 0) = Silhouette;
    facts.at(1, 0) = pixel_fact::Texture;
    ImageGrey error(4, 1, 0.0f), oneRay(4, 1, 0.0f), aamap(4, 1, 0.0f);
    Image<std::uint16_t> rays(4, 1, 1);
    error.at(0, 0) = 0.5f;   // the render still errs at the silhouette...
    oneRay.at(0, 0) = 0.5f;  // ...which the 1-ray image got wrong too
    rays.at(1, 0) = 16;      // 16 rays on the texture, where one was enough
    rays.at(2, 0) = 0;       // an interpolated pixel, in error
    error.at(2, 0) = 0.3f;
    ImageRGB8 image;
    Image<std::uint8_t> own(4, 1, 1);
    const CauseCounts r = renderCauses(facts, error, oneRay, rays, &own, 0.1f, &image);
    EXPECT_EQ(r.missed[static_cast<int>(PixelCause::Silhouette)], 1u);
    EXPECT_EQ(r.missed[static_cast<int>(PixelCause::Interpolated)], 1u);
    EXPECT_EQ(r.wasted[static_cast<int>(PixelCause::Texture)], 1u);
    EXPECT_EQ(r.missedTotal(), 2u);
    EXPECT_EQ(r.wastedTotal(), 1u);
    EXPECT_EQ(image.at(0, 0), colour(PixelCause::Silhouette));
    EXPECT_EQ(image.at(3, 0), glm::u8vec3(0)) << "neither missed nor wasted";

    aamap.at(1, 0) = 1.0f;  // flags the texture (not aliased) and misses the silhouette
    const CauseCounts m = mapCauses(facts, oneRay, aamap, nullptr, 0.1f, nullptr);
    EXPECT_EQ(m.missed[static_cast<int>(PixelCause::Silhouette)], 1u);
    EXPECT_EQ(m.wasted[static_cast<int>(PixelCause::Texture)], 1u);
    EXPECT_EQ(m.missedTotal() + m.wastedTotal(), 2u);
    EXPECT_THROW(renderCauses(PixelFacts(3, 1, 0), error, oneRay, rays, nullptr, 0.1f, nullptr), std::invalid_argument);
    // A missed pixel whose own display value equals the reference's is beside an error, whatever
    // its facts: FLIP rose there from a neighbour.
    own.at(0, 0) = 0;
    const CauseCounts spread = renderCauses(facts, error, oneRay, rays, &own, 0.1f, nullptr);
    EXPECT_EQ(spread.missed[static_cast<int>(PixelCause::BesideError)], 1u);
    EXPECT_EQ(spread.missed[static_cast<int>(PixelCause::Silhouette)], 0u);
}

TEST(PixelCauses, RunnerReportsThemAndCachesTheFacts) {
    const fs::path dir = fs::path(::testing::TempDir()) / "pixel_causes_runner";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string yaml = "scene: builtin:cornell\nimage: {width: 48, height: 32}\n"
                             "renders:\n  - {strategy: uniform, rpp: 16}\n  - {strategy: aamap, rpp: 16}\n"
                             "report: {plots: false}\n";
    const ExperimentConfig c = parseConfig(yaml, (dir / "exp.yaml").string(), {});
    FakeBackend backend;
    backend.withFacts = true;
    const Results first = runExperimentWith(c, dir / "out", backend, RunnerOptions{"test-rev", false});
    EXPECT_EQ(backend.factsComputed, 1);
    ASSERT_TRUE(first.mapQuality.contains("causes"));
    for (const RenderRecord& r : first.renders) {
        ASSERT_TRUE(r.metrics.contains("causes")) << r.name;
        EXPECT_TRUE(fs::exists(dir / "out" / (r.name + ".causes.png"))) << r.name;
        // The fake's error sits on its edge column, whose facts say silhouette: every missed
        // pixel there is a silhouette, the rest (FLIP spreading beside it) plain.
        const auto& missed = r.metrics["causes"]["missed"];
        std::uint64_t sum = 0;
        for (const auto& [k, v] : missed.items()) sum += v.get<std::uint64_t>();
        EXPECT_EQ(sum, r.metrics["causes"]["missed_total"].get<std::uint64_t>());
        EXPECT_EQ(missed["interpolated"], 0);
        EXPECT_EQ(missed["other"], 0) << "the fake's errors sit on its edge, or beside it";
    }
    EXPECT_TRUE(fs::exists(dir / "out" / "causes.png"));
    const std::string html = [&] {
        std::ifstream in(dir / "out" / "report.html");
        return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    EXPECT_NE(html.find("Causes: why error pixels remain"), std::string::npos);
    EXPECT_NE(html.find("Causes: where extra rays bought nothing"), std::string::npos);

    // A second run computes no facts: they come from the cache like the renders.
    FakeBackend again;
    again.withFacts = true;
    runExperimentWith(c, dir / "out", again, RunnerOptions{"test-rev", false});
    EXPECT_EQ(again.factsComputed, 0);
    EXPECT_EQ(again.prepares, 0) << "a fully cached run loads no scene";
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aamap
