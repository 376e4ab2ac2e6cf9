// Embree's packet widths on incoherent rays, through the tracer's own BVH (EmbreeScene): the same
// rays traced one by one (rtcIntersect1) and as packets of 4, 8 and 16, on one thread. Rays leave
// uniformly chosen points of uniformly chosen triangles in uniform directions, as a path's bounce
// rays do in the limit of no coherence. Prints each width's time and rays per second per round.
//   bench_packets --scene SCENE [--rays 2097152] [--rounds 3]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <CLI/CLI.hpp>
#include <embree3/rtcore.h>
#include <fmt/format.h>

#include "core/error.h"
#include "scene/lights.h"
#include "scene/load_scene.h"
#include "tracer/embree_scene.h"

namespace {

struct Rays {
    std::vector<float> ox, oy, oz, dx, dy, dz;
};

Rays incoherentRays(const aamap::Scene& scene, int count) {
    const auto& m = scene.mesh;
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Rays r;
    for (int i = 0; i < count; ++i) {
        const auto t = m.triangles[std::min(m.triangles.size() - 1, static_cast<std::size_t>(u(rng) * m.triangles.size()))];
        float b1 = u(rng), b2 = u(rng);
        if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
        const glm::vec3 p = m.positions[t.x] + b1 * (m.positions[t.y] - m.positions[t.x]) + b2 * (m.positions[t.z] - m.positions[t.x]);
        const float z = 2.0f * u(rng) - 1.0f, phi = 2.0f * std::numbers::pi_v<float> * u(rng), s = std::sqrt(1.0f - z * z);
        r.ox.push_back(p.x), r.oy.push_back(p.y), r.oz.push_back(p.z);
        r.dx.push_back(s * std::cos(phi)), r.dy.push_back(s * std::sin(phi)), r.dz.push_back(z);
    }
    return r;
}

// Traces every ray in packets of W (W = 1: rtcIntersect1); returns the hits.
template <int W, class Packet, class Intersect>
long trace(RTCScene scene, const Rays& r, float tnear, Intersect intersect) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    alignas(64) int valid[W];
    for (int i = 0; i < W; ++i) valid[i] = -1;
    long hits = 0;
    const int n = static_cast<int>(r.ox.size()) / W * W;
    for (int first = 0; first < n; first += W) {
        Packet h{};
        for (int i = 0; i < W; ++i) {
            const int k = first + i;
            h.ray.org_x[i] = r.ox[k], h.ray.org_y[i] = r.oy[k], h.ray.org_z[i] = r.oz[k];
            h.ray.dir_x[i] = r.dx[k], h.ray.dir_y[i] = r.dy[k], h.ray.dir_z[i] = r.dz[k];
            h.ray.tnear[i] = tnear, h.ray.tfar[i] = INFINITY, h.ray.mask[i] = ~0u, h.ray.id[i] = static_cast<unsigned>(i);
            h.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID, h.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        }
        intersect(valid, scene, &context, &h);
        for (int i = 0; i < W; ++i) hits += h.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    }
    return hits;
}

long traceSingle(RTCScene scene, const Rays& r, float tnear) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    long hits = 0;
    for (std::size_t k = 0; k < r.ox.size(); ++k) {
        RTCRayHit h{};
        h.ray.org_x = r.ox[k], h.ray.org_y = r.oy[k], h.ray.org_z = r.oz[k];
        h.ray.dir_x = r.dx[k], h.ray.dir_y = r.dy[k], h.ray.dir_z = r.dz[k];
        h.ray.tnear = tnear, h.ray.tfar = INFINITY, h.ray.mask = ~0u;
        h.hit.geomID = RTC_INVALID_GEOMETRY_ID, h.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &h);
        hits += h.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    return hits;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Embree packet widths on incoherent rays through the tracer's BVH"};
    std::string sceneSpec;
    int count = 1 << 21, rounds = 3;
    app.add_option("--scene", sceneSpec, "scene file (OBJ, glTF, Mitsuba XML) or builtin:NAME")->required();
    app.add_option("--rays", count, "rays per width")->check(CLI::Range(16, 1 << 26));
    app.add_option("--rounds", rounds, "rounds, the widths interleaved in each")->check(CLI::Range(1, 100));
    CLI11_PARSE(app, argc, argv);
    try {
        const aamap::Scene scene = aamap::loadScene(sceneSpec);
        if (scene.mesh.triangles.empty()) throw aamap::InputError(sceneSpec, "the scene has no triangles");
        const aamap::EmbreeScene geometry(scene);
        const aamap::Bounds b = aamap::sceneBounds(scene);
        const float tnear = 1e-5f * glm::length(b.extent());  // off the surface the ray leaves
        const Rays rays = incoherentRays(scene, count);
        fmt::print("{}: {} triangles, {} incoherent rays, 1 thread\n", sceneSpec, scene.mesh.triangles.size(), count);
        for (int round = 1; round <= rounds; ++round) {
            std::string line = fmt::format("round {}:", round);
            const auto timed = [&](const char* label, auto&& run) {
                const auto t0 = std::chrono::steady_clock::now();
                const long hits = run();
                const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                line += fmt::format("  {} {:.0f} ms ({:.2f} M rays/s, {} hits)", label, 1e3 * s, count / s * 1e-6, hits);
            };
            const RTCScene s = geometry.handle();
            timed("1", [&] { return traceSingle(s, rays, tnear); });
            timed("4", [&] { return trace<4, RTCRayHit4>(s, rays, tnear, rtcIntersect4); });
            timed("8", [&] { return trace<8, RTCRayHit8>(s, rays, tnear, rtcIntersect8); });
            timed("16", [&] { return trace<16, RTCRayHit16>(s, rays, tnear, rtcIntersect16); });
            fmt::print("{}\n", line);
        }
    } catch (const std::exception& e) {
        fmt::print(stderr, "bench_packets: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
