#include "scene/mesh_orientation.h"

#include <utility>

#include <glm/geometric.hpp>

namespace aamap {

std::size_t orientTrianglesToNormals(TriangleMesh& mesh) {
    if (mesh.normals.size() != mesh.positions.size()) return 0;
    std::size_t reversed = 0;
    for (glm::uvec3& t : mesh.triangles) {
        const glm::vec3 face = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
        const glm::vec3 shading = mesh.normals[t.x] + mesh.normals[t.y] + mesh.normals[t.z];
        // Not `!(d >= 0)`: NaN normals carry no orientation, and a NaN test would reverse them.
        if (glm::dot(face, shading) < 0.0f) {
            std::swap(t.y, t.z);
            ++reversed;
        }
    }
    return reversed;
}

}  // namespace aamap
