#pragma once
// The strategies a render may name, as the config, --set, --help and docs/config.md see them: the
// tracer's registry (tracer/strategy.h), where each strategy declares its own parameters.
#include <string>
#include <vector>

#include "tracer/strategy.h"

namespace aamap {

// Every parameter name of every strategy, deduplicated, in registry order (for --set paths).
std::vector<std::string> allStrategyParamNames();

// A strategy's parameters, each as ParamSpec::summary, ", "-joined ("none" without any): the
// parameters column of docs/config.md's strategy table (markdown) and the --help lines.
std::string strategyParamsText(const StrategyDescriptor& strategy, bool markdown);
// `aamap run --help`: a line per strategy, name, [aamap] when it uses the map, its parameters.
std::string strategyHelpLines();

}  // namespace aamap
