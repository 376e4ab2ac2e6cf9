// Config checks that protect a study from silent loss: two renders that would share one table
// cell are an error with a did-you-mean, not a hidden render.
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/config.h"

namespace aamap {
namespace {


TEST(ConfigChecks, RendersSharingATableCellAreAnErrorWithADidYouMean) {
    const char* yaml = "scene: builtin:cornell\n"
                       "renders:\n"
                       "  - {strategy: variance, rpp: 16, noise_threshold: [0.01, 0.05], series: Variance}\n";
    try {
        parseConfig(yaml, "exp.yaml", {});
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.line(), 3) << what;
        EXPECT_NE(what.find("share one table cell"), std::string::npos) << what;
        EXPECT_NE(what.find("series: \"Variance noise_threshold={noise_threshold}\""), std::string::npos) << what;
    }
    // The suggested series (or the default one, which names what the entry wrote) is accepted.
    EXPECT_NO_THROW(parseConfig("scene: builtin:cornell\nrenders:\n  - {strategy: variance, rpp: 16, "
                                "noise_threshold: [0.01, 0.05], series: \"Variance noise_threshold={noise_threshold}\"}\n",
                                "exp.yaml", {}));
    EXPECT_NO_THROW(parseConfig("scene: builtin:cornell\nrenders:\n  - {strategy: variance, rpp: 16, "
                                "noise_threshold: [0.01, 0.05]}\n",
                                "exp.yaml", {}));
    // Two entries in one cell are caught as well.
    EXPECT_THROW(parseConfig("scene: builtin:cornell\nrenders:\n  - {strategy: uniform, rpp: 4, series: S}\n"
                             "  - {strategy: aamap, rpp: 4, series: S}\n",
                             "exp.yaml", {}),
                 InputError);
}

// The error a config gives, or "" if it parses.
std::string errorOf(const std::string& yaml) {
    try {
        parseConfig(yaml, "exp.yaml", {});
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(ConfigChecks, NumbersAreWrittenPlain) {
    const std::string head = "scene: builtin:cornell\n";
    // Quoted numbers are strings: rejected, wherever a number is read.
    for (const char* bad : {"renders:\n  - {strategy: uniform, rpp: \"4\"}\n",
                            "renders:\n  - {strategy: uniform, rpp: '4'}\n",
                            "image: {width: \"64\"}\nrenders:\n  - {strategy: uniform, rpp: 1}\n",
                            "snapshot: {gain: \"2.5\"}\nrenders:\n  - {strategy: uniform, rpp: 1}\n",
                            "seed: \"7\"\nrenders:\n  - {strategy: uniform, rpp: 1}\n",
                            "timing: {interleave: \"true\"}\nrenders:\n  - {strategy: uniform, rpp: 1}\n",
                            "camera: {position: [0, 1, \"3\"], look_at: [0, 1, 0]}\nrenders:\n  - {strategy: uniform, rpp: 1}\n",
                            "renders:\n  - {strategy: aamap-subsample, rpp: 4, spacing: \"8\"}\n"}) {
        const std::string what = errorOf(head + bad);
        EXPECT_NE(what.find("quoted string"), std::string::npos) << bad << " -> " << what;
    }
    // An integer key takes integer literals only.
    for (const char* bad : {"renders:\n  - {strategy: uniform, rpp: 4.0}\n",
                            "renders:\n  - {strategy: uniform, rpp: [1, 4.0]}\n",
                            "image: {width: 64.0}\nrenders:\n  - {strategy: uniform, rpp: 1}\n",
                            "renders:\n  - {strategy: aamap-subsample, rpp: 4, spacing: 8.0}\n"}) {
        const std::string what = errorOf(head + bad);
        EXPECT_NE(what.find("expected an integer"), std::string::npos) << bad << " -> " << what;
    }
    // What the docs write is accepted.
    EXPECT_EQ(errorOf(head + "image: {width: 64, exposure: 2}\nrenders:\n  - {strategy: aamap-subsample, rpp: 4, spacing: 8}\n"),
              "");
}

TEST(ConfigChecks, LightKeyTypoGetsADidYouMean) {
    const std::string what = errorOf("scene: builtin:cornell\nlights:\n  - {type: point, position: [0, 1, 0], "
                                     "intensty: [1, 1, 1]}\nrenders:\n  - {strategy: uniform, rpp: 1}\n");
    EXPECT_NE(what.find("did you mean 'intensity'"), std::string::npos) << what;
    EXPECT_NE(what.find("exp.yaml:3"), std::string::npos) << what;
    // A typo of a required key reads as a typo, not as the missing key.
    const std::string position = errorOf("scene: builtin:cornell\nlights:\n  - {type: point, positon: [0, 1, 0], "
                                         "intensity: [1, 1, 1]}\nrenders:\n  - {strategy: uniform, rpp: 1}\n");
    EXPECT_NE(position.find("did you mean 'position'"), std::string::npos) << position;
}

}  // namespace
}  // namespace aamap
