#include "eval/strategies.h"

#include <algorithm>

#include <fmt/format.h>

namespace aamap {

std::vector<std::string> allStrategyParamNames() {
    std::vector<std::string> names;
    for (const StrategyDescriptor& s : strategyRegistry())
        for (const ParamSpec& p : s.params)
            if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
    return names;
}

std::string strategyParamsText(const StrategyDescriptor& strategy, bool markdown) {
    std::vector<std::string> params;
    for (const ParamSpec& p : strategy.params) params.push_back(p.summary(markdown));
    return params.empty() ? "none" : fmt::format("{}", fmt::join(params, ", "));
}

std::string strategyHelpLines() {
    std::string lines;
    for (const StrategyDescriptor& s : strategyRegistry())
        lines += fmt::format("    {:<16}{}{}\n", s.name, s.usesAamap ? "[aamap] " : "",
                             s.params.empty() ? "no parameters" : strategyParamsText(s, false));
    return lines;
}

}  // namespace aamap
