// The registry from the tracer's side: every declared parameter reaches the strategy it configures
// (the resolved value shows in describe()), and makeStrategy checks what a strategy needs.
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "tracer/block_sums.h"
#include "tracer/strategy.h"

namespace aamap {
namespace {

// A value of p other than its default, as far from it as the range allows.
ParamValue otherValue(const ParamSpec& p) {
    if (p.type == ParamType::Choice) return p.choices.back();
    const double v = p.hi != p.defaultValue ? p.hi : p.lo;
    if (p.type == ParamType::Int) return static_cast<int>(v);
    return v;
}

TEST(StrategyParams, EveryParameterReachesItsStrategy) {
    constexpr int kSize = 8, kStrata = 16;  // n = 16: the largest values still fit the 16-bit ray map
    const ImageGrey map(kSize, kSize, 0.5f);
    for (const StrategyDescriptor& d : strategyRegistry()) {
        StrategySettings s;
        s.name = d.name;
        s.strata = kStrata;
        s.aamap = &map;
        const std::string defaults = makeStrategy(s, kSize, kSize)->describe();
        EXPECT_EQ(defaults.rfind(d.name + " ", 0), 0u) << defaults;  // named as registered
        for (const ParamSpec& p : d.params) {
            SCOPED_TRACE(d.name + "." + p.name);
            StrategySettings changed = s;
            changed.params.set(p.name, otherValue(p));
            EXPECT_NE(makeStrategy(changed, kSize, kSize)->describe(), defaults);
        }
    }
}

TEST(StrategyParams, ResolveTypesChecksAndFillsDefaults) {
    const StrategyDescriptor& d = *findStrategy("aamap-subsample");
    const StrategyParams p = resolveParams(d, {{"threshold", 2}, {"spacing", 16.0}});
    EXPECT_EQ(p.entries().front().first, "spacing");  // schema order
    EXPECT_EQ(p.integer("spacing"), 16);               // an integral real narrowed
    EXPECT_EQ(p.real("threshold"), 2.0);               // an int widened
    EXPECT_EQ(p.choice("mapping"), "paper");           // the default
    EXPECT_EQ(resolveParams(d, {{"threshold", std::numeric_limits<double>::infinity()}}).real("threshold"),
              std::numeric_limits<double>::infinity());
    EXPECT_THROW(resolveParams(d, {{"spacing", 8.5}}), std::invalid_argument);
    EXPECT_THROW(resolveParams(d, {{"spacing", "eight"}}), std::invalid_argument);
    EXPECT_THROW(resolveParams(d, {{"mapping", 1}}), std::invalid_argument);  // choices by name only
    EXPECT_THROW(resolveParams(d, {{"threshold", std::numeric_limits<double>::quiet_NaN()}}), std::invalid_argument);
    EXPECT_THROW(resolveParams(d, {{"sample_step", 4}}), std::invalid_argument);  // another strategy's
    EXPECT_THROW(p.real("spacing"), std::invalid_argument);                        // typed reads
    EXPECT_THROW(p.integer("min_samples"), std::invalid_argument);

    const ParamSpec& spacing = *d.param("spacing");
    EXPECT_EQ(spacing.clamp(0), ParamValue(1));
    EXPECT_EQ(spacing.clamp(1000.0), ParamValue(64));
    EXPECT_EQ(d.param("mapping")->clamp(std::string("linear")), ParamValue(std::string("paper")));
}

TEST(StrategyParams, MakeStrategyChecksTheNeeds) {
    const ImageGrey map(8, 8, 0.0f), small(4, 8, 0.0f);
    const BlockSums otherSums(ImageGrey(9, 8, 0.0f));
    for (const StrategyDescriptor& d : strategyRegistry()) {
        SCOPED_TRACE(d.name);
        StrategySettings s;
        s.name = d.name;
        s.strata = 2;
        EXPECT_EQ(d.usesAamap, [&] {
            try {
                makeStrategy(s, 8, 8);
                return false;
            } catch (const std::invalid_argument&) {
                return true;
            }
        }()) << "no map";
        s.aamap = &small;
        if (d.usesAamap) {
            EXPECT_THROW(makeStrategy(s, 8, 8), std::invalid_argument);
        }
        s.aamap = &map;
        EXPECT_NO_THROW(makeStrategy(s, 8, 8));
        s.blockSums = &otherSums;
        if (d.needsBlockSums) {
            EXPECT_THROW(makeStrategy(s, 8, 8), std::invalid_argument);
        }
    }
}

}  // namespace
}  // namespace aamap
