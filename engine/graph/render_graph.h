#pragma once
// The render-graph compiler: pure CPU code, no Vulkan includes (tested without a GPU).
//
// Passes declare the named resources they access and how. Nobody writes barriers by hand: the
// compiler culls everything the requested outputs do not need, orders the rest topologically
// and plans, for every access, the transition from the resource's previous use.
//
// Versioned resources (as FrameGraph and Granite): every write makes a new version of a resource.
//   * R has at most one initial writer (mode Write), which makes version 0; without one, version 0
//     is the host upload of an imported resource. Two initial writers are an error.
//   * Each pass that updates R in place (mode ReadWrite) reads the version before it and makes the
//     next one; updaters form one chain in declaration order, so any number of them compose (a
//     planar-mirror composite and a probe composite both updating the snapshot).
//   * A read of R sees the newest version made by a pass declared before the reader (an import
//     counts as declared first). A read declared before every writer of R sees R's final version,
//     so a chain may also be declared consumer-first.
//   * A pass depends on the producer of each version it reads (read after write), and an updater
//     also on every pass that reads the version it overwrites (write after read: the versions share
//     one image). A read of a version nobody makes is an error ("missing producer").
#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace aamap::graph {

enum class Format : std::uint8_t { RGBA8Unorm, RGBA16Float, RGBA32Float, R32Float, R16Float, D32Float };
const char* toString(Format format);
bool isDepthFormat(Format format);
std::uint32_t bytesPerTexel(Format format);

enum class Usage : std::uint8_t {
    Undefined,        // only as the "before" state of a first use: contents are discarded
    Sampled,          // read through a sampler or texelFetch (fragment or compute)
    StorageRead,      // imageLoad / storage buffer read
    StorageWrite,     // imageStore / storage buffer write
    ColorAttachment,  // rasterised colour
    DepthAttachment,  // depth test and write
    TransferSrc,      // copied out (readback)
    TransferDst,      // filled by a copy (upload of imported resources)
};
const char* toString(Usage usage);

enum class AccessMode : std::uint8_t { Read, Write, ReadWrite };

// Absolute size, or a scale of another resource's resolved size (rounded to nearest, at least 1).
struct Size {
    std::uint32_t width = 0, height = 0;  // used when relativeTo is empty
    std::string relativeTo;
    float scaleX = 1.0f, scaleY = 1.0f;

    static Size absolute(std::uint32_t w, std::uint32_t h) { return {w, h, {}, 1.0f, 1.0f}; }
    static Size relative(std::string resource, float sx = 1.0f, float sy = 1.0f) {
        return {0, 0, std::move(resource), sx, sy};
    }
};

enum class ResourceKind : std::uint8_t { Image, Buffer };

struct ResourceDesc {
    std::string name;
    ResourceKind kind = ResourceKind::Image;
    Format format = Format::RGBA16Float;  // images
    Size size;                            // images
    std::uint32_t layers = 1;             // images: 6 for a cube map
    bool cube = false;                    // images: view as a cube map when sampled
    std::uint64_t bytes = 0;              // buffers
    bool imported = false;                // contents uploaded from the host before the graph runs
};

// Shorthands for the two common descriptions.
inline ResourceDesc imageResource(std::string name, Format format, Size size, bool imported = false) {
    ResourceDesc d;
    d.name = std::move(name);
    d.format = format;
    d.size = std::move(size);
    d.imported = imported;
    return d;
}
inline ResourceDesc bufferResource(std::string name, std::uint64_t bytes) {
    ResourceDesc d;
    d.name = std::move(name);
    d.kind = ResourceKind::Buffer;
    d.bytes = bytes;
    return d;
}

struct Access {
    std::string resource;
    Usage usage = Usage::Sampled;
    AccessMode mode = AccessMode::Read;
    // Filled by the compiler in CompiledPass/CulledPass: the version of the resource this access
    // reads (Read) or makes (Write, ReadWrite); ignored in a PassDesc.
    std::uint32_t version = 0;
};
inline Access reads(std::string r, Usage u) { return {std::move(r), u, AccessMode::Read, 0}; }
inline Access writes(std::string r, Usage u) { return {std::move(r), u, AccessMode::Write, 0}; }
inline Access updates(std::string r, Usage u) { return {std::move(r), u, AccessMode::ReadWrite, 0}; }

enum class QueueKind : std::uint8_t { Graphics, Compute };

struct PassDesc {
    std::string name;
    QueueKind queue = QueueKind::Graphics;
    std::vector<Access> accesses;
    std::string purpose;  // why the scene needs it, e.g. "shadow cube map for light 'ceiling' sample 2"
};

using PassId = std::uint32_t;

// A transition a resource needs before an access. `from` is Usage::Undefined on a first use
// whose contents are not needed (initial write) and Usage::TransferDst for imported resources.
struct Barrier {
    std::string resource;
    Usage from = Usage::Undefined;
    Usage to = Usage::Undefined;
};

struct ResolvedResource {
    ResourceDesc desc;
    std::uint32_t width = 0, height = 0;  // images only
};

struct CompiledPass {
    PassId id = 0;
    std::string name;
    std::vector<Barrier> barriersBefore;
    std::string keptBecause;  // e.g. "writes 'edges', read by 'blur' -> ... -> output 'aamap'"
    std::vector<Access> accesses;  // copied from its PassDesc (DOT edges, executor bindings)
};

struct CulledPass {
    PassId id = 0;
    std::string name;
    std::string reason;  // e.g. "none of its writes ('debug') reaches a requested output"
    std::vector<Access> accesses;  // copied from its PassDesc (DOT edges)
};

struct CompiledGraph {
    std::vector<CompiledPass> passes;  // execution order
    std::vector<CulledPass> culled;
    std::map<std::string, ResolvedResource> resources;  // live resources only
    std::vector<std::string> outputs;                     // as requested
    std::vector<Barrier> finalBarriers;  // brings every output to TransferSrc for readback

    // One line per pass kept (and why) and per pass culled (and why).
    std::string explain() const;
    // Graphviz DOT: passes as boxes, resources as ellipses, culled passes greyed out.
    std::string toDot() const;
};

class GraphError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class RenderGraph {
public:
    // Throws GraphError on a duplicate name.
    void addResource(ResourceDesc desc);
    PassId addPass(PassDesc desc);

    const std::vector<ResourceDesc>& resources() const { return resources_; }
    const std::vector<PassDesc>& passes() const { return passes_; }

    // Culls, orders and plans barriers for the given outputs (each its final version). Throws
    // GraphError naming the pass and the resource on: an unknown resource, a missing producer,
    // two initial writers, a cycle,
    // a relative size that refers to an unknown resource or to itself (also indirectly).
    CompiledGraph compile(std::span<const std::string> outputs) const;

private:
    std::vector<ResourceDesc> resources_;
    std::vector<PassDesc> passes_;
};

}  // namespace aamap::graph
