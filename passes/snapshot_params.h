#pragma once
// The `snapshot` config section, declared once: the Snapshot's settings (passes/snapshot.h).
// The config reader, --set, --help and docs/config.md are generated from this list.
#include <vector>

#include "core/params.h"

namespace aamap {

const std::vector<ParamSpec>& snapshotParams();

}  // namespace aamap
