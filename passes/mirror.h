#pragma once
// Planar mirrors in the Snapshot, as the paper did them: for each planar mirror the camera sees,
// render the scene from the camera reflected in the mirror plane, clipped to the plane, and add
// it (times the mirror's reflectance) into the mirror's pixels. One reflection level: mirrors
// seen in a mirror show their diffuse part only.
//
// Three passes, present only when a planar mirror is reflected in this view:
//   "mirror"           the G-buffer once per mirror with its reflected view-projection (the
//                      camera's matrix times the reflection, so pixel (x, y) of layer i is what
//                      mirror i shows at snapshot pixel (x, y)), into layer i of mirror.colour;
//   "mirror.mask"      the mirror triangles from the camera, kept where the G-buffer's depth says
//                      they are the visible surface: (reflectance, layer + 1) per pixel;
//   "mirror.composite" snapshot += reflectance x mirror.colour[layer] (updates the snapshot).
//
// The scene's mirror planes come from scene/mirror_planes.h (findPlanarMirrors); its curved
// triangles are reflected through environment probes (passes/mirror_probes.h), and --explain names
// them. Per view, the planes that cover the most snapshot pixels are reflected (the budget below);
// the others show their diffuse part only.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "engine/vk/resources.h"
#include "passes/gbuffer.h"
#include "scene/mirror_planes.h"
#include "scene/scene.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

// Why the device cannot render reflected views into layers (shaderOutputLayer), or empty.
std::string reflectedViewsUnsupported(VulkanContext& context, const std::string& pass);

class MirrorPass {
public:
    // The per-view budget. Each reflected plane costs a full G-buffer render, so the planes that
    // matter for the image go first: the largest projected coverage, at most kMaxMirrors (the
    // layers of mirror.colour). A plane covering fewer than kMinReflectedPixels snapshot pixels
    // cannot hold a reflected edge that the 5 x 5 Laplacian and its blur tell apart from the
    // mirror's own outline, so it shows its diffuse part only.
    static constexpr std::uint32_t kMaxMirrors = 16;
    static constexpr double kMinReflectedPixels = 16.0;

    MirrorPass(VulkanContext& context, const Scene& scene);

    bool hasPlanarMirrors() const { return !mirrors_.planar.empty(); }
    const MirrorGroups& groups() const { return mirrors_; }
    // Whether add() would declare the mirror passes for this camera and snapshot size (a planar
    // mirror in view, within the budget).
    bool anyInView(const SnapshotView& view, glm::uvec2 snapshotPixels) const;

    // Declares the three passes for the mirrors `camera` sees (none: nothing is declared and the
    // reason is returned in `why`). `snapshot` and `depth` are the G-buffer's outputs, of
    // `snapshotPixels`; the reflected views are drawn with `gbuffer`'s shading
    // (GBufferPass::addReflected). `gbuffer` and this object must outlive execution.
    void add(graph::RenderGraph& graph, vk::GraphExecutor& executor, GBufferPass& gbuffer,
             const std::string& snapshot, const std::string& depth, const SnapshotView& view,
             glm::uvec2 snapshotPixels, const GBufferShadows& shadows, std::string* why = nullptr);

private:
    struct VisibleMirror {
        const PlanarMirror* mirror;
        float sign;     // of the eye's side of the plane
        double pixels;  // projectedPixels of its triangles
    };
    struct MirrorSelection {
        std::vector<VisibleMirror> reflected;  // largest first
        std::size_t inView = 0;                // planes covering any pixel, eye off the plane
        std::size_t tooSmall = 0;              // of those, under kMinReflectedPixels
        std::size_t overLimit = 0;             // large enough, beyond kMaxMirrors
    };
    MirrorSelection selectMirrors(const SnapshotView& view, glm::uvec2 snapshotPixels) const;
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
