// Names of the enums, format facts, and the two human-readable views of a compiled graph.
#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

#include "engine/graph/render_graph.h"

namespace aamap::graph {

const char* toString(Format format) {
    switch (format) {
        case Format::RGBA8Unorm: return "RGBA8Unorm";
        case Format::RGBA16Float: return "RGBA16Float";
        case Format::RGBA32Float: return "RGBA32Float";
        case Format::R32Float: return "R32Float";
        case Format::R16Float: return "R16Float";
        case Format::D32Float: return "D32Float";
    }
    return "?";
}

bool isDepthFormat(Format format) { return format == Format::D32Float; }

std::uint32_t bytesPerTexel(Format format) {
    switch (format) {
        case Format::RGBA8Unorm: return 4;
        case Format::RGBA16Float: return 8;
        case Format::RGBA32Float: return 16;
        case Format::R32Float: return 4;
        case Format::R16Float: return 2;
        case Format::D32Float: return 4;
    }
    return 0;
}

const char* toString(Usage usage) {
    switch (usage) {
        case Usage::Undefined: return "Undefined";
        case Usage::Sampled: return "Sampled";
        case Usage::StorageRead: return "StorageRead";
        case Usage::StorageWrite: return "StorageWrite";
        case Usage::ColorAttachment: return "ColorAttachment";
        case Usage::DepthAttachment: return "DepthAttachment";
        case Usage::TransferSrc: return "TransferSrc";
        case Usage::TransferDst: return "TransferDst";
    }
    return "?";
}

namespace {

std::string describe(const ResolvedResource& r) {
    const ResourceDesc& d = r.desc;
    if (d.kind == ResourceKind::Buffer) return fmt::format("buffer, {} bytes", d.bytes);
    std::string text = fmt::format("{}x{} {}", r.width, r.height, toString(d.format));
    if (d.layers > 1) text += fmt::format(", {} layers", d.layers);
    if (d.cube) text += ", cube";
    if (d.imported) text += ", imported";
    return text;
}

// A DOT double-quoted string: only '"' and '\' need escaping; newlines become "\n".
std::string quoted(std::string_view s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (c == '\n') {
            out += "\\n";
            continue;
        }
        out += c;
    }
    return out + "\"";
}

}  // namespace

std::string CompiledGraph::explain() const {
    std::string outs;
    for (const std::string& o : outputs) outs += fmt::format("{}'{}'", outs.empty() ? "" : ", ", o);
    std::string text = fmt::format("render graph: {} passes kept, {} culled; outputs {}\n", passes.size(),
                                   culled.size(), outs);
    for (std::size_t i = 0; i < passes.size(); ++i) {
        const CompiledPass& p = passes[i];
        text += fmt::format("  {:>2} kept   '{}': {} [{} barriers]\n", i, p.name, p.keptBecause,
                            p.barriersBefore.size());
    }
    for (const CulledPass& c : culled) text += fmt::format("     culled '{}': {}\n", c.name, c.reason);
    for (const auto& [name, r] : resources) text += fmt::format("     resource '{}': {}\n", name, describe(r));
    return text;
}

std::string CompiledGraph::toDot() const {
    // Every resource any pass touches gets a node, live or not, so culled passes keep their edges.
    std::map<std::string, std::string> ids;
    auto note = [&](const std::vector<Access>& accesses) {
        for (const Access& a : accesses) ids.emplace(a.resource, "");
    };
    for (const CompiledPass& p : passes) note(p.accesses);
    for (const CulledPass& c : culled) note(c.accesses);
    for (const std::string& o : outputs) ids.emplace(o, "");
    int next = 0;
    for (auto& [name, id] : ids) id = fmt::format("r{}", next++);

    std::string dot = "digraph render_graph {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n";
    for (const auto& [name, id] : ids) {
        const auto live = resources.find(name);
        const bool output = std::find(outputs.begin(), outputs.end(), name) != outputs.end();
        std::string label = name;
        if (live != resources.end()) label += fmt::format("\n{}", describe(live->second));
        dot += fmt::format("  {} [shape=ellipse, label={}{}{}];\n", id, quoted(label),
                           output ? ", peripheries=2" : "",
                           live == resources.end() ? ", color=gray60, fontcolor=gray50" : "");
    }
    // One edge per access direction (resource -> pass for reads, pass -> resource for writes; an
    // update both ways), labelled with the usage; a culled pass's edges are dashed like the pass.
    // A resource written more than once labels each edge with the version it carries.
    std::set<std::string> versionedResources;
    for (const CompiledPass& p : passes)
        for (const Access& a : p.accesses)
            if (a.version > 0) versionedResources.insert(a.resource);
    for (const CulledPass& c : culled)
        for (const Access& a : c.accesses)
            if (a.version > 0) versionedResources.insert(a.resource);
    auto edges = [&](const std::string& node, const std::vector<Access>& accesses, bool grey) {
        const char* style = grey ? ", color=gray60, fontcolor=gray50, style=dashed" : "";
        for (const Access& a : accesses) {
            const std::string& r = ids.at(a.resource);
            const bool shown = versionedResources.count(a.resource) > 0;
            auto label = [&](std::uint32_t version) {
                return quoted(shown ? fmt::format("{} v{}", toString(a.usage), version) : std::string(toString(a.usage)));
            };
            // An update reads the version before the one it makes.
            const std::uint32_t readVersion = a.mode == AccessMode::ReadWrite ? a.version - 1 : a.version;
            if (a.mode != AccessMode::Write)
                dot += fmt::format("  {} -> {} [label={}{}];\n", r, node, label(readVersion), style);
            if (a.mode != AccessMode::Read) dot += fmt::format("  {} -> {} [label={}{}];\n", node, r, label(a.version), style);
        }
    };
    // Tooltips carry why a pass was kept or culled (the --explain text) into SVG renderings.
    for (std::size_t i = 0; i < passes.size(); ++i) {
        const std::string node = fmt::format("p{}", passes[i].id);
        dot += fmt::format("  {} [shape=box, label={}, tooltip={}];\n", node,
                           quoted(fmt::format("{}: {}", i, passes[i].name)), quoted(passes[i].keptBecause));
        edges(node, passes[i].accesses, false);
    }
    for (const CulledPass& c : culled) {
        const std::string node = fmt::format("p{}", c.id);
        dot += fmt::format("  {} [shape=box, style=\"filled,dashed\", fillcolor=gray90, fontcolor=gray50, label={}, "
                           "tooltip={}];\n",
                           node, quoted(c.name + " (culled)"), quoted(c.reason));
        edges(node, c.accesses, true);
    }
    return dot + "}\n";
}

}  // namespace aamap::graph
