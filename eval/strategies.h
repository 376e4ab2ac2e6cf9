#pragma once
// The strategies a render may name, with their parameters: the schema side of the table (names,
// ranges, defaults, documentation). The runner side, which turns an entry into the tracer's
// StrategySettings, is eval/strategy_settings.cpp. Adding a strategy = one entry in each.
#include <string>
#include <vector>

namespace aamap {

struct StrategyParam {
    std::string name;     // the YAML key inside renders[] (a list value sweeps it)
    bool integer = false;
    double lo = 0, hi = 0;  // inclusive range
    double defaultValue = 0;
    std::string doc;
    std::vector<std::string> choices;  // non-empty: a named option, stored as its index
};

struct StrategyInfo {
    std::string name;       // renders[].strategy
    bool usesAamap = false;  // needs the Snapshot (and so the GPU, unless cached)
    std::vector<StrategyParam> params;
    std::string doc;
};

// In documentation order; the first entry ("uniform") is the baseline of speedups.
const std::vector<StrategyInfo>& strategyTable();
// Adds (or replaces) an entry at run time: for tests and for custom RenderBackends. Not
// thread-safe; call before parsing configs.
void registerStrategy(StrategyInfo info);
const StrategyInfo* findStrategy(const std::string& name);
std::vector<std::string> strategyNames();
// A parameter value as text (a choice's name, else formatParam) and as JSON (string or number).
std::string paramText(const std::string& strategy, const std::string& key, double value);
const StrategyParam* findParam(const std::string& strategy, const std::string& key);

// Every parameter name of every strategy, deduplicated, in table order (for --set paths).
std::vector<std::string> allStrategyParamNames();

}  // namespace aamap
