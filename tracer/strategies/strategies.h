#pragma once
// The built-in strategies, each declared by its own file (tracer/strategy.cpp lists them).
#include "tracer/strategy.h"

namespace aamap {

StrategyDescriptor uniformStrategy();      // strategies/uniform.cpp
StrategyDescriptor aamapStrategy();        // strategies/aamap.cpp
StrategyDescriptor subsampleStrategy();    // strategies/subsample.cpp
StrategyDescriptor rpictStrategy();        // strategies/rpict.cpp
StrategyDescriptor supersampleStrategy();  // strategies/supersample.cpp
StrategyDescriptor varianceStrategy();     // strategies/variance.cpp
StrategyDescriptor shapeIdStrategy();      // strategies/shape_id.cpp
StrategyDescriptor hybridStrategy();       // strategies/hybrid.cpp

}  // namespace aamap
