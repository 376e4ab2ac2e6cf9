#include "scene/mirror_planes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

namespace aamap {
namespace {

bool positive(glm::vec3 c) { return c.x > 0.0f || c.y > 0.0f || c.z > 0.0f; }

}  // namespace

void mirrorAlbedos(const Material& m, glm::vec3& kd, glm::vec3& reflectance) {
    kd = m.kd;
    reflectance = glm::max(m.ks, glm::vec3(0.0f));
    if (!positive(reflectance)) reflectance = glm::vec3(1.0f);
    const glm::vec3 sum = kd + reflectance;
    const float most = std::max({sum.x, sum.y, sum.z});
    if (most > 1.0f) {
        kd /= most;
        reflectance /= most;
    }
}

glm::mat4 reflectionMatrix(glm::vec3 n, float d) {
    glm::mat4 r(1.0f);
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) r[c][k] -= 2.0f * n[k] * n[c];
    r[3] = glm::vec4(2.0f * d * n, 1.0f);
    return r;
}

std::string CurvedMirror::describe() const {
    const std::size_t n = triangles.size();
    if (planes == 0) return fmt::format("{}: {} triangle{} curved", group, n, n == 1 ? "" : "s");
    return fmt::format("{}: {} plane{} reflected, {} triangle{} curved", group, planes, planes == 1 ? "" : "s", n,
                       n == 1 ? "" : "s");
}

namespace {

struct Facet {
    std::uint32_t triangle;
    glm::vec3 normal;  // unit
    float area;
    glm::vec3 centroid;
};

// A set of triangles in one plane. Membership is tested against the plane of its first (largest)
// triangle, so the plane cannot drift along a chain of slightly tilted neighbours.
struct PlaneCluster {
    glm::vec3 seedNormal;
    float seedOffset;
    glm::vec3 weightedNormal{0.0f};    // sum of area x normal, oriented as the seed
    glm::vec3 weightedCentroid{0.0f};  // sum of area x centroid
    float area = 0.0f;
    std::vector<std::uint32_t> triangles;
};

// Clusters are found through a grid on the unit sphere of normals: two normals within
// kPlaneNormalCos are closer than its chord in every coordinate, so in neighbouring cells.
class NormalGrid {
public:
    NormalGrid() : cell_(std::sqrt(2.0f * (1.0f - kPlaneNormalCos))) {}
    void insert(glm::vec3 n, std::uint32_t cluster) { cells_[key(cellOf(n))].push_back(cluster); }
    // The lowest-numbered cluster near n or -n for which `accepts` holds, or -1.
    template <class Accepts>
    std::int64_t find(glm::vec3 n, Accepts accepts) const {
        std::int64_t best = -1;
        for (const glm::vec3 direction : {n, -n}) {
            const glm::ivec3 c = cellOf(direction);
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const auto it = cells_.find(key(c + glm::ivec3(dx, dy, dz)));
                        if (it == cells_.end()) continue;
                        for (const std::uint32_t cluster : it->second)
                            if ((best < 0 || cluster < best) && accepts(cluster)) best = cluster;
                    }
        }
        return best;
    }

private:
    glm::ivec3 cellOf(glm::vec3 n) const { return glm::ivec3(glm::floor(n / cell_)); }
    static std::uint64_t key(glm::ivec3 c) {
        const auto part = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v + (1 << 20))); };
        return part(c.x) | part(c.y) << 21 | part(c.z) << 42;
    }
    float cell_;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

std::vector<PlaneCluster> clusterIntoPlanes(const TriangleMesh& mesh, std::vector<Facet> facets, float tolerance) {
    // Largest first (then by index, for a deterministic result): the seeds are the triangles
    // whose normals the float positions pin down best.
    std::sort(facets.begin(), facets.end(), [](const Facet& a, const Facet& b) {
        return a.area != b.area ? a.area > b.area : a.triangle < b.triangle;
    });
    std::vector<PlaneCluster> clusters;
    NormalGrid grid;
    for (const Facet& f : facets) {
        const glm::uvec3 v = mesh.triangles[f.triangle];
        const auto inPlane = [&](std::uint32_t c) {
            const PlaneCluster& cluster = clusters[c];
            if (std::fabs(glm::dot(f.normal, cluster.seedNormal)) <= kPlaneNormalCos) return false;
            for (int k = 0; k < 3; ++k)
                if (!(std::fabs(glm::dot(cluster.seedNormal, mesh.positions[v[k]]) - cluster.seedOffset) <= tolerance))
                    return false;
            return true;
        };
        const std::int64_t found = grid.find(f.normal, inPlane);
        if (found < 0) {
            PlaneCluster seed;
            seed.seedNormal = f.normal;
            seed.seedOffset = glm::dot(f.normal, f.centroid);
            grid.insert(f.normal, static_cast<std::uint32_t>(clusters.size()));
            clusters.push_back(std::move(seed));
        }
        PlaneCluster& cluster = clusters[found < 0 ? clusters.size() - 1 : static_cast<std::size_t>(found)];
        const float orientation = glm::dot(f.normal, cluster.seedNormal) < 0.0f ? -1.0f : 1.0f;
        cluster.weightedNormal += f.area * orientation * f.normal;
        cluster.weightedCentroid += f.area * f.centroid;
        cluster.area += f.area;
        cluster.triangles.push_back(f.triangle);
    }
    return clusters;  // in order of their largest triangle
}

