// The render-graph compiler: validation, culling, ordering, sizes and barriers.
// Text output (explain, DOT, enum names) lives in graph_text.cpp.
#include "engine/graph/render_graph.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <set>
#include <unordered_map>

#include <fmt/format.h>

namespace aamap::graph {
namespace {

constexpr std::uint32_t kNone = ~0u;

bool writesTo(AccessMode mode) { return mode != AccessMode::Read; }

// Usages that can only read, and usages that can only write; attachments may do both.
bool isReadOnlyUsage(Usage u) { return u == Usage::Sampled || u == Usage::StorageRead || u == Usage::TransferSrc; }
bool isWriteOnlyUsage(Usage u) { return u == Usage::StorageWrite || u == Usage::TransferDst; }

const char* toString(AccessMode mode) {
    switch (mode) {
        case AccessMode::Read: return "reads";
        case AccessMode::Write: return "writes";
        case AccessMode::ReadWrite: return "updates";
    }
    return "?";
}

// The declarations indexed by resource, checked once per compile.
struct Index {
    const std::vector<ResourceDesc>& resources;
    const std::vector<PassDesc>& passes;
    std::unordered_map<std::string, std::uint32_t> byName;
    // Per resource, the producer of each version: [0] the initial writer (kNone: the import, or
    // nobody), then the updaters in declaration order.
    std::vector<std::vector<PassId>> producers;
    std::vector<std::vector<std::uint32_t>> accessed;  // per pass: resource index of each access
    std::vector<std::vector<std::uint32_t>> versions;  // per pass: version each access reads or makes
    std::vector<std::vector<std::vector<PassId>>> readers;  // per resource and version: its Read passes

