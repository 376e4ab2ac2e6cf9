#pragma once
// A strategy's parameters: the schema a strategy declares (core/params.h ParamSpec, one per
// parameter) and the typed values a render hands it (StrategyParams, keyed by name). The one place
// where a value is checked against its range, for the config, --set, the viewer and the tracer alike.
#include "core/params.h"

namespace aamap {

// A render's strategy values: int, real or a choice's name, in schema order once resolved.
using StrategyParams = ParamValues;

}  // namespace aamap