bool allVerticesInPlane(const TriangleMesh& mesh, const PlaneCluster& cluster, const PlaneCluster& plane,
                        float tolerance) {
    for (const std::uint32_t t : cluster.triangles)
        for (int k = 0; k < 3; ++k)
            if (!(std::fabs(glm::dot(plane.seedNormal, mesh.positions[mesh.triangles[t][k]]) - plane.seedOffset) <=
                  tolerance))
                return false;
    return true;
}

// Sorts the clusters by area, largest first, after merging each cluster whose vertices all lie in
// a larger one's plane into it: a sliver whose float normal tilts past kPlaneNormalCos is still
// part of its plane, and would otherwise be a plane of its own or a curved hole in the mirror.
// Only the largest clusters can be accepted as mirrors (at most kMaxPlanesPerGroup in a faceted
// group, at most 1 / kMinPlaneAreaFraction holding that share), so only they absorb others.
void absorbClustersInLargerPlanes(const TriangleMesh& mesh, std::vector<PlaneCluster>& clusters, float tolerance) {
    const auto byArea = [](const PlaneCluster& a, const PlaneCluster& b) { return a.area > b.area; };
    std::stable_sort(clusters.begin(), clusters.end(), byArea);
    const auto absorbers = static_cast<std::size_t>(
        std::max<double>(static_cast<double>(kMaxPlanesPerGroup), std::ceil(1.0 / kMinPlaneAreaFraction)));
    std::vector<bool> absorbed(clusters.size(), false);
    for (std::size_t c = 1; c < clusters.size(); ++c) {
        for (std::size_t into = 0; into < std::min(c, absorbers); ++into) {
            if (absorbed[into] || !allVerticesInPlane(mesh, clusters[c], clusters[into], tolerance)) continue;
            PlaneCluster& plane = clusters[into];
            const PlaneCluster& part = clusters[c];
            const float orientation = glm::dot(part.weightedNormal, plane.seedNormal) < 0.0f ? -1.0f : 1.0f;
            plane.weightedNormal += orientation * part.weightedNormal;
            plane.weightedCentroid += part.weightedCentroid;
            plane.area += part.area;
            plane.triangles.insert(plane.triangles.end(), part.triangles.begin(), part.triangles.end());
            absorbed[c] = true;
            break;
        }
    }
    std::vector<PlaneCluster> kept;
    for (std::size_t c = 0; c < clusters.size(); ++c)
        if (!absorbed[c]) kept.push_back(std::move(clusters[c]));
    clusters = std::move(kept);
    std::stable_sort(clusters.begin(), clusters.end(), byArea);
}

}  // namespace