    std::uint32_t find(const std::string& name) const {
        auto it = byName.find(name);
        return it == byName.end() ? kNone : it->second;
    }
    const std::string& passName(PassId p) const { return passes[p].name; }
    const std::string& resName(std::uint32_t r) const { return resources[r].name; }
    bool hasWriter(std::uint32_t r) const {
        return producers[r].size() > 1 || producers[r][0] != kNone;
    }
    std::uint32_t finalVersion(std::uint32_t r) const { return static_cast<std::uint32_t>(producers[r].size() - 1); }
    // The version access i of pass p reads; kNone for an initial write, which reads nothing.
    std::uint32_t versionRead(PassId p, std::size_t i) const {
        switch (passes[p].accesses[i].mode) {
            case AccessMode::Write: return kNone;
            case AccessMode::ReadWrite: return versions[p][i] - 1;
            case AccessMode::Read: return versions[p][i];
        }
        return kNone;
    }
};

void checkAccess(const PassDesc& pass, const Access& a, const ResourceDesc& res) {
    auto fail = [&](std::string_view what) {
        throw GraphError(fmt::format("pass '{}' {} '{}' as {}: {}", pass.name, toString(a.mode), a.resource,
                                     toString(a.usage), what));
    };
    if (a.usage == Usage::Undefined) fail("Undefined is not a usage");
    if (isReadOnlyUsage(a.usage) && writesTo(a.mode)) fail("this usage cannot write");
    if (isWriteOnlyUsage(a.usage) && a.mode == AccessMode::Read) fail("this usage cannot read");
    const bool attachment = a.usage == Usage::ColorAttachment || a.usage == Usage::DepthAttachment;
    if (attachment && res.kind == ResourceKind::Buffer) fail("a buffer cannot be an attachment");
    if (res.kind == ResourceKind::Image) {
        if (a.usage == Usage::ColorAttachment && isDepthFormat(res.format)) fail("depth format as colour attachment");
        if (a.usage == Usage::DepthAttachment && !isDepthFormat(res.format)) fail("colour format as depth attachment");
    }
}

Index buildIndex(const std::vector<ResourceDesc>& resources, const std::vector<PassDesc>& passes) {
    Index idx{resources, passes, {}, {}, {}, {}, {}};
    for (std::uint32_t r = 0; r < resources.size(); ++r) idx.byName.emplace(resources[r].name, r);
    idx.producers.assign(resources.size(), std::vector<PassId>{kNone});
    idx.accessed.resize(passes.size());
    idx.versions.resize(passes.size());
    // First the accesses and the version chains (initial writer, then updaters as declared).
    for (PassId p = 0; p < passes.size(); ++p) {
        const PassDesc& pass = passes[p];
        std::set<std::uint32_t> seen;
        for (const Access& a : pass.accesses) {
            const std::uint32_t r = idx.find(a.resource);
            if (r == kNone)
                throw GraphError(fmt::format("pass '{}' {} unknown resource '{}'", pass.name, toString(a.mode), a.resource));
            if (!seen.insert(r).second)
                throw GraphError(fmt::format("pass '{}' accesses resource '{}' twice (use updates() to read and write it)",
                                             pass.name, a.resource));
            checkAccess(pass, a, resources[r]);
            idx.accessed[p].push_back(r);
            idx.versions[p].push_back(0);
            if (a.mode == AccessMode::Write) {
                PassId& initial = idx.producers[r][0];
                if (initial != kNone)
                    throw GraphError(fmt::format(
                        "resource '{}' has two initial writers, passes '{}' and '{}' (a later pass should use updates())",
                        a.resource, passes[initial].name, pass.name));
                initial = p;
            } else if (a.mode == AccessMode::ReadWrite) {
                idx.versions[p].back() = static_cast<std::uint32_t>(idx.producers[r].size());
                idx.producers[r].push_back(p);
            }
        }
    }
    // Then the version each read sees: the newest made by a pass declared before the reader (an
    // import before all), else, for a reader declared ahead of every writer, the final one.
    idx.readers.resize(resources.size());
    for (std::uint32_t r = 0; r < resources.size(); ++r) idx.readers[r].resize(idx.producers[r].size());
    for (PassId p = 0; p < passes.size(); ++p) {
        for (std::size_t i = 0; i < passes[p].accesses.size(); ++i) {
            if (passes[p].accesses[i].mode != AccessMode::Read) continue;
            const std::uint32_t r = idx.accessed[p][i];
            const std::vector<PassId>& made = idx.producers[r];
            std::uint32_t v = idx.finalVersion(r);
            for (std::uint32_t k = idx.finalVersion(r) + 1; k-- > 0;) {
                const bool before = made[k] == kNone ? k == 0 && resources[r].imported : made[k] < p;
                if (before) {
                    v = k;
                    break;
                }
            }
            idx.versions[p][i] = v;
            idx.readers[r][v].push_back(p);
        }
    }
    return idx;
}

// The pass that made version v of r, or kNone when it is the import (or nobody's).
PassId producerOf(const Index& idx, std::uint32_t r, std::uint32_t v) { return idx.producers[r][v]; }

// Why a pass is kept: it writes `resource`, which `consumer` reads (kNone: a requested output).
struct KeepReason {
    std::uint32_t resource = kNone;
    PassId consumer = kNone;
};

// Walks back from the outputs in breadth-first, declaration order: the recorded reason is the
// shortest chain to an output, and the result does not depend on hash order. A pass keeps only
// the producers of the versions it reads.
std::vector<std::optional<KeepReason>> cull(const Index& idx, const std::vector<std::uint32_t>& outputs) {
    std::vector<std::optional<KeepReason>> kept(idx.passes.size());
    std::deque<PassId> queue;
    for (std::uint32_t r : outputs) {
        const PassId w = producerOf(idx, r, idx.finalVersion(r));
        if (w == kNone || kept[w]) continue;
        kept[w] = KeepReason{r, kNone};
        queue.push_back(w);
    }
    while (!queue.empty()) {
        const PassId p = queue.front();
        queue.pop_front();
        const PassDesc& pass = idx.passes[p];
        for (std::size_t i = 0; i < pass.accesses.size(); ++i) {
            const std::uint32_t v = idx.versionRead(p, i);
            if (v == kNone) continue;
            const std::uint32_t r = idx.accessed[p][i];
            const PassId w = producerOf(idx, r, v);
            if (w == kNone && !idx.resources[r].imported)
                throw GraphError(fmt::format("pass '{}' {} '{}', but no other pass writes {} and it is not "
                                             "imported (missing producer)",
                                             pass.name, toString(pass.accesses[i].mode), idx.resName(r),
                                             v == 0 ? "it" : "the version it reads"));
            if (w == kNone || kept[w]) continue;
            kept[w] = KeepReason{r, p};
            queue.push_back(w);
        }
    }
    return kept;
}

// Why one pass must run before another: it makes the version the other reads, or it reads the
// version the other (an updater) overwrites.
struct Edge {
    std::uint32_t resource = kNone;
    bool writeAfterRead = false;
};

// Kahn's algorithm; among ready passes the earliest declared goes first (deterministic).
std::vector<PassId> order(const Index& idx, const std::vector<std::optional<KeepReason>>& kept) {
    const std::size_t n = idx.passes.size();
    std::vector<std::map<PassId, Edge>> preds(n);  // predecessor -> first resource linking them
    std::vector<std::vector<PassId>> succs(n);
    auto link = [&](PassId before, PassId after, Edge e) {
        if (before != kNone && before != after && kept[before] && preds[after].emplace(before, e).second)
            succs[before].push_back(after);
    };
    for (PassId c = 0; c < n; ++c) {
        if (!kept[c]) continue;
        const PassDesc& pass = idx.passes[c];
        for (std::size_t i = 0; i < pass.accesses.size(); ++i) {
            const std::uint32_t r = idx.accessed[c][i];
            const std::uint32_t v = idx.versionRead(c, i);
            if (v != kNone) link(producerOf(idx, r, v), c, {r, false});
            // An updater overwrites the image its predecessor version's readers sample.
            if (pass.accesses[i].mode == AccessMode::ReadWrite)
                for (PassId reader : idx.readers[r][v]) link(reader, c, {r, true});
        }
    }
    std::vector<std::size_t> inDegree(n);
    std::set<PassId> ready;
    std::size_t keptCount = 0;
    for (PassId p = 0; p < n; ++p) {
        if (!kept[p]) continue;
        ++keptCount;
        inDegree[p] = preds[p].size();
        if (inDegree[p] == 0) ready.insert(p);
    }
    std::vector<PassId> result;
    while (!ready.empty()) {
        const PassId p = *ready.begin();
        ready.erase(ready.begin());
        result.push_back(p);
        for (PassId s : succs[p])
            if (--inDegree[s] == 0) ready.insert(s);
    }
    if (result.size() == keptCount) return result;

    // Every pass left over has a predecessor that is also left over: following predecessors from
    // any of them must revisit a pass, and the walk between the two visits is a cycle.
    auto left = [&](PassId p) { return kept[p] && inDegree[p] > 0; };
    PassId start = 0;
    while (!left(start)) ++start;
    std::vector<PassId> walk{start};
    std::map<PassId, std::size_t> position{{start, 0}};
    for (;;) {
        PassId pred = kNone;
        for (const auto& [w, e] : preds[walk.back()])
            if (left(w)) { pred = w; break; }
        if (auto it = position.find(pred); it != position.end()) {
            walk.erase(walk.begin(), walk.begin() + static_cast<std::ptrdiff_t>(it->second));
            break;
        }
        position.emplace(pred, walk.size());
        walk.push_back(pred);
    }
    std::reverse(walk.begin(), walk.end());  // producer before consumer
    std::string names, steps;
    for (std::size_t i = 0; i < walk.size(); ++i) {
        const PassId from = walk[i], to = walk[(i + 1) % walk.size()];
        const Edge& e = preds[to].at(from);
        names += fmt::format("{}'{}'", i ? ", " : "", idx.passName(from));
        steps += e.writeAfterRead
                     ? fmt::format("{}'{}' reads '{}' before '{}' updates it", i ? "; " : "", idx.passName(from),
                                   idx.resName(e.resource), idx.passName(to))
                     : fmt::format("{}'{}' writes '{}' read by '{}'", i ? "; " : "", idx.passName(from),
                                   idx.resName(e.resource), idx.passName(to));
    }
    throw GraphError(fmt::format("cycle through passes {}: {}", names, steps));
}

std::string usedBy(const Index& idx, std::uint32_t r) {
    for (PassId p = 0; p < idx.passes.size(); ++p)
        for (std::uint32_t a : idx.accessed[p])
            if (a == r) return fmt::format(" (accessed by pass '{}')", idx.passName(p));
    return {};
}

// Resolves every image's size, following relative sizes recursively.
std::vector<ResolvedResource> resolveSizes(const Index& idx) {
    const std::size_t n = idx.resources.size();
    std::vector<ResolvedResource> out(n);
    std::vector<int> state(n, 0);  // 0 unvisited, 1 on the current chain, 2 done
    std::vector<std::uint32_t> chain;
    auto resolve = [&](auto&& self, std::uint32_t r) -> void {
        if (state[r] == 2) return;
        const ResourceDesc& d = idx.resources[r];
        out[r].desc = d;
        auto fail = [&](const std::string& what) {
            throw GraphError(fmt::format("resource '{}'{}: {}", d.name, usedBy(idx, r), what));
        };
        if (d.kind == ResourceKind::Buffer) {
            if (d.bytes == 0) fail("buffer of 0 bytes");
            state[r] = 2;
            return;
        }
        if (d.layers == 0) fail("image with 0 layers");
        if (d.size.relativeTo.empty()) {
            if (d.size.width == 0 || d.size.height == 0)
                fail(fmt::format("absolute size {}x{} is empty", d.size.width, d.size.height));
            out[r].width = d.size.width;
            out[r].height = d.size.height;
            state[r] = 2;
            return;
        }
        if (!(d.size.scaleX > 0.0f) || !(d.size.scaleY > 0.0f) || !std::isfinite(d.size.scaleX) ||
            !std::isfinite(d.size.scaleY))
            fail(fmt::format("relative size has a bad scale {}x{}", d.size.scaleX, d.size.scaleY));
        const std::uint32_t base = idx.find(d.size.relativeTo);
        if (base == kNone) fail(fmt::format("size is relative to unknown resource '{}'", d.size.relativeTo));
        if (base == r) fail("size is relative to itself");
        if (idx.resources[base].kind == ResourceKind::Buffer)
            fail(fmt::format("size is relative to buffer '{}'", d.size.relativeTo));
        if (state[base] == 1) {
            std::string loop;
            auto it = std::find(chain.begin(), chain.end(), base);
            for (; it != chain.end(); ++it) loop += fmt::format("'{}' -> ", idx.resName(*it));
            fail(fmt::format("relative sizes form a cycle: {}'{}' -> '{}'", loop, d.name, idx.resName(base)));
        }
        state[r] = 1;
        chain.push_back(r);
        self(self, base);
        chain.pop_back();
        auto scaled = [](std::uint32_t v, float s) {
            return static_cast<std::uint32_t>(std::max(1.0, std::round(static_cast<double>(v) * s)));
        };
        out[r].width = scaled(out[base].width, d.size.scaleX);
        out[r].height = scaled(out[base].height, d.size.scaleY);
        state[r] = 2;
    };
    for (std::uint32_t r = 0; r < n; ++r) resolve(resolve, r);
    return out;
}

std::string keptBecause(const Index& idx, const std::vector<std::optional<KeepReason>>& kept, PassId p) {
    std::string text;
    for (PassId cur = p;;) {
        const KeepReason& why = *kept[cur];
        if (!text.empty()) text += " -> ";
        if (why.consumer == kNone) {
            text += fmt::format("writes output '{}'", idx.resName(why.resource));
            return text;
        }
        text += fmt::format("writes '{}' -> read by '{}'", idx.resName(why.resource), idx.passName(why.consumer));
        cur = why.consumer;
    }
}

std::string culledReason(const PassDesc& pass) {
    std::string writes;
    for (const Access& a : pass.accesses)
        if (writesTo(a.mode)) writes += fmt::format("{}'{}'", writes.empty() ? "" : ", ", a.resource);
    if (writes.empty()) return "writes nothing, so nothing can need it";
    return fmt::format("none of its writes ({}) reaches a requested output", writes);
}

// A pass's accesses with the version each reads or makes.
std::vector<Access> versioned(const Index& idx, PassId p) {
    std::vector<Access> accesses = idx.passes[p].accesses;
    for (std::size_t i = 0; i < accesses.size(); ++i) accesses[i].version = idx.versions[p][i];
    return accesses;
}

}  // namespace

void RenderGraph::addResource(ResourceDesc desc) {
    for (const ResourceDesc& r : resources_)
        if (r.name == desc.name) throw GraphError(fmt::format("duplicate resource '{}'", desc.name));
    resources_.push_back(std::move(desc));
}

PassId RenderGraph::addPass(PassDesc desc) {
    for (const PassDesc& p : passes_)
        if (p.name == desc.name) throw GraphError(fmt::format("duplicate pass '{}'", desc.name));
    passes_.push_back(std::move(desc));
    return static_cast<PassId>(passes_.size() - 1);
}

CompiledGraph RenderGraph::compile(std::span<const std::string> outputs) const {
    const Index idx = buildIndex(resources_, passes_);
    if (outputs.empty()) throw GraphError("compile() needs at least one output");
    std::vector<std::uint32_t> outputIds;
    for (const std::string& name : outputs) {
        const std::uint32_t r = idx.find(name);
        if (r == kNone) throw GraphError(fmt::format("unknown output '{}': no resource has that name", name));
        if (!idx.hasWriter(r) && !resources_[r].imported)
            throw GraphError(fmt::format("output '{}' has no producer: no pass writes it and it is not imported", name));
        if (std::find(outputIds.begin(), outputIds.end(), r) == outputIds.end()) outputIds.push_back(r);
    }

    const auto kept = cull(idx, outputIds);
    const std::vector<PassId> sequence = order(idx, kept);
    const std::vector<ResolvedResource> sizes = resolveSizes(idx);

    CompiledGraph g;
    g.outputs.assign(outputs.begin(), outputs.end());

    // Barrier plan: the state each resource was left in by its last access.
    struct State {
        bool touched = false;
        Usage usage = Usage::Undefined;
        bool wrote = false;
    };
    std::vector<State> state(resources_.size());
    for (PassId p : sequence) {
        CompiledPass cp{p, passes_[p].name, {}, keptBecause(idx, kept, p), versioned(idx, p)};
        for (std::size_t i = 0; i < cp.accesses.size(); ++i) {
            const Access& a = cp.accesses[i];
            const std::uint32_t r = idx.accessed[p][i];
            State& s = state[r];
            if (!s.touched) {
                cp.barriersBefore.push_back({a.resource, resources_[r].imported ? Usage::TransferDst : Usage::Undefined, a.usage});
            } else if (s.usage != a.usage || s.wrote || writesTo(a.mode)) {  // RAW, WAW and WAR
                cp.barriersBefore.push_back({a.resource, s.usage, a.usage});
            }
            s = {true, a.usage, writesTo(a.mode)};
            g.resources.emplace(a.resource, sizes[r]);
        }
        g.passes.push_back(std::move(cp));
    }
    for (std::uint32_t r : outputIds) {
        const State& s = state[r];
        const Usage from = s.touched ? s.usage : Usage::TransferDst;  // untouched output: imported
        if (from != Usage::TransferSrc || s.wrote) g.finalBarriers.push_back({resources_[r].name, from, Usage::TransferSrc});
        g.resources.emplace(resources_[r].name, sizes[r]);
    }
    for (PassId p = 0; p < passes_.size(); ++p)
        if (!kept[p]) g.culled.push_back({p, passes_[p].name, culledReason(passes_[p]), versioned(idx, p)});
    return g;
}

}  // namespace aamap::graph
