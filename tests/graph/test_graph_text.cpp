// The two human-readable views of a compiled graph (engine/graph/graph_text.cpp): `explain()` for
// `aamap snapshot --explain` and the DOT writer behind `--dot FILE`. Checked structurally: every
// pass and resource appears once, every access is one edge, culled passes and only they are dashed.
#include <algorithm>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/graph/render_graph.h"
#include "tests/graph/mock_graph.h"

namespace aamap::graph {
namespace {

using mock::image;
using mock::pass;

// A shadowed raster and the aamap chain, plus two passes nobody asked for: one reading the colour
// (a debug view) and one updating a resource in place after producing it (a block-sum pair).
RenderGraph snapshotLike() {
    RenderGraph g;
    ResourceDesc shadow = image("shadow");
    shadow.format = Format::D32Float;
    g.addResource(shadow);
    for (const char* r : {"colour", "grey", "aamap", "debugView", "sums"}) g.addResource(image(r));
    g.addPass(pass("shadow_cubes", {writes("shadow", Usage::DepthAttachment)}));
    g.addPass(pass("gbuffer", {reads("shadow", Usage::Sampled), writes("colour", Usage::ColorAttachment)}));
    g.addPass(pass("luma", {reads("colour", Usage::Sampled), writes("grey", Usage::StorageWrite)}));
    g.addPass(pass("reduce", {reads("grey", Usage::Sampled), writes("aamap", Usage::StorageWrite)}));
    g.addPass(pass("debug", {reads("colour", Usage::Sampled), writes("debugView", Usage::StorageWrite)}));
    g.addPass(pass("sum_rows", {reads("aamap", Usage::Sampled), writes("sums", Usage::StorageWrite)}));
    g.addPass(pass("sum_columns", {updates("sums", Usage::StorageWrite)}));
    return g;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

struct DotGraph {
    std::map<std::string, std::string> nodes;  // id -> attribute text
    std::vector<std::pair<std::pair<std::string, std::string>, std::string>> edges;  // (from, to), attributes
};

// A parser for the subset of DOT the writer emits: "  id [attrs];" and "  a -> b [attrs];".
DotGraph parse(const std::string& dot) {
    DotGraph g;
    const std::regex node(R"(^  (\w+) \[(.*)\];$)"), edge(R"(^  (\w+) -> (\w+) \[(.*)\];$)");
    for (const std::string& line : lines(dot)) {
        std::smatch m;
        if (std::regex_match(line, m, edge)) {
            g.edges.push_back({{m[1], m[2]}, m[3]});
        } else if (std::regex_match(line, m, node) && m[1] != "node") {
            EXPECT_FALSE(g.nodes.contains(m[1])) << "node declared twice: " << line;
            g.nodes[m[1]] = m[2];
        }
    }
    return g;
}

std::string nodeWithLabel(const DotGraph& g, const std::string& labelPart) {
    std::string found;
    for (const auto& [id, attrs] : g.nodes)
        if (attrs.find(labelPart) != std::string::npos) {
            EXPECT_TRUE(found.empty()) << "two nodes match " << labelPart;
            found = id;
        }
    return found;
}

TEST(GraphText, ExplainNamesEveryKeptAndCulledPassWithItsReason) {
    const RenderGraph g = snapshotLike();
    const std::vector<std::string> outputs{"aamap"};
    const CompiledGraph c = g.compile(outputs);
    ASSERT_EQ(c.passes.size(), 4u);
    ASSERT_EQ(c.culled.size(), 3u);
    const std::string text = c.explain();
    for (const CompiledPass& p : c.passes) {
        EXPECT_FALSE(p.keptBecause.empty()) << p.name;
        EXPECT_NE(text.find("kept   '" + p.name + "': " + p.keptBecause), std::string::npos) << text;
    }
    for (const CulledPass& p : c.culled) {
        EXPECT_FALSE(p.reason.empty()) << p.name;
        EXPECT_NE(text.find("culled '" + p.name + "': " + p.reason), std::string::npos) << text;
    }
    // The shadow pass is kept because the raster reads it, on the way to the output.
    const auto& shadow = *std::find_if(c.passes.begin(), c.passes.end(), [](auto& p) { return p.name == "shadow_cubes"; });
    EXPECT_NE(shadow.keptBecause.find("gbuffer"), std::string::npos) << shadow.keptBecause;
    EXPECT_NE(shadow.keptBecause.find("aamap"), std::string::npos) << shadow.keptBecause;
}

TEST(GraphText, DotHasEveryPassResourceAndAccessAndDashesOnlyCulledPasses) {
    const RenderGraph g = snapshotLike();
    const std::vector<std::string> outputs{"aamap"};
    const CompiledGraph c = g.compile(outputs);
    const std::string dot = c.toDot();
    ASSERT_EQ(dot.rfind("digraph render_graph {\n", 0), 0u) << dot;
    ASSERT_EQ(dot.substr(dot.size() - 2), "}\n");
    const DotGraph d = parse(dot);

    // One node per pass (kept: "i: name"; culled: "name (culled)"), one per resource.
    std::map<std::string, std::string> passNode, resourceNode;
    for (std::size_t i = 0; i < c.passes.size(); ++i)
        passNode[c.passes[i].name] = nodeWithLabel(d, "label=\"" + std::to_string(i) + ": " + c.passes[i].name + "\"");
    for (const CulledPass& p : c.culled) passNode[p.name] = nodeWithLabel(d, "label=\"" + p.name + " (culled)\"");
    for (const ResourceDesc& r : g.resources()) resourceNode[r.name] = nodeWithLabel(d, "label=\"" + r.name);
    EXPECT_EQ(d.nodes.size(), g.passes().size() + g.resources().size()) << dot;
    for (const auto& [name, id] : passNode) {
        ASSERT_FALSE(id.empty()) << name;
        EXPECT_NE(d.nodes.at(id).find("shape=box"), std::string::npos);
    }
    for (const auto& [name, id] : resourceNode) {
        ASSERT_FALSE(id.empty()) << name;
        EXPECT_NE(d.nodes.at(id).find("shape=ellipse"), std::string::npos);
    }
    EXPECT_NE(d.nodes.at(resourceNode["aamap"]).find("peripheries=2"), std::string::npos) << "output marked";

    // Every access is an edge in its direction (an update both ways), labelled with its usage;
    // edges of culled passes are dashed, the others are not.
    std::size_t expectedEdges = 0;
    for (const PassDesc& p : g.passes()) {
        const bool culled = std::any_of(c.culled.begin(), c.culled.end(), [&](auto& x) { return x.name == p.name; });
        const std::string& pn = passNode[p.name];
        EXPECT_EQ(d.nodes.at(pn).find("dashed") != std::string::npos, culled) << p.name;
        for (const Access& a : p.accesses) {
            const std::string& rn = resourceNode[a.resource];
            for (bool toPass : {true, false}) {
                if ((toPass && a.mode == AccessMode::Write) || (!toPass && a.mode == AccessMode::Read)) continue;
                ++expectedEdges;
                const auto key = toPass ? std::make_pair(rn, pn) : std::make_pair(pn, rn);
                const auto it = std::find_if(d.edges.begin(), d.edges.end(), [&](auto& e) { return e.first == key; });
                ASSERT_NE(it, d.edges.end()) << p.name << " " << a.resource;
                // The usage, then the version where the resource has more than one ('sums').
                EXPECT_NE(it->second.find(std::string("label=\"") + toString(a.usage)), std::string::npos);
                EXPECT_EQ(it->second.find("dashed") != std::string::npos, culled) << p.name << " " << a.resource;
            }
        }
    }
    EXPECT_EQ(d.edges.size(), expectedEdges) << dot;
}

TEST(GraphText, DotLabelsTheVersionsOfAResourceWrittenMoreThanOnce) {
    RenderGraph g;
    for (const char* r : {"colour", "grey"}) g.addResource(image(r));
    g.addPass(pass("draw", {writes("colour", Usage::ColorAttachment)}));
    g.addPass(pass("composite", {updates("colour", Usage::StorageWrite)}));
    g.addPass(pass("luma", {reads("colour", Usage::StorageRead), writes("grey", Usage::StorageWrite)}));
    const std::vector<std::string> outputs{"grey"};
    const std::string dot = g.compile(outputs).toDot();
    for (const char* label : {"\"ColorAttachment v0\"", "\"StorageWrite v0\"", "\"StorageWrite v1\"", "\"StorageRead v1\""})
        EXPECT_NE(dot.find(label), std::string::npos) << label << " in\n" << dot;
    EXPECT_NE(dot.find("label=\"StorageWrite\""), std::string::npos) << "'grey' has one version: no label";
}

TEST(GraphText, DotEscapesQuotesAndBackslashesInNames) {
    RenderGraph g;
    g.addResource(image("a \"quoted\" \\ name"));
    g.addPass(pass("draw \"it\"", {writes("a \"quoted\" \\ name", Usage::ColorAttachment)}));
    const std::vector<std::string> outputs{"a \"quoted\" \\ name"};
    const std::string dot = g.compile(outputs).toDot();
    EXPECT_NE(dot.find(R"(a \"quoted\" \\ name)"), std::string::npos) << dot;
    EXPECT_NE(dot.find(R"(0: draw \"it\")"), std::string::npos) << dot;
    // Outside escapes, quotes pair up on every line.
    for (const std::string& line : lines(dot)) {
        const std::string unescaped = std::regex_replace(line, std::regex(R"(\\.)"), "");
        EXPECT_EQ(std::count(unescaped.begin(), unescaped.end(), '"') % 2, 0) << line;
    }
}

}  // namespace
}  // namespace aamap::graph
