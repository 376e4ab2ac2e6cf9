#include "eval/strategies.h"

#include <algorithm>

#include "eval/config.h"

namespace aamap {

// One entry per strategy (names as tracer/strategy.cpp's toString), plus its case in
// strategy_settings.cpp. A parameter: {name, integer, lo, hi, default, doc[, choices]}.
namespace {
const StrategyParam kMapping = {"mapping", true, 0, 1, 0, "map value -> strata: paper (k = 1 + round(a (n-1))) or "
                                "linear-rays (rays linear in a)", {"paper", "linear-rays"}};

std::vector<StrategyInfo>& table() {
    static std::vector<StrategyInfo> t = {
        {"uniform", false, {}, "n x n jittered rays in every pixel (the paper's standard render)"},
        {"aamap", true, {kMapping}, "k x k rays, k from the aamap (the paper's non-adaptive selective render)"},
        {"aamap-subsample", true,
         {{"spacing", true, 1, 64, 8, "grid spacing s in pixels (the paper's Space 8 / Space 16)"},
          {"threshold", false, 0, 1e9, 0, "blocks whose aamap sum exceeds it are split, the rest interpolated"},
          kMapping},
         "adaptive subsampling guided by the aamap, then k x k rays in traced pixels (paper section 4)"},
        {"rpict", false,
         {{"spacing", true, 1, 64, 4, "-ps: initial sample spacing"},
          {"threshold", false, 0, 1e9, 0.05, "-pt: relative colour/depth difference that forces a split"}},
         "Radiance rpict-style adaptive subsampling by image contrast (no aamap)"},
        {"supersample", false,
         {{"supersample", true, 2, 3, 2, "render at this factor of the resolution"},
          {"filter", true, 0, 1, 0, "down filter, as pfilt", {"box", "gaussian"}},
          {"filter_radius", false, 0.01, 10, 0.6, "gaussian: radius in output pixels"}},
         "supersample and filter down (pfilt)"},
        {"variance", false,
         {{"noise_threshold", false, 0, 1e9, 0.01, "pixels whose error estimate is at least this get more samples"},
          {"min_samples", true, 2, 1024, 4, "first round of samples per pixel"},
          {"sample_step", true, 1, 1024, 4, "samples added per round"}},
         "variance-driven adaptive sampling (Cycles)"},
        {"shape-id", false,
         {{"min_samples", true, 1, 1024, 4, "first samples per pixel (rounded down to a square)"}},
         "n x n more samples where the first ones hit different shapes (pbrt-v2)"},
        {"hybrid", true,
         {kMapping,
          {"noise_threshold", false, 0, 1e9, 0.01, "flagged pixels stop adding samples once their error is below it"},
          {"sample_step", true, 1, 1024, 4, "samples added per round to a flagged pixel"}},
         "the aamap says where to look (1 ray elsewhere), sample contrast where to stop (beyond the paper)"},
    };
    return t;
}
}  // namespace

const std::vector<StrategyInfo>& strategyTable() { return table(); }

void registerStrategy(StrategyInfo info) {
    for (StrategyInfo& s : table())
        if (s.name == info.name) {
            s = std::move(info);
            return;
        }
    table().push_back(std::move(info));
}

const StrategyInfo* findStrategy(const std::string& name) {
    for (const StrategyInfo& s : strategyTable())
        if (s.name == name) return &s;
    return nullptr;
}

std::vector<std::string> strategyNames() {
    std::vector<std::string> names;
    for (const StrategyInfo& s : strategyTable()) names.push_back(s.name);
    return names;
}

const StrategyParam* findParam(const std::string& strategy, const std::string& key) {
    const StrategyInfo* s = findStrategy(strategy);
    if (s == nullptr) return nullptr;
    for (const StrategyParam& p : s->params)
        if (p.name == key) return &p;
    return nullptr;
}

std::string paramText(const std::string& strategy, const std::string& key, double value) {
    const StrategyParam* p = findParam(strategy, key);
    if (p != nullptr && !p->choices.empty()) {
        const auto i = static_cast<std::size_t>(value);
        return i < p->choices.size() ? p->choices[i] : "?";
    }
    return formatParam(value);
}

std::vector<std::string> allStrategyParamNames() {
    std::vector<std::string> names;
    for (const StrategyInfo& s : strategyTable())
        for (const StrategyParam& p : s.params)
            if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
    return names;
}

}  // namespace aamap
