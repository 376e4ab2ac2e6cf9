// Mock resources and passes for the render-graph tests: only names, usages and sizes matter to
// the compiler and to its text views.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "engine/graph/render_graph.h"

namespace aamap::graph::mock {

inline ResourceDesc image(std::string name, Size size = Size::absolute(64, 64), bool imported = false) {
    ResourceDesc d;
    d.name = std::move(name);
    d.format = Format::RGBA16Float;
    d.size = std::move(size);
    d.imported = imported;
    return d;
}

inline ResourceDesc buffer(std::string name, bool imported) {
    ResourceDesc d;
    d.name = std::move(name);
    d.kind = ResourceKind::Buffer;
    d.bytes = 1024;
    d.imported = imported;
    return d;
}

inline PassDesc pass(std::string name, std::vector<Access> accesses) {
    return PassDesc{std::move(name), QueueKind::Compute, std::move(accesses), "test"};
}

}  // namespace aamap::graph::mock
