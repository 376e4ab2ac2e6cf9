#include "scene/builtin_scenes.h"

#include <array>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "scene/lights.h"

namespace aamap {
namespace {

using Quad = std::array<glm::vec3, 4>;

// Flat-shaded quad as two triangles with their own vertices. The winding is flipped if needed so
// that the geometric normal points towards `reference` (facingReference) or away from it.
void addQuad(Scene& scene, Quad q, glm::vec3 reference, bool facingReference, std::uint32_t material,
             std::uint32_t object) {
    const glm::vec3 centre = 0.25f * (q[0] + q[1] + q[2] + q[3]);
    const glm::vec3 n = glm::cross(q[1] - q[0], q[2] - q[0]) + glm::cross(q[2] - q[0], q[3] - q[0]);
    if ((glm::dot(n, reference - centre) > 0.0f) != facingReference) std::swap(q[1], q[3]);
    TriangleMesh& mesh = scene.mesh;
    for (const auto& tri : {std::array{0, 1, 2}, std::array{0, 2, 3}}) {
        const glm::vec3 a = q[tri[0]], b = q[tri[1]], c = q[tri[2]];
        const glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        for (const glm::vec3& p : {a, b, c}) {
            mesh.positions.push_back(p);
            mesh.normals.push_back(normal);
        }
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.materialIds.push_back(material);
        mesh.objectIds.push_back(object);
    }
}

// The published data is in millimetres; the scene is in metres.
Quad mm(std::array<float, 12> v) {
    Quad q;
    for (int i = 0; i < 4; ++i) q[i] = glm::vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]) / 1000.0f;
    return q;
}

Scene cornellBox() {
    Scene scene;
    scene.name = "cornell";
    // RGB approximations of the measured reflectance spectra.
    scene.materials = {
        {.name = "white", .kd = glm::vec3(0.74f)},
        {.name = "red", .kd = {0.63f, 0.065f, 0.05f}},
        {.name = "green", .kd = {0.14f, 0.45f, 0.09f}},
        // Light: a neutral white with radiance Le = 57 W/(sr m^2). Why 57: the floor point under
        // the centre of the 0.130 m x 0.105 m light, h = 0.5483 m below it, receives
        // E = pi * Le * F, with F the form factor to a parallel rectangle seen from below its centre
        // (4 corner rectangles of 0.065 x 0.0525: F = 4 * 0.003558 = 0.014232), so E = 0.04471 Le.
        // A Lambertian floor with albedo 0.74 then has radiance 0.74 / pi * 0.04471 * 57 = 0.600
        // from direct light alone: mid-grey at exposure 1.
        {.name = "light", .kd = glm::vec3(0.78f), .ke = glm::vec3(57.0f)},
    };
    enum : std::uint32_t { White, Red, Green, Light };
    const std::vector<std::string> names = {"floor", "ceiling", "backWall", "leftWall", "rightWall",
                                            "shortBlock", "tallBlock", "light"};
    const glm::vec3 inside = glm::vec3(278.0f, 274.4f, 279.6f) / 1000.0f;  // the middle of the room

    // Walls face the inside of the room (wall and vertex order as published).
    addQuad(scene, mm({552.8f, 0, 0, 0, 0, 0, 0, 0, 559.2f, 549.6f, 0, 559.2f}), inside, true, White, 0);
    addQuad(scene, mm({556, 548.8f, 0, 556, 548.8f, 559.2f, 0, 548.8f, 559.2f, 0, 548.8f, 0}), inside, true, White, 1);
    addQuad(scene, mm({549.6f, 0, 559.2f, 0, 0, 559.2f, 0, 548.8f, 559.2f, 556, 548.8f, 559.2f}), inside, true, White, 2);
    addQuad(scene, mm({552.8f, 0, 0, 549.6f, 0, 559.2f, 556, 548.8f, 559.2f, 556, 548.8f, 0}), inside, true, Red, 3);
    addQuad(scene, mm({0, 0, 559.2f, 0, 0, 0, 0, 548.8f, 0, 0, 548.8f, 559.2f}), inside, true, Green, 4);

    // Blocks face away from their own centres (tops and four sides; the bottoms rest on the floor).
    const std::array<std::array<float, 12>, 5> shortBlock = {{
        {130, 165, 65, 82, 165, 225, 240, 165, 272, 290, 165, 114},
        {290, 0, 114, 290, 165, 114, 240, 165, 272, 240, 0, 272},
        {130, 0, 65, 130, 165, 65, 290, 165, 114, 290, 0, 114},
        {82, 0, 225, 82, 165, 225, 130, 165, 65, 130, 0, 65},
        {240, 0, 272, 240, 165, 272, 82, 165, 225, 82, 0, 225},
    }};
    const std::array<std::array<float, 12>, 5> tallBlock = {{
        {423, 330, 247, 265, 330, 296, 314, 330, 456, 472, 330, 406},
        {423, 0, 247, 423, 330, 247, 472, 330, 406, 472, 0, 406},
        {472, 0, 406, 472, 330, 406, 314, 330, 456, 314, 0, 456},
        {314, 0, 456, 314, 330, 456, 265, 330, 296, 265, 0, 296},
        {265, 0, 296, 265, 330, 296, 423, 330, 247, 423, 0, 247},
    }};
    const glm::vec3 shortCentre = glm::vec3(185.5f, 82.5f, 168.5f) / 1000.0f;
    const glm::vec3 tallCentre = glm::vec3(368.5f, 165.0f, 351.5f) / 1000.0f;
    for (const auto& face : shortBlock) addQuad(scene, mm(face), shortCentre, false, White, 5);
    for (const auto& face : tallBlock) addQuad(scene, mm(face), tallCentre, false, White, 6);

    // The light is published at the ceiling's height (548.8 mm); it sits 0.5 mm lower so that the
    // two never fight for depth in the raster or for the first hit in the tracer. Faces down.
    addQuad(scene, mm({343, 548.3f, 227, 343, 548.3f, 332, 213, 548.3f, 332, 213, 548.3f, 227}),
            glm::vec3(0.278f, 0.0f, 0.2795f), true, Light, 7);
    scene.areaLights = buildAreaLights(scene, names);
    scene.areaLights.at(0).name = "light";

    // The published camera: 35 mm lens, 25 mm x 25 mm film -> fov = 2 atan(12.5 / 35) = 39.31 deg.
    View view;
    view.name = "cornell:camera";
    view.position = glm::vec3(278.0f, 273.0f, -800.0f) / 1000.0f;
    view.direction = {0, 0, 1};
    view.up = {0, 1, 0};
    view.horizontalFovDeg = view.verticalFovDeg = glm::degrees(2.0f * std::atan(12.5f / 35.0f));
    scene.views.push_back(view);
    return scene;
}

