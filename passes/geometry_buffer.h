#pragma once
// The geometric aamap's raster: per snapshot texel the world normal (turned towards the camera),
// the view depth and the object and material ids (layout: glsl/shared/geometric_edges.h). No
// shading. Its own vertex buffer (the G-buffer's carries no ids), uploaded on first use, so a
// Snapshot that only asks for the luminance map never pays for it.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/graph/render_graph.h"
#include "engine/vk/graph_executor.h"
#include "engine/vk/pipeline.h"
#include "engine/vk/resources.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace aamap::passes {

inline const std::string kGeometryNormalDepth = "geometry_normal_depth";  // RGBA32F
inline const std::string kGeometryIds = "geometry_ids";                    // RGBA32F
inline const std::string kGeometryDepth = "geometry_depth";                // D32, the raster's z-buffer

class GeometryBufferPass {
public:
    static constexpr graph::Format kFormat = graph::Format::RGBA32Float;

    GeometryBufferPass(VulkanContext& context, const Scene& scene);  // flattens the mesh, no upload yet
    ~GeometryBufferPass();

    // Declares kGeometryNormalDepth, kGeometryIds and kGeometryDepth sized like `like` and the
    // pass "geometry_buffer". Must outlive execution; call prepare() before executing a graph
    // that keeps the pass.
    void add(graph::RenderGraph& graph, vk::GraphExecutor& executor, const std::string& like,
             const PinholeCamera& camera, float nearPlane, float farPlane);
    void prepare();  // uploads the vertices once
    bool prepared() const { return static_cast<bool>(vertices_) || vertexCount_ == 0; }

private:
    VulkanContext* context_;
    vk::Pipeline pipeline_;
    std::vector<std::byte> pending_;  // flattened vertices until prepare()
    vk::Buffer vertices_;
    std::uint32_t vertexCount_ = 0;
};

}  // namespace aamap::passes
