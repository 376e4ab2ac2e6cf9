#pragma once
// Curved mirrors in the Snapshot. The tracer reflects every mirror triangle; a planar view
// (passes/mirror.h) cannot show what a curved one reflects, so each curved mirror group in view
// gets an environment probe: the G-buffer rendered into the 6 faces of a cube from the centre of
// the group's bounding sphere, with the near plane at its radius so that the mirror does not see
// itself. The curved triangles, drawn from the camera where they are the visible surface, then
// add reflectance x the probe's colour in the reflected direction. The usual probe
// approximation: exact for a mirror small against its distance to what it reflects; no parallax,
// one reflection level (mirrors seen in a probe show their diffuse part).
//
// Two passes, present only when a curved mirror is in view:
//   "mirror.probes"           GBufferPass::addReflected with one view per cube face, into layers
//                             6i..6i+5 of mirror.probes.colour (the shadow maps' face order and
//                             coordinates, glsl/shadow_cube.glsl, so one lookup serves both);
//   "mirror.probes.composite" the curved triangles from the camera, added into the snapshot.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "engine/vk/resources.h"
#include "passes/gbuffer.h"
#include "passes/mirror.h"
#include "scene/scene.h"

namespace aamap::passes {

inline const std::string kMirrorProbeColour = "mirror.probes.colour";
inline const std::string kMirrorProbeDepth = "mirror.probes.depth";
inline const std::string kMirrorProbesPass = "mirror.probes";
inline const std::string kMirrorProbeCompositePass = "mirror.probes.composite";

// The view of cube face `face` (0..5 = +X -X +Y -Y +Z -Z) from `centre` as a reversed-depth
// matrix: clip = (sc, tc, nearPlane, ma) of p - centre, the shadow cube maps' projection, so
// texel (x, y) of the face is direction ((x + 0.5) / size * 2 - 1, ...) of cubeFaceCoords.
glm::mat4 cubeFaceViewProjection(glm::vec3 centre, int face, float nearPlane);

class MirrorProbes {
public:
    // The per-view budget: each probe costs six G-buffer renders of kFaceSize^2 (together about
    // a 160^2 snapshot at 64), so the groups that cover the most pixels go first. A group under
    // MirrorPass::kMinReflectedPixels shows no reflected edge the aamap could tell apart.
    static constexpr std::uint32_t kMaxProbes = 4;
    static constexpr std::uint32_t kFaceSize = 64;

    MirrorProbes(VulkanContext& context, const Scene& scene, const MirrorGroups& groups);

    bool any() const { return !probes_.empty() && unsupported_.empty(); }
    bool anyInView(const SnapshotView& view, glm::uvec2 snapshotPixels) const;

    // Declares both passes for the probes `view` sees (none: nothing is declared); `why` says
    // which were rendered, or why none. `gbuffer` and this object must outlive execution.
    void add(graph::RenderGraph& graph, vk::GraphExecutor& executor, GBufferPass& gbuffer,
             const std::string& snapshot, const std::string& depth, const SnapshotView& view,
             glm::uvec2 snapshotPixels, const GBufferShadows& shadows, std::string* why = nullptr);

private:
    struct Vertex {  // of the composite's draw (mirror_probe.vert)
        glm::vec3 position;
        glm::vec3 normal;
        glm::vec3 reflectance;
        float firstLayer;  // 6 x the probe's index in the view's selection, set per view
    };
    struct Probe {
        std::string name;
        std::vector<Vertex> vertices;             // the curved triangles, three corners each
        std::vector<glm::vec3> corners;           // their positions, for projectedPixels
        std::vector<glm::uvec3> cornerTriangles;  // (3i, 3i + 1, 3i + 2)
        std::vector<std::uint32_t> allTriangles;  // 0 .. n - 1
        glm::vec3 centre{0.0f};
        float radius = 0.0f;  // of the bounding sphere about centre: the probe's near plane
    };
    struct Selected {
        const Probe* probe;
        double pixels;
    };
    std::vector<Selected> select(const SnapshotView& view, glm::uvec2 snapshotPixels) const;
    void buildCompositePipeline();

    VulkanContext* context_;
    std::string unsupported_;
    std::vector<Probe> probes_;
    vk::Pipeline compositePipeline_;
    vk::Buffer vertices_;  // rebuilt per view: the selected probes' triangles
    std::uint32_t vertexCount_ = 0;
};

}  // namespace aamap::passes