void addSphere(Scene& scene, glm::vec3 centre, float radius, std::uint32_t material, std::uint32_t object) {
    constexpr int kRings = 24, kSegments = 48;
    TriangleMesh& mesh = scene.mesh;
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (int r = 0; r <= kRings; ++r) {
        const float theta = std::numbers::pi_v<float> * static_cast<float>(r) / kRings;
        for (int s = 0; s <= kSegments; ++s) {
            const float phi = 2.0f * std::numbers::pi_v<float> * static_cast<float>(s) / kSegments;
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
            mesh.positions.push_back(centre + radius * n);
            mesh.normals.push_back(n);
        }
    }
    const auto at = [&](int r, int s) { return base + static_cast<std::uint32_t>(r * (kSegments + 1) + s); };
    for (int r = 0; r < kRings; ++r) {
        for (int s = 0; s < kSegments; ++s) {
            // Counter-clockwise seen from outside; the pole rows lose their zero-area halves.
            if (r != 0) mesh.triangles.push_back({at(r, s), at(r + 1, s), at(r, s + 1)});
            if (r != kRings - 1) mesh.triangles.push_back({at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
            for (int k = (r != 0) + (r != kRings - 1); k > 0; --k) {
                mesh.materialIds.push_back(material);
                mesh.objectIds.push_back(object);
            }
        }
    }
}

Scene spheresPlane() {
    Scene scene;
    scene.name = "spheres-plane";
    scene.materials = {
        {.name = "floor", .kd = glm::vec3(0.74f)},
        {.name = "red", .kd = {0.63f, 0.065f, 0.05f}},
        {.name = "mirror", .kind = MaterialKind::Mirror, .kd = glm::vec3(0.0f), .ks = glm::vec3(0.9f)},
        {.name = "glass", .kind = MaterialKind::Glass, .kd = glm::vec3(0.0f), .ks = glm::vec3(1.0f), .ior = 1.5f},
        // 1 m x 1 m light 3 m above the floor: E = pi * Le * 4 F(0.5, 0.5, 3) = 0.10715 Le, so
        // Le = 23.8 gives the floor under it 0.74 / pi * 0.10715 * 23.8 = 0.60, as in "cornell".
        {.name = "light", .kd = glm::vec3(0.78f), .ke = glm::vec3(23.8f)},
    };
    const glm::vec3 above(0.0f, 10.0f, 0.0f);
    addQuad(scene, {glm::vec3(-4, 0, -4), glm::vec3(4, 0, -4), glm::vec3(4, 0, 4), glm::vec3(-4, 0, 4)}, above, true, 0, 0);
    addSphere(scene, {-1.2f, 0.5f, 0.0f}, 0.5f, 1, 1);
    addSphere(scene, {0.0f, 0.5f, -0.3f}, 0.5f, 2, 2);
    addSphere(scene, {1.2f, 0.5f, 0.0f}, 0.5f, 3, 3);
    addQuad(scene, {glm::vec3(-0.5f, 3, -0.5f), glm::vec3(0.5f, 3, -0.5f), glm::vec3(0.5f, 3, 0.5f), glm::vec3(-0.5f, 3, 0.5f)},
            glm::vec3(0.0f), true, 4, 4);
    const std::vector<std::string> names = {"floor", "diffuseSphere", "mirrorSphere", "glassSphere", "light"};
    scene.areaLights = buildAreaLights(scene, names);
    scene.areaLights.at(0).name = "light";

    View view;
    view.name = "spheres-plane:camera";
    view.position = {0.0f, 1.6f, 4.5f};
    view.direction = glm::normalize(glm::vec3(0.0f, 0.4f, 0.0f) - view.position);
    view.up = {0, 1, 0};
    view.horizontalFovDeg = 50.0f;
    view.verticalFovDeg = glm::degrees(2.0f * std::atan(std::tan(glm::radians(25.0f)) * 0.75f));  // 4:3
    scene.views.push_back(view);
    return scene;
}

}  // namespace

std::vector<std::string> builtinSceneNames() { return {"cornell", "spheres-plane"}; }

Scene builtinScene(std::string_view name) {
    if (name == "cornell") return cornellBox();
    if (name == "spheres-plane") return spheresPlane();
    throw InputError(fmt::format("builtin:{}", name),
                     fmt::format("unknown built-in scene '{}' (known: {})", name, fmt::join(builtinSceneNames(), ", ")));
}

}  // namespace aamap
