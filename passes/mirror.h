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
// The MaterialKind::Mirror triangles of one object and one material form a mirror group, which
// findPlanarMirrors splits into planes (a wall mirror with its bevel strips, the faces of a
// mirrored box): each plane is a PlanarMirror. A group of many small planes is a tessellated
// curved surface: its triangles outside the planes it keeps are curved, reflected through
// environment probes (passes/mirror_probes.h), and --explain names them. Per view, the planes
// that cover the most snapshot pixels are reflected (the budget below); the others show their
// diffuse part only.
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
#include "scene/scene.h"
#include "passes/snapshot_graph.h"

namespace aamap::passes {

// How a mirror group splits into planes. Triangles share a plane when their normals are within
// kPlaneNormalCos of each other (about 0.8 degrees: far below a bevel's or a box edge's angle,
// far above float noise in a modelled flat face) and their vertices within kPlaneOffsetTolerance
// x the scene's diagonal of the plane (either orientation: both faces of a thin mirror are one);
// a smaller plane whose vertices all lie in a larger one is part of it (a sliver's tilted normal).
inline constexpr float kPlaneNormalCos = 0.9999f;
inline constexpr float kPlaneOffsetTolerance = 1e-4f;
// A group of at most kMaxPlanesPerGroup planes is faceted on purpose (a framed mirror: 5, a box:
// 6), so every plane is a mirror. A group of more planes is a tessellated curved surface, whose
// facets hold a small share of its area each (a 12 x 6 sphere: under 3%): only planes holding at
// least kMinPlaneAreaFraction of the group's area are mirrors there (the flat cap of a cylinder).
inline constexpr std::size_t kMaxPlanesPerGroup = 8;
inline constexpr float kMinPlaneAreaFraction = 0.1f;

struct PlanarMirror {
    std::string name;                      // "object/material", plus " plane k" when its group has several
    glm::vec3 normal{0.0f};                // unit, the plane is dot(normal, p) = offset
    float offset = 0.0f;
    std::vector<std::uint32_t> triangles;  // indices into TriangleMesh::triangles, ascending
    glm::vec3 reflectance{1.0f};           // the tracer's ks for this material (after energy scaling)
};

// The triangles of one mirror group that lie in no accepted plane: reflected through an
// environment probe (passes/mirror_probes.h), not a planar view.
struct CurvedMirror {
    std::string group;           // "object/material"
    std::size_t planes = 0;      // of the same group that are PlanarMirrors
    std::vector<std::uint32_t> triangles;  // the curved ones, ascending
    glm::vec3 reflectance{1.0f};             // as PlanarMirror::reflectance
    std::string describe() const;  // "object 3/m: 2 planes reflected, 40 triangles curved"
};

struct MirrorGroups {
    std::vector<PlanarMirror> planar;  // per group (by object, then material), largest plane first
    std::vector<CurvedMirror> curved;  // the groups with curved triangles, in the same order
};

// Splits the scene's mirror triangles per object and material, then each group into planes.
MirrorGroups findPlanarMirrors(const Scene& scene);

// Snapshot pixels that `triangles` (of `positions`) cover under `viewProj` (w the view depth),
// each clipped to the frustum and to w >= nearPlane, in a `pixels`-sized image. Overlaps count
// twice and occlusion is ignored: an over-estimate, so a plane that shows is never skipped for
// being small. Indices out of range count nothing. ndcBounds (if given) gets the clipped
// triangles' NDC bounding box (min x, min y, max x, max y; empty: min > max).
double projectedPixels(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
                       const std::vector<std::uint32_t>& which, const glm::mat4& viewProj, float nearPlane,
                       glm::uvec2 pixels, glm::vec4* ndcBounds = nullptr);

// Diffuse albedo and reflectance of a Mirror material as the tracer splits them
// (tracer/embree_scene.cpp convertMaterial): ks 0 means a perfect mirror, and kd + ks <= 1.
void mirrorAlbedos(const Material& m, glm::vec3& kd, glm::vec3& reflectance);

// Reflection in the plane dot(n, p) = d (n unit).
glm::mat4 reflectionMatrix(glm::vec3 n, float d);

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
