#pragma once
// Builds small scenes in code for the tracer's tests and benchmark (no loaders involved).
// Quads are (p0, p0 + a, p0 + a + b, p0 + b); their front side faces cross(a, b).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include "scene/scene.h"
#include "tracer/tracer.h"

namespace aamap::testing {

class SceneBuilder {
public:
    std::uint32_t material(const std::string& name, glm::vec3 kd, glm::vec3 ke = glm::vec3(0.0f)) {
        Material m;
        m.name = name;
        m.kd = kd;
        m.ke = ke;
        scene_.materials.push_back(m);
        return static_cast<std::uint32_t>(scene_.materials.size() - 1);
    }

    // Returns the indices of its two triangles.
    std::vector<std::uint32_t> quad(glm::vec3 p0, glm::vec3 a, glm::vec3 b, std::uint32_t material) {
        TriangleMesh& m = scene_.mesh;
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        const glm::vec3 n = glm::normalize(glm::cross(a, b));
        for (const glm::vec3& p : {p0, p0 + a, p0 + a + b, p0 + b}) {
            m.positions.push_back(p);
            m.normals.push_back(n);
        }
        const auto t0 = static_cast<std::uint32_t>(m.triangles.size());
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
        for (int i = 0; i < 2; ++i) {
            m.materialIds.push_back(material);
            m.objectIds.push_back(nextObject_);
        }
        ++nextObject_;
        return {t0, t0 + 1};
    }

    // Axis-aligned box with outward-facing sides.
    void box(glm::vec3 lo, glm::vec3 hi, std::uint32_t material) {
        const glm::vec3 d = hi - lo;
        const glm::vec3 X(d.x, 0, 0), Y(0, d.y, 0), Z(0, 0, d.z);
        quad(lo, Y, X, material);                // -z
        quad(lo + Z, X, Y, material);            // +z
        quad(lo, Z, Y, material);                // -x
        quad(lo + X, Y, Z, material);            // +x
        quad(lo, X, Z, material);                // -y
        quad(lo + Y, Z, X, material);            // +y
    }

    // An emissive quad registered as an area light (front side emits).
    void areaLightQuad(glm::vec3 p0, glm::vec3 a, glm::vec3 b, glm::vec3 radiance, glm::vec3 kd = glm::vec3(0.0f)) {
        const std::uint32_t mat = material("light" + std::to_string(scene_.areaLights.size()), kd, radiance);
        AreaLight light;
        light.name = scene_.materials[mat].name;
        light.triangles = quad(p0, a, b, mat);
        light.radiance = radiance;
        light.area = glm::length(glm::cross(a, b));
        scene_.areaLights.push_back(light);
    }

    void pointLight(glm::vec3 position, glm::vec3 intensity, glm::vec3 normal = glm::vec3(0.0f)) {
        PointLight p;
        p.name = "point" + std::to_string(scene_.pointLights.size());
        p.position = position;
        p.intensity = intensity;
        p.normal = normal;
        scene_.pointLights.push_back(p);
    }

    Scene& scene() { return scene_; }

private:
    Scene scene_;
    std::uint32_t nextObject_ = 0;
};

// A Cornell-box-like room (side 2, floor at y = 0, open at +z), two boxes and a ceiling quad light,
// with a view from the open side.
inline Scene cornellLikeScene() {
    SceneBuilder b;
    const auto white = b.material("white", glm::vec3(0.73f));
    const auto red = b.material("red", glm::vec3(0.65f, 0.05f, 0.05f));
    const auto green = b.material("green", glm::vec3(0.12f, 0.45f, 0.15f));
    const glm::vec3 X(2, 0, 0), Y(0, 2, 0), Z(0, 0, 2), o(-1, 0, -1);
    b.quad(o, Z, X, white);           // floor, faces +y
    b.quad(o + Y, X, Z, white);       // ceiling, faces -y
    b.quad(o, X, Y, white);           // back wall, faces +z
    b.quad(o, Y, Z, red);             // left wall, faces +x
    b.quad(o + X, Z, Y, green);       // right wall, faces -x
    b.box({-0.65f, 0.0f, -0.55f}, {-0.05f, 1.2f, 0.05f}, white);  // tall box
    b.box({0.1f, 0.0f, -0.1f}, {0.7f, 0.6f, 0.5f}, white);        // short box
    // Light just below the ceiling, facing down (cross(+x, +z) = -y).
    b.areaLightQuad({-0.25f, 1.999f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, glm::vec3(17.0f, 12.0f, 4.0f));
    Scene scene = std::move(b.scene());
    scene.name = "cornell-like";
    View view;
    view.name = "front";
    view.position = {0.0f, 1.0f, 3.9f};
    view.direction = {0.0f, 0.0f, -1.0f};
    view.horizontalFovDeg = view.verticalFovDeg = 39.3f;
    scene.views.push_back(view);
    return scene;
}

// One Cornell-like scene and tracer shared by all tests of a suite (the BVH is built once).
// Derive a suite-named fixture: class MySuite : public testing::CornellTracerTest {};
class CornellTracerTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        scene_ = new Scene(cornellLikeScene());
        tracer_ = new Tracer(*scene_);
    }
    static void TearDownTestSuite() {
        delete tracer_;
        delete scene_;
        tracer_ = nullptr;
        scene_ = nullptr;
    }
    static const View& view() { return scene_->views.front(); }
    static inline Scene* scene_ = nullptr;
    static inline Tracer* tracer_ = nullptr;
};

}  // namespace aamap::testing
