#pragma once
// Planar mirrors in the Snapshot, as the paper did them: for each planar mirror the camera sees,
// render the scene from the camera reflected in the mirror plane, clipped to the plane, and add
// it (times the mirror's reflectance) into the mirror's pixels. One reflection level: mirrors
// seen in a mirror show their diffuse part only.
//
// Three passes, present only when a planar mirror is visible:
//   "mirror"           the G-buffer once per mirror with its reflected view-projection (the
//                      camera's matrix times the reflection, so pixel (x, y) of layer i is what
//                      mirror i shows at snapshot pixel (x, y)), into layer i of mirror.colour;
//   "mirror.mask"      the mirror triangles from the camera, kept where the G-buffer's depth says
//                      they are the visible surface: (reflectance, layer + 1) per pixel;
//   "mirror.composite" snapshot += reflectance x mirror.colour[layer] (updates the snapshot).
// A planar mirror is the set of MaterialKind::Mirror triangles of one object and one material
// when they are coplanar; other mirror groups (curved) get no reflection, and --explain says so.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "engine/vk/resources.h"
#include "passes/gbuffer.h"
#include "scene/scene.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

struct PlanarMirror {
    std::string name;                      // "object/material"
    glm::vec3 normal{0.0f};                // unit, the plane is dot(normal, p) = offset
    float offset = 0.0f;
    std::vector<std::uint32_t> triangles;  // indices into TriangleMesh::triangles
    glm::vec3 reflectance{1.0f};           // the tracer's ks for this material (after energy scaling)
};

struct MirrorGroups {
    std::vector<PlanarMirror> planar;
    std::vector<std::string> curved;  // mirror groups that are not coplanar: no reflection
};

// Groups the scene's mirror triangles per object and material and keeps the coplanar ones.
MirrorGroups findPlanarMirrors(const Scene& scene);

// Diffuse albedo and reflectance of a Mirror material as the tracer splits them
// (tracer/embree_scene.cpp convertMaterial): ks 0 means a perfect mirror, and kd + ks <= 1.
void mirrorAlbedos(const Material& m, glm::vec3& kd, glm::vec3& reflectance);

// Reflection in the plane dot(n, p) = d (n unit).
glm::mat4 reflectionMatrix(glm::vec3 n, float d);

class MirrorPass {
public:
    static constexpr std::uint32_t kMaxMirrors = 16;  // per view: the nearest visible ones

    MirrorPass(VulkanContext& context, const Scene& scene);

    bool hasPlanarMirrors() const { return !mirrors_.planar.empty(); }
    // Whether add() would declare the mirror passes for this camera (a planar mirror in view).
    bool anyInView(const SnapshotView& view) const;

    // Declares the three passes for the mirrors `camera` sees (none: nothing is declared and the
    // reason is returned in `why`). `snapshot` and `depth` are the G-buffer's outputs; the
    // reflected views are drawn with `gbuffer`'s shading (GBufferPass::addReflected). `gbuffer`
    // and this object must outlive execution.
    void add(graph::RenderGraph& graph, vk::GraphExecutor& executor, GBufferPass& gbuffer,
             const std::string& snapshot, const std::string& depth, const SnapshotView& view,
             const GBufferShadows& shadows, std::string* why = nullptr);

private:
    struct VisibleMirror {
        const PlanarMirror* mirror;
        float sign;      // of the eye's side of the plane
        float distance;  // of the nearest corner to the eye
    };
    std::vector<VisibleMirror> visibleMirrors(const SnapshotView& view) const;
    void buildMaskPipeline();  // the executor's prepare steps
    void buildCompositePipeline();

    VulkanContext* context_;
    MirrorGroups mirrors_;
    std::string unsupported_;  // why the device cannot render mirrors, if it cannot
    std::vector<glm::vec3> positions_;  // the mesh's, for visibility tests
    std::vector<glm::uvec3> triangles_;
    vk::Pipeline maskPipeline_, compositePipeline_;  // built when their pass is kept
    vk::Buffer maskVertices_;            // rebuilt per view: only the visible mirrors, with layers
    std::uint32_t maskVertexCount_ = 0;
};

}  // namespace aamap::passes