MirrorGroups findPlanarMirrors(const Scene& scene) {
    const TriangleMesh& mesh = scene.mesh;
    const auto vertexCount = static_cast<std::uint32_t>(mesh.positions.size());
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<Facet>> groups;  // (object, material)
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const std::uint32_t material = t < mesh.materialIds.size() ? mesh.materialIds[t] : 0u;
        if (material >= scene.materials.size() || scene.materials[material].kind != MaterialKind::Mirror) continue;
        const std::uint32_t object = t < mesh.objectIds.size() ? mesh.objectIds[t] : 0u;
        const glm::uvec3 i = mesh.triangles[t];
        if (i.x >= vertexCount || i.y >= vertexCount || i.z >= vertexCount) continue;
        const glm::vec3 a = mesh.positions[i.x], b = mesh.positions[i.y], c = mesh.positions[i.z];
        const glm::vec3 cross = glm::cross(b - a, c - a);
        const float length = glm::length(cross);
        if (!(length > 0.0f) || !std::isfinite(length)) continue;  // no area: nothing to reflect in or to see
        groups[{object, material}].push_back({static_cast<std::uint32_t>(t), cross / length, 0.5f * length, (a + b + c) / 3.0f});
    }
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& p : mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const float diagonal = glm::length(hi - lo);
    const float tolerance = kPlaneOffsetTolerance * (std::isfinite(diagonal) ? std::max(diagonal, 1e-6f) : 1.0f);

    MirrorGroups out;
    for (auto& [key, facets] : groups) {
        const Material& material = scene.materials[key.second];
        const std::string name = fmt::format("object {}/{}", key.first, material.name);
        float groupArea = 0.0f;
        for (const Facet& f : facets) groupArea += f.area;
        std::vector<PlaneCluster> clusters = clusterIntoPlanes(mesh, std::move(facets), tolerance);
        absorbClustersInLargerPlanes(mesh, clusters, tolerance);
        const bool faceted = clusters.size() <= kMaxPlanesPerGroup;
        glm::vec3 kd, reflectance;
        mirrorAlbedos(material, kd, reflectance);
        std::vector<PlanarMirror> planes;
        CurvedMirror curved{name};
        for (PlaneCluster& cluster : clusters) {
            const float length = glm::length(cluster.weightedNormal);
            if (!faceted && !(cluster.area >= kMinPlaneAreaFraction * groupArea)) {
                curved.triangles.insert(curved.triangles.end(), cluster.triangles.begin(), cluster.triangles.end());
                continue;
            }
            PlanarMirror mirror;
            // Area-weighted: the normal of the summed normals, through the area-weighted centroid.
            mirror.normal = length > 0.0f ? cluster.weightedNormal / length : cluster.seedNormal;
            mirror.offset = glm::dot(mirror.normal, cluster.weightedCentroid / cluster.area);
            mirror.triangles = std::move(cluster.triangles);
            std::sort(mirror.triangles.begin(), mirror.triangles.end());
            mirror.reflectance = reflectance;
            planes.push_back(std::move(mirror));
        }
        const bool onePlane = planes.size() == 1 && curved.triangles.empty();
        for (std::size_t k = 0; k < planes.size(); ++k) {
            planes[k].name = onePlane ? name : fmt::format("{} plane {}", name, k + 1);
            out.planar.push_back(std::move(planes[k]));
        }
        curved.planes = planes.size();
        std::sort(curved.triangles.begin(), curved.triangles.end());
        curved.reflectance = reflectance;
        if (!curved.triangles.empty()) out.curved.push_back(std::move(curved));
    }
    return out;
}

double projectedPixels(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles,
                       const std::vector<std::uint32_t>& which, const glm::mat4& viewProj, float nearPlane,
                       glm::uvec2 pixels, glm::vec4* ndcBounds) {
    glm::vec4 bounds(INFINITY, INFINITY, -INFINITY, -INFINITY);
    // Clip-space half-planes of the visible region: x, y within [-w, w], w at least the near plane.
    const float nearest = nearPlane > 0.0f ? nearPlane : 1e-6f;  // keeps the divide finite
    const auto inside = [nearest](const glm::vec4& c, int plane) {
        switch (plane) {
            case 0: return c.w - c.x;
            case 1: return c.w + c.x;
            case 2: return c.w - c.y;
            case 3: return c.w + c.y;
            default: return c.w - nearest;
        }
    };
    double ndcArea = 0.0;
    std::vector<glm::vec4> polygon, clipped;
    for (const std::uint32_t t : which) {
        if (t >= triangles.size()) continue;
        const glm::uvec3 v = triangles[t];
        if (v.x >= positions.size() || v.y >= positions.size() || v.z >= positions.size()) continue;
        polygon.clear();
        for (int k = 0; k < 3; ++k) polygon.push_back(viewProj * glm::vec4(positions[v[k]], 1.0f));
        for (int plane = 0; plane < 5 && !polygon.empty(); ++plane) {  // Sutherland-Hodgman
            clipped.clear();
            for (std::size_t k = 0; k < polygon.size(); ++k) {
                const glm::vec4& p = polygon[k];
                const glm::vec4& q = polygon[(k + 1) % polygon.size()];
                const float dp = inside(p, plane), dq = inside(q, plane);
                if (dp >= 0.0f) clipped.push_back(p);
                if ((dp >= 0.0f) != (dq >= 0.0f)) clipped.push_back(p + (dp / (dp - dq)) * (q - p));
            }
            std::swap(polygon, clipped);
        }
        if (polygon.size() < 3) continue;
        double twiceArea = 0.0;  // shoelace, after the divide (w >= nearPlane > 0 here)
        for (std::size_t k = 0; k < polygon.size(); ++k) {
            const glm::vec4& p = polygon[k];
            const glm::vec4& q = polygon[(k + 1) % polygon.size()];
            twiceArea += static_cast<double>(p.x / p.w) * (q.y / q.w) - static_cast<double>(q.x / q.w) * (p.y / p.w);
        }
        if (!std::isfinite(twiceArea)) continue;
        ndcArea += 0.5 * std::fabs(twiceArea);
        for (const glm::vec4& p : polygon) {
            const glm::vec2 ndc(p.x / p.w, p.y / p.w);
            bounds = glm::vec4(glm::min(glm::vec2(bounds), ndc), glm::max(glm::vec2(bounds.z, bounds.w), ndc));
        }
    }
    if (ndcBounds) *ndcBounds = bounds;
    // NDC spans 2 x 2 over the image.
    return ndcArea * 0.25 * static_cast<double>(pixels.x) * static_cast<double>(pixels.y);
}

}  // namespace aamap
