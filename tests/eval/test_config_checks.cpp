// Config checks that protect a study from silent loss: every shipped experiment parses, and two
// renders that would share one table cell are an error with a did-you-mean, not a hidden render.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/config.h"

namespace aamap {
namespace {

namespace fs = std::filesystem;

TEST(ConfigChecks, EveryShippedConfigParses) {
    int parsed = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(AAMAP_SOURCE_DIR) / "configs")) {
        if (entry.path().extension() != ".yaml") continue;
        EXPECT_NO_THROW(loadConfig(entry.path().string(), {})) << entry.path();
        ++parsed;
    }
    EXPECT_GE(parsed, 4);
}

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

}  // namespace
}  // namespace aamap
