#include "scene/polygon.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace aamap {
namespace {

float cross2(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool insideTriangle(glm::vec2 p, glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    return cross2(a, b, p) >= 0.0f && cross2(b, c, p) >= 0.0f && cross2(c, a, p) >= 0.0f;
}

std::vector<std::array<int, 3>> fan(int n) {
    std::vector<std::array<int, 3>> out;
    for (int i = 1; i + 1 < n; ++i) out.push_back({0, i, i + 1});
    return out;
}

}  // namespace

std::vector<std::array<int, 3>> triangulatePolygon(std::span<const glm::vec3> points) {
    const int n = static_cast<int>(points.size());
    if (n < 3) return {};
    if (n == 3) return {{0, 1, 2}};

    glm::vec3 normal(0.0f);  // Newell's method: robust for non-planar polygons
    for (int i = 0; i < n; ++i) {
        const glm::vec3 a = points[i], b = points[(i + 1) % n];
        normal += glm::vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const glm::vec3 m = glm::abs(normal);
    if (!(m.x + m.y + m.z > 0.0f) || n > 128) return fan(n);  // degenerate, or too big for O(n^3)

    // Project by dropping the dominant axis, keeping the polygon counter-clockwise in 2D.
    const int axis = (m.x >= m.y && m.x >= m.z) ? 0 : (m.y >= m.z ? 1 : 2);
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const bool flip = normal[axis] < 0.0f;
    std::vector<glm::vec2> p(n);
    for (int i = 0; i < n; ++i) p[i] = flip ? glm::vec2(points[i][v], points[i][u]) : glm::vec2(points[i][u], points[i][v]);

    if (n == 4) {
        bool convex = true;
        for (int i = 0; i < 4; ++i) convex = convex && cross2(p[i], p[(i + 1) % 4], p[(i + 2) % 4]) > 0.0f;
        if (convex) {
            const float d02 = glm::length(points[2] - points[0]), d13 = glm::length(points[3] - points[1]);
            if (d02 <= d13) return {{0, 1, 2}, {0, 2, 3}};
            return {{0, 1, 3}, {1, 2, 3}};
        }
    }

    std::vector<int> ring(n);
    for (int i = 0; i < n; ++i) ring[i] = i;
    std::vector<std::array<int, 3>> out;
    while (ring.size() > 3) {
        const int size = static_cast<int>(ring.size());
        bool clipped = false;
        for (int i = 0; i < size && !clipped; ++i) {
            const int a = ring[(i + size - 1) % size], b = ring[i], c = ring[(i + 1) % size];
            if (cross2(p[a], p[b], p[c]) <= 0.0f) continue;  // reflex or collinear corner
            bool empty = true;
            for (int j : ring) {
                if (j != a && j != b && j != c && p[j] != p[a] && p[j] != p[b] && p[j] != p[c] &&
                    insideTriangle(p[j], p[a], p[b], p[c])) {
                    empty = false;
                    break;
                }
            }
            if (!empty) continue;
            out.push_back({a, b, c});
            ring.erase(ring.begin() + i);
            clipped = true;
        }
        if (!clipped) return fan(n);
    }
    out.push_back({ring[0], ring[1], ring[2]});
    return out;
}

}  // namespace aamap
