// The render-graph compiler on mock passes (no GPU): culling, ordering, errors, sizes, barriers.
#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/graph/render_graph.h"
#include "tests/graph/mock_graph.h"

namespace aamap::graph {
namespace {

using mock::buffer;
using mock::image;
using mock::pass;

CompiledGraph compileFor(const RenderGraph& g, std::vector<std::string> outputs) {
    return g.compile(outputs);
}

std::vector<std::string> order(const CompiledGraph& c) {
    std::vector<std::string> names;
    for (const CompiledPass& p : c.passes) names.push_back(p.name);
    return names;
}

const CompiledPass& find(const CompiledGraph& c, const std::string& name) {
    auto it = std::find_if(c.passes.begin(), c.passes.end(), [&](const CompiledPass& p) { return p.name == name; });
    if (it == c.passes.end()) throw std::runtime_error("no kept pass " + name);
    return *it;
}

// Runs `body`, expecting a GraphError whose text contains every one of `needles`.
template <class F>
void expectGraphError(F&& body, std::vector<std::string> needles) {
    try {
        body();
        FAIL() << "expected a GraphError";
    } catch (const GraphError& e) {
        const std::string what = e.what();
        for (const std::string& n : needles) EXPECT_NE(what.find(n), std::string::npos) << "'" << n << "' not in: " << what;
    }
}

bool sameBarrier(const Barrier& b, const std::string& r, Usage from, Usage to) {
    return b.resource == r && b.from == from && b.to == to;
}

// The aamap chain, with a debug view nobody asked for.
RenderGraph aamapChain() {
    RenderGraph g;
    for (const char* r : {"color", "grey", "edges", "blurred", "debugView"}) g.addResource(image(r));
    g.addResource(image("aamap", Size::absolute(32, 32)));
    g.addPass(pass("gbuffer", {writes("color", Usage::ColorAttachment)}));
    g.addPass(pass("luma", {reads("color", Usage::Sampled), writes("grey", Usage::StorageWrite)}));
    g.addPass(pass("laplacian", {reads("grey", Usage::Sampled), writes("edges", Usage::StorageWrite)}));
    g.addPass(pass("debug", {reads("color", Usage::Sampled), writes("debugView", Usage::StorageWrite)}));
    g.addPass(pass("blur", {reads("edges", Usage::Sampled), writes("blurred", Usage::StorageWrite)}));
    g.addPass(pass("reduce", {reads("blurred", Usage::Sampled), writes("aamap", Usage::StorageWrite)}));
    return g;
}

TEST(Graph, CullsPassesThatDoNotReachAnOutput) {
    const CompiledGraph c = compileFor(aamapChain(), {"aamap"});
    EXPECT_EQ(order(c), (std::vector<std::string>{"gbuffer", "luma", "laplacian", "blur", "reduce"}));
    ASSERT_EQ(c.culled.size(), 1u);
    EXPECT_EQ(c.culled[0].name, "debug");
    EXPECT_NE(c.culled[0].reason.find("debugView"), std::string::npos) << c.culled[0].reason;
    EXPECT_EQ(c.resources.count("debugView"), 0u) << "resources of culled passes are not live";
    EXPECT_EQ(c.resources.count("edges"), 1u);
}

TEST(Graph, RequestingTheDebugOutputKeepsItsPass) {
    const CompiledGraph c = compileFor(aamapChain(), {"aamap", "debugView"});
    EXPECT_TRUE(c.culled.empty());
    EXPECT_EQ(c.passes.size(), 6u);
}

TEST(Graph, KeptBecauseExplainsTheChainToTheOutput) {
    const CompiledGraph c = compileFor(aamapChain(), {"aamap"});
    EXPECT_EQ(find(c, "laplacian").keptBecause,
              "writes 'edges' -> read by 'blur' -> writes 'blurred' -> read by 'reduce' -> writes output 'aamap'");
    EXPECT_EQ(find(c, "reduce").keptBecause, "writes output 'aamap'");
}

TEST(Graph, ChainDeclaredInReverseRunsInDependencyOrder) {
    RenderGraph g;
    for (const char* r : {"a", "b", "out"}) g.addResource(image(r));
    g.addPass(pass("third", {reads("b", Usage::Sampled), writes("out", Usage::StorageWrite)}));
    g.addPass(pass("second", {reads("a", Usage::Sampled), writes("b", Usage::StorageWrite)}));
    g.addPass(pass("first", {writes("a", Usage::StorageWrite)}));
    EXPECT_EQ(order(compileFor(g, {"out"})), (std::vector<std::string>{"first", "second", "third"}));
}

TEST(Graph, IndependentPassesKeepDeclarationOrder) {
    RenderGraph g;
    for (const char* r : {"x", "y", "z", "out"}) g.addResource(image(r));
    g.addPass(pass("consumer", {reads("z", Usage::Sampled), reads("y", Usage::Sampled), reads("x", Usage::Sampled),
                                writes("out", Usage::StorageWrite)}));
    g.addPass(pass("makeZ", {writes("z", Usage::StorageWrite)}));
    g.addPass(pass("makeX", {writes("x", Usage::StorageWrite)}));
    g.addPass(pass("makeY", {writes("y", Usage::StorageWrite)}));
    EXPECT_EQ(order(compileFor(g, {"out"})), (std::vector<std::string>{"makeZ", "makeX", "makeY", "consumer"}));
}

TEST(Graph, UpdaterRunsAfterInitialWriterAndBeforeReaders) {
    RenderGraph g;
    for (const char* r : {"color", "out"}) g.addResource(image(r));
    g.addPass(pass("resolve", {reads("color", Usage::Sampled), writes("out", Usage::StorageWrite)}));
    g.addPass(pass("mirror", {updates("color", Usage::ColorAttachment)}));
    g.addPass(pass("clear", {writes("color", Usage::ColorAttachment)}));
    const CompiledGraph c = compileFor(g, {"out"});
    EXPECT_EQ(order(c), (std::vector<std::string>{"clear", "mirror", "resolve"}));
    // Write-after-write with the same usage still needs a barrier.
    const CompiledPass& mirror = find(c, "mirror");
    ASSERT_EQ(mirror.barriersBefore.size(), 1u);
    EXPECT_TRUE(sameBarrier(mirror.barriersBefore[0], "color", Usage::ColorAttachment, Usage::ColorAttachment));
}

TEST(Graph, CycleErrorNamesPassesAndResources) {
    RenderGraph g;
    for (const char* r : {"ping", "pong", "out", "seed"}) g.addResource(image(r));
    g.addPass(pass("start", {writes("seed", Usage::StorageWrite)}));
    g.addPass(pass("alpha", {reads("seed", Usage::Sampled), reads("pong", Usage::Sampled), writes("ping", Usage::StorageWrite)}));
    g.addPass(pass("beta", {reads("ping", Usage::Sampled), writes("pong", Usage::StorageWrite)}));
    g.addPass(pass("finish", {reads("ping", Usage::Sampled), writes("out", Usage::StorageWrite)}));
    expectGraphError([&] { compileFor(g, {"out"}); }, {"cycle", "'alpha'", "'beta'", "'ping'", "'pong'"});
}

TEST(Graph, TwoUpdatersComposeInDeclarationOrder) {
    RenderGraph g;
    g.addResource(image("accum"));
    g.addPass(pass("addB", {updates("accum", Usage::StorageWrite)}));  // declared first, so version 1
    g.addPass(pass("init", {writes("accum", Usage::StorageWrite)}));
    g.addPass(pass("addA", {updates("accum", Usage::StorageWrite)}));
    const CompiledGraph c = compileFor(g, {"accum"});
    EXPECT_EQ(order(c), (std::vector<std::string>{"init", "addB", "addA"}));
    EXPECT_TRUE(c.culled.empty());
    EXPECT_EQ(find(c, "init").accesses[0].version, 0u);
    EXPECT_EQ(find(c, "addB").accesses[0].version, 1u);
    EXPECT_EQ(find(c, "addA").accesses[0].version, 2u);
    // Each update waits for the previous write (same usage, still a barrier), and the readback
    // for the last one.
    for (const char* updater : {"addB", "addA"}) {
        const auto& b = find(c, updater).barriersBefore;
        ASSERT_EQ(b.size(), 1u) << updater;
        EXPECT_TRUE(sameBarrier(b[0], "accum", Usage::StorageWrite, Usage::StorageWrite)) << updater;
    }
    ASSERT_EQ(c.finalBarriers.size(), 1u);
    EXPECT_TRUE(sameBarrier(c.finalBarriers[0], "accum", Usage::StorageWrite, Usage::TransferSrc));
}

// The Snapshot's shape: a G-buffer, two composites that each update the colour in place (planar
// mirrors, then curved ones), a luminance pass after both, and a mask drawn from the depth.
RenderGraph mirroredSnapshot() {
    RenderGraph g;
    for (const char* r : {"snapshot", "mask", "probeColour", "grey"}) g.addResource(image(r));
    g.addResource(image("depth"));
    g.addPass(pass("gbuffer", {writes("snapshot", Usage::ColorAttachment)}));
    g.addPass(pass("mirror.mask", {writes("mask", Usage::StorageWrite)}));
    g.addPass(pass("mirror.composite", {updates("snapshot", Usage::StorageWrite), reads("mask", Usage::StorageRead)}));
    g.addPass(pass("probes.render", {writes("probeColour", Usage::ColorAttachment)}));
    g.addPass(pass("probes.composite", {updates("snapshot", Usage::ColorAttachment), reads("probeColour", Usage::Sampled)}));
    g.addPass(pass("luminance", {reads("snapshot", Usage::StorageRead), writes("grey", Usage::StorageWrite)}));
    return g;
}

TEST(Graph, PlanarAndProbeCompositesBothKeptAndOrdered) {
    const CompiledGraph c = compileFor(mirroredSnapshot(), {"grey", "snapshot"});
    EXPECT_TRUE(c.culled.empty());
    const std::vector<std::string> seq = order(c);
    auto at = [&](const char* n) { return std::find(seq.begin(), seq.end(), n) - seq.begin(); };
    EXPECT_LT(at("gbuffer"), at("mirror.composite"));
    EXPECT_LT(at("mirror.composite"), at("probes.composite"));
    EXPECT_LT(at("probes.composite"), at("luminance"));
    EXPECT_EQ(find(c, "luminance").accesses[0].version, 2u) << "reads the snapshot after both composites";
    const auto& b = find(c, "probes.composite").barriersBefore;
    EXPECT_TRUE(std::any_of(b.begin(), b.end(), [](const Barrier& x) {
        return sameBarrier(x, "snapshot", Usage::StorageWrite, Usage::ColorAttachment);
    }));
    EXPECT_NE(find(c, "mirror.composite").keptBecause.find("'probes.composite'"), std::string::npos)
        << find(c, "mirror.composite").keptBecause;
}

TEST(Graph, ReaderBetweenUpdatersSeesItsVersionAndRunsBeforeTheNextUpdate) {
    RenderGraph g;
    for (const char* r : {"color", "histogram"}) g.addResource(image(r));
    g.addPass(pass("draw", {writes("color", Usage::ColorAttachment)}));
    g.addPass(pass("measure", {reads("color", Usage::Sampled), writes("histogram", Usage::StorageWrite)}));
    g.addPass(pass("overlay", {updates("color", Usage::ColorAttachment)}));
    const CompiledGraph c = compileFor(g, {"color", "histogram"});
    EXPECT_EQ(order(c), (std::vector<std::string>{"draw", "measure", "overlay"}));
    EXPECT_EQ(find(c, "measure").accesses[0].version, 0u);
    // Write after read of the same image: the overlay waits for the sampling to finish.
    const auto& b = find(c, "overlay").barriersBefore;
    ASSERT_EQ(b.size(), 1u);
    EXPECT_TRUE(sameBarrier(b[0], "color", Usage::Sampled, Usage::ColorAttachment));

    // Only the final version asked for: the reader of version 0 is culled, the chain is not.
    const CompiledGraph only = compileFor(g, {"color"});
    EXPECT_EQ(order(only), (std::vector<std::string>{"draw", "overlay"}));
    ASSERT_EQ(only.culled.size(), 1u);
    EXPECT_EQ(only.culled[0].name, "measure");
}

TEST(Graph, UpdaterOfAnImportRunsAfterTheImportsEarlierReaders) {
    RenderGraph g;
    g.addResource(image("lut", Size::absolute(16, 16), true));
    g.addResource(image("out"));
    g.addPass(pass("use", {reads("lut", Usage::Sampled), writes("out", Usage::StorageWrite)}));
    g.addPass(pass("refine", {updates("lut", Usage::StorageWrite)}));
    const CompiledGraph c = compileFor(g, {"out", "lut"});
    EXPECT_EQ(order(c), (std::vector<std::string>{"use", "refine"}));
    EXPECT_EQ(find(c, "use").accesses[0].version, 0u) << "the host's upload";
    EXPECT_TRUE(sameBarrier(find(c, "use").barriersBefore[0], "lut", Usage::TransferDst, Usage::Sampled));
}

TEST(Graph, WriteAfterReadCycleIsNamed) {
    // 'probe' reads version 0 of 'colour' and 'cubes', which the update of 'colour' makes: the
    // update must run both after and before 'probe'.
    RenderGraph h;
    for (const char* r : {"colour", "cubes", "stats"}) h.addResource(image(r));
    h.addPass(pass("draw", {writes("colour", Usage::ColorAttachment)}));
    h.addPass(pass("probe", {reads("colour", Usage::Sampled), reads("cubes", Usage::Sampled),
                             writes("stats", Usage::StorageWrite)}));
    h.addPass(pass("composite", {updates("colour", Usage::StorageWrite), writes("cubes", Usage::StorageWrite)}));
    expectGraphError([&] { compileFor(h, {"stats", "colour"}); },
                     {"cycle", "'probe'", "'composite'", "reads 'colour' before 'composite' updates it", "'cubes'"});
}

TEST(Graph, MissingProducerNamesPassAndResource) {
    RenderGraph g;
    for (const char* r : {"shadowMap", "out"}) g.addResource(image(r));
    g.addPass(pass("lighting", {reads("shadowMap", Usage::Sampled), writes("out", Usage::ColorAttachment)}));
    expectGraphError([&] { compileFor(g, {"out"}); }, {"missing producer", "'lighting'", "'shadowMap'"});
}

TEST(Graph, UpdaterWithoutInitialWriterIsMissingItsProducer) {
    RenderGraph g;
    g.addResource(image("accum"));
    g.addPass(pass("add", {updates("accum", Usage::StorageWrite)}));
    expectGraphError([&] { compileFor(g, {"accum"}); }, {"missing producer", "'add'", "'accum'"});
}

TEST(Graph, ImportedResourceNeedsNoProducer) {
    RenderGraph g;
    g.addResource(buffer("vertices", true));
    g.addResource(image("out"));
    g.addPass(pass("draw", {reads("vertices", Usage::StorageRead), writes("out", Usage::ColorAttachment)}));
    const CompiledGraph c = compileFor(g, {"out"});
    ASSERT_EQ(c.passes.size(), 1u);
    const auto& b = c.passes[0].barriersBefore;
    ASSERT_EQ(b.size(), 2u);
    EXPECT_TRUE(sameBarrier(b[0], "vertices", Usage::TransferDst, Usage::StorageRead));
    EXPECT_TRUE(sameBarrier(b[1], "out", Usage::Undefined, Usage::ColorAttachment));
}

TEST(Graph, TwoInitialWritersNameBothPassesAndTheResource) {
    RenderGraph g;
    g.addResource(image("color"));
    g.addPass(pass("opaque", {writes("color", Usage::ColorAttachment)}));
    g.addPass(pass("sky", {writes("color", Usage::ColorAttachment)}));
    expectGraphError([&] { compileFor(g, {"color"}); }, {"'opaque'", "'sky'", "'color'", "two initial writers"});
}

TEST(Graph, UnknownResourceAndOutputAreErrors) {
    RenderGraph g;
    g.addResource(image("out"));
    g.addPass(pass("typo", {reads("colour", Usage::Sampled), writes("out", Usage::StorageWrite)}));
    expectGraphError([&] { compileFor(g, {"out"}); }, {"'typo'", "'colour'", "unknown"});

    RenderGraph h;
    h.addResource(image("out"));
    h.addPass(pass("make", {writes("out", Usage::StorageWrite)}));
    expectGraphError([&] { compileFor(h, {"aamap"}); }, {"unknown output", "'aamap'"});
}

TEST(Graph, DuplicateNamesAreErrors) {
    RenderGraph g;
    g.addResource(image("a"));
    EXPECT_THROW(g.addResource(image("a")), GraphError);
    g.addPass(pass("p", {writes("a", Usage::StorageWrite)}));
    EXPECT_THROW(g.addPass(pass("p", {})), GraphError);
}

TEST(Graph, UsageThatCannotWriteIsRejected) {
    RenderGraph g;
    g.addResource(image("a"));
    g.addPass(pass("bad", {writes("a", Usage::Sampled)}));
    expectGraphError([&] { compileFor(g, {"a"}); }, {"'bad'", "'a'", "Sampled"});
}

TEST(Graph, RelativeSizesResolveRecursively) {
    RenderGraph g;
    g.addResource(image("frame", Size::absolute(512, 384)));
    g.addResource(image("half", Size::relative("snapshot", 0.5f, 1.0f / 3.0f)));  // declared before its base
    g.addResource(image("snapshot", Size::relative("frame", 1.5f, 1.5f)));
    g.addResource(image("tiny", Size::relative("frame", 0.0001f, 0.0001f)));
    g.addPass(pass("render", {writes("snapshot", Usage::ColorAttachment)}));
    g.addPass(pass("down", {reads("snapshot", Usage::Sampled), writes("half", Usage::StorageWrite),
                            writes("tiny", Usage::StorageWrite)}));
    g.addPass(pass("final", {reads("half", Usage::Sampled), reads("tiny", Usage::Sampled),
                             writes("frame", Usage::StorageWrite)}));
    const CompiledGraph c = compileFor(g, {"frame"});
    EXPECT_EQ(c.resources.at("snapshot").width, 768u);
    EXPECT_EQ(c.resources.at("snapshot").height, 576u);
    EXPECT_EQ(c.resources.at("half").width, 384u);
    EXPECT_EQ(c.resources.at("half").height, 192u);
    EXPECT_EQ(c.resources.at("tiny").width, 1u) << "at least one texel";
    EXPECT_EQ(c.resources.at("tiny").height, 1u);
    EXPECT_EQ(c.resources.at("frame").width, 512u);
}

TEST(Graph, BadRelativeSizesAreErrors) {
    auto graphWith = [](std::vector<ResourceDesc> extra) {
        RenderGraph g;
        g.addResource(image("out"));
        for (auto& r : extra) g.addResource(std::move(r));
        g.addPass(pass("make", {writes("out", Usage::StorageWrite)}));
        return g;
    };
    const RenderGraph self = graphWith({image("loop", Size::relative("loop"))});
    expectGraphError([&] { compileFor(self, {"out"}); }, {"'loop'", "itself"});
    const RenderGraph indirect = graphWith({image("a", Size::relative("b")), image("b", Size::relative("c")),
                                            image("c", Size::relative("a"))});
    expectGraphError([&] { compileFor(indirect, {"out"}); }, {"cycle", "'a'", "'b'", "'c'"});
    const RenderGraph unknown = graphWith({image("a", Size::relative("nowhere"))});
    expectGraphError([&] { compileFor(unknown, {"out"}); }, {"'a'", "'nowhere'"});
    const RenderGraph negative = graphWith({image("a", Size::relative("out", -1.0f, 1.0f))});
    expectGraphError([&] { compileFor(negative, {"out"}); }, {"'a'", "scale"});
}

TEST(Graph, BarriersForWriteThenSampledThenStorageRead) {
    RenderGraph g;
    for (const char* r : {"edges", "out"}) g.addResource(image(r));
    g.addPass(pass("write", {writes("edges", Usage::StorageWrite)}));
    g.addPass(pass("sample", {reads("edges", Usage::Sampled)}));
    g.addPass(pass("load", {reads("edges", Usage::StorageRead), writes("out", Usage::StorageWrite)}));
    // 'sample' writes nothing, so it is culled; request 'edges' too so that it is not.
    const CompiledGraph culled = compileFor(g, {"out"});
    ASSERT_EQ(culled.culled.size(), 1u);
    EXPECT_EQ(culled.culled[0].name, "sample");

    RenderGraph h;
    for (const char* r : {"edges", "sum", "out"}) h.addResource(image(r));
    h.addPass(pass("write", {writes("edges", Usage::StorageWrite)}));
    h.addPass(pass("sample", {reads("edges", Usage::Sampled), writes("sum", Usage::StorageWrite)}));
    h.addPass(pass("load", {reads("sum", Usage::Sampled), reads("edges", Usage::StorageRead),
                            writes("out", Usage::StorageWrite)}));
    const CompiledGraph c = compileFor(h, {"out"});
    ASSERT_EQ(order(c), (std::vector<std::string>{"write", "sample", "load"}));
    const auto& w = c.passes[0].barriersBefore;
    ASSERT_EQ(w.size(), 1u);
    EXPECT_TRUE(sameBarrier(w[0], "edges", Usage::Undefined, Usage::StorageWrite));
    const auto& s = c.passes[1].barriersBefore;
    ASSERT_EQ(s.size(), 2u);
    EXPECT_TRUE(sameBarrier(s[0], "edges", Usage::StorageWrite, Usage::Sampled));
    EXPECT_TRUE(sameBarrier(s[1], "sum", Usage::Undefined, Usage::StorageWrite));
    const auto& l = c.passes[2].barriersBefore;
    ASSERT_EQ(l.size(), 3u);
    EXPECT_TRUE(sameBarrier(l[0], "sum", Usage::StorageWrite, Usage::Sampled));
    EXPECT_TRUE(sameBarrier(l[1], "edges", Usage::Sampled, Usage::StorageRead));
    EXPECT_TRUE(sameBarrier(l[2], "out", Usage::Undefined, Usage::StorageWrite));
    ASSERT_EQ(c.finalBarriers.size(), 1u);
    EXPECT_TRUE(sameBarrier(c.finalBarriers[0], "out", Usage::StorageWrite, Usage::TransferSrc));
}

TEST(Graph, ReadAfterReadOfTheSameUsageNeedsNoBarrier) {
    RenderGraph g;
    for (const char* r : {"color", "a", "b", "out"}) g.addResource(image(r));
    g.addPass(pass("draw", {writes("color", Usage::ColorAttachment)}));
    g.addPass(pass("readA", {reads("color", Usage::Sampled), writes("a", Usage::StorageWrite)}));
    g.addPass(pass("readB", {reads("color", Usage::Sampled), writes("b", Usage::StorageWrite)}));
    g.addPass(pass("merge", {reads("a", Usage::Sampled), reads("b", Usage::Sampled), writes("out", Usage::StorageWrite)}));
    const CompiledGraph c = compileFor(g, {"out"});
    const auto& a = find(c, "readA").barriersBefore;
    EXPECT_TRUE(std::any_of(a.begin(), a.end(), [](const Barrier& b) {
        return sameBarrier(b, "color", Usage::ColorAttachment, Usage::Sampled);
    }));
    for (const Barrier& b : find(c, "readB").barriersBefore) EXPECT_NE(b.resource, "color");
}

TEST(Graph, ImportedResourceStartsFromTransferDst) {
    RenderGraph g;
    g.addResource(image("snapshot", Size::absolute(96, 96), true));
    g.addResource(image("aamap", Size::relative("snapshot", 2.0f / 3.0f, 2.0f / 3.0f)));
    g.addPass(pass("filter", {reads("snapshot", Usage::Sampled), writes("aamap", Usage::StorageWrite)}));
    const CompiledGraph c = compileFor(g, {"aamap", "snapshot"});
    const auto& b = c.passes[0].barriersBefore;
    ASSERT_EQ(b.size(), 2u);
    EXPECT_TRUE(sameBarrier(b[0], "snapshot", Usage::TransferDst, Usage::Sampled));
    EXPECT_TRUE(sameBarrier(b[1], "aamap", Usage::Undefined, Usage::StorageWrite));
    ASSERT_EQ(c.finalBarriers.size(), 2u);
    EXPECT_TRUE(sameBarrier(c.finalBarriers[0], "aamap", Usage::StorageWrite, Usage::TransferSrc));
    EXPECT_TRUE(sameBarrier(c.finalBarriers[1], "snapshot", Usage::Sampled, Usage::TransferSrc));
    EXPECT_EQ(c.resources.at("aamap").width, 64u);
}

TEST(Graph, ExplainAndDotShowKeptAndCulledPasses) {
    const CompiledGraph c = compileFor(aamapChain(), {"aamap"});
    const std::string text = c.explain();
    EXPECT_NE(text.find("culled 'debug'"), std::string::npos) << text;
    EXPECT_NE(text.find("'laplacian': writes 'edges' -> read by 'blur'"), std::string::npos) << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 5 + 1 + 5) << text;  // header, kept, culled, live

    const std::string dot = c.toDot();
    EXPECT_EQ(dot.rfind("digraph render_graph {", 0), 0u) << dot;
    EXPECT_EQ(dot.substr(dot.size() - 2), "}\n");
    EXPECT_NE(dot.find("debug (culled)"), std::string::npos) << dot;
    EXPECT_NE(dot.find("\"debugView\""), std::string::npos) << dot;
    EXPECT_EQ(std::count(dot.begin(), dot.end(), '{'), std::count(dot.begin(), dot.end(), '}'));
    EXPECT_EQ(std::count(dot.begin(), dot.end(), '"') % 2, 0);
}

}  // namespace
}  // namespace aamap::graph
