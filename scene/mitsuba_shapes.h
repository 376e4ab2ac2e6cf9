#pragma once
// Mitsuba shapes to triangles. Meshes: obj (scene/obj_loader.h; its MTL materials are not used,
// the shape's BSDF is), ply (binary or ASCII, through Assimp) and serialized (scene/mitsuba_serialized.h;
// shape_index picks the mesh). Built-in shapes, in their local
// frame before to_world: rectangle [-1,1]^2 at z = 0 facing +Z; cube [-1,1]^3; disk of radius 1
// at z = 0 facing +Z; sphere (center, radius); cylinder (p0, p1, radius: an open tube, no caps,
// as in Mitsuba). Curved shapes are tessellated so that no point of
// the mesh lies farther than kTessellationError x radius from the true surface; the disk keeps
// its exact area (an area light keeps its power).
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/mitsuba_xml.h"
#include "scene/scene.h"

namespace aamap::mitsuba {

inline constexpr float kTessellationError = 1e-3f;  // relative to the radius

struct ShapeMesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // per vertex; empty: flat
    std::vector<glm::vec2> uvs;      // per vertex, v = 0 at the image's top; empty: none
    std::vector<glm::uvec3> triangles;
};

// The local-space triangles of a shape of type obj, ply, serialized, rectangle, cube, disk, sphere or cylinder. Throws
// InputError (the shape's file:line) for a missing or unreadable mesh file or a bad parameter.
ShapeMesh shapeGeometry(const Element& shape, Warnings& warnings);

// Segments around a circle for the error bound: the chord's sagitta 1 - cos(pi / n) <= error.
int circleSegments(float relativeError);

// Appends a shape to the scene's mesh, transformed by toWorld (normals by its inverse transpose;
// a mirroring transform keeps the winding facing the same way). flipNormals turns the shape's
// front side; faceNormals drops its vertex normals. Zero-area triangles are dropped and counted.
void appendShape(TriangleMesh& mesh, const ShapeMesh& shape, const glm::mat4& toWorld, bool flipNormals,
                 bool faceNormals, std::uint32_t material, std::uint32_t object, std::size_t& degenerate);

}  // namespace aamap::mitsuba
