// Mitsuba scene import: small scenes written here, checked against what the file says.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.h"
#include "scene/lights.h"
#include "scene/load_scene.h"
#include "scene/mitsuba_loader.h"
#include "scene/mitsuba_shapes.h"
#include "scene/mitsuba_xml.h"
#include "scene/spectrum.h"

namespace aamap {
namespace {
namespace fs = std::filesystem;

class Mitsuba : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("aamap_mitsuba_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    fs::path write(const std::string& name, const std::string& text) const {
        fs::create_directories((dir / name).parent_path());
        std::ofstream(dir / name, std::ios::binary) << text;
        return dir / name;
    }
    Scene load(const std::string& body, MitsubaLoadReport* report = nullptr, const std::string& version = "3.0.0") {
        return loadMitsuba(write("scene.xml", "<scene version=\"" + version + "\">\n" + body + "</scene>\n"), report);
    }
    // The InputError's message for a scene that must fail.
    std::string error(const std::string& body) {
        try {
            load(body);
        } catch (const InputError& e) {
            return e.what();
        }
        ADD_FAILURE() << "loaded; expected an InputError";
        return {};
    }
};

Bounds boundsOf(const Scene& s) { return sceneBounds(s); }

void expectVec(glm::vec3 a, glm::vec3 b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST_F(Mitsuba, SensorLookAtFovAxisAndFilm) {
    const Scene s = load(R"(<sensor type="perspective">
  <float name="fov" value="60"/>
  <string name="fov_axis" value="y"/>
  <transform name="to_world"><lookat origin="1, 2, 3" target="1, 2, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film>
</sensor>
)");
    ASSERT_EQ(s.views.size(), 1u);
    const View& v = s.views[0];
    expectVec(v.position, {1, 2, 3});
    expectVec(v.direction, {0, 0, -1});
    expectVec(v.up, {0, 1, 0});
    EXPECT_NEAR(v.verticalFovDeg, 60.0f, 1e-3f);
    // tan(h/2) = aspect * tan(v/2)
    EXPECT_NEAR(std::tan(glm::radians(v.horizontalFovDeg) / 2), 2.0f * std::tan(glm::radians(30.0f)), 1e-5f);
    EXPECT_EQ(s.imageWidth, 200);
    EXPECT_EQ(s.imageHeight, 100);
}

TEST_F(Mitsuba, Version05CamelCaseNamesAndDefaultFilm) {
    const Scene s = load(R"(<sensor type="perspective">
  <float name="fov" value="40"/>
  <string name="fovAxis" value="x"/>
  <transform name="toWorld"><translate x="0" y="0" z="-5"/></transform>
</sensor>
)", nullptr, "0.5.0");
    ASSERT_EQ(s.views.size(), 1u);
    expectVec(s.views[0].position, {0, 0, -5});
    expectVec(s.views[0].direction, {0, 0, 1});  // Mitsuba's cameras look down local +Z
    EXPECT_NEAR(s.views[0].horizontalFovDeg, 40.0f, 1e-3f);
    EXPECT_EQ(s.imageWidth, 768);  // Mitsuba's default film
    EXPECT_EQ(s.imageHeight, 576);
}

TEST_F(Mitsuba, IntegratorSamplerAndFilterSayHowTheFileRenders) {
    // Mitsuba 0.5 names, a path tracer inside an aov wrapper, the first sensor's sampler and filter.
    const Scene s = load(R"(<integrator type="aov">
  <integrator type="path"><integer name="maxDepth" value="65"/><integer name="rrDepth" value="12"/>
    <boolean name="hideEmitters" value="true"/></integrator>
</integrator>
<sensor type="perspective"><float name="fov" value="40"/>
  <sampler type="independent"><integer name="sampleCount" value="64"/></sampler>
  <film type="hdrfilm"><rfilter type="gaussian"/></film>
</sensor>
)", nullptr, "0.5.0");
    EXPECT_EQ(s.render.integrator, "path");
    EXPECT_EQ(s.render.maxDepth, 65);
    EXPECT_EQ(s.render.rrDepth, 12);
    EXPECT_TRUE(s.render.hideEmitters);
    EXPECT_EQ(s.render.sampleCount, 64);
    EXPECT_EQ(s.render.filter, "gaussian");
    EXPECT_NE(s.render.at.find("scene.xml:"), std::string::npos) << s.render.at;

    // Mitsuba's defaults: unlimited depth, roulette from 5; direct light is a path of two segments.
    const Scene unlimited = load("<integrator type=\"volpath\"/>\n");
    EXPECT_FALSE(unlimited.render.maxDepth.has_value());
    EXPECT_EQ(unlimited.render.rrDepth, 5);
    EXPECT_EQ(load("<integrator type=\"direct\"/>\n").render.maxDepth, 2);
    const Scene none = load("");
    EXPECT_TRUE(none.render.integrator.empty());
    EXPECT_FALSE(none.render.maxDepth.has_value());

    // Depths Mitsuba would refuse are errors naming the line.
    EXPECT_NE(error("<integrator type=\"path\"><integer name=\"max_depth\" value=\"0\"/></integrator>\n")
                  .find("max_depth 0"),
              std::string::npos);
    EXPECT_NE(error("<integrator type=\"path\"><integer name=\"rr_depth\" value=\"-2\"/></integrator>\n").find(":2"),
              std::string::npos);
}

TEST_F(Mitsuba, TransformsApplyInOrder) {
    // Scale by 2, then rotate 90 degrees about +Z, then translate: the rectangle [-1,1]^2 becomes
    // [-2,2]^2 around (10, 0, 0).
    const Scene s = load(R"(<shape type="rectangle">
  <transform name="to_world">
    <scale value="2"/>
    <rotate z="1" angle="90"/>
    <translate x="10"/>
  </transform>
</shape>
)");
    const Bounds b = boundsOf(s);
    expectVec(b.lo, {8, -2, 0}, 1e-4f);
    expectVec(b.hi, {12, 2, 0}, 1e-4f);
    ASSERT_EQ(s.mesh.triangles.size(), 2u);
    for (const glm::vec3& n : s.mesh.normals) expectVec(n, {0, 0, 1});
}

TEST_F(Mitsuba, MatrixIsRowMajorAndFlipNormalsTurnsTheFront) {
    const Scene s = load(R"(<shape type="rectangle">
  <transform name="to_world"><matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/></transform>
  <boolean name="flip_normals" value="true"/>
</shape>
)");
    expectVec(boundsOf(s).centre(), {5, 6, 7}, 1e-5f);
    expectVec(triangleNormal(s.mesh, 0), {0, 0, -1});
    for (const glm::vec3& n : s.mesh.normals) expectVec(n, {0, 0, -1});
}

TEST_F(Mitsuba, CubeIsClosedAndFacesOutwards) {
    const Scene s = load("<shape type=\"cube\"/>\n");
    ASSERT_EQ(s.mesh.triangles.size(), 12u);
    for (std::uint32_t t = 0; t < 12; ++t) {
        const glm::uvec3 tri = s.mesh.triangles[t];
        const glm::vec3 centroid = (s.mesh.positions[tri.x] + s.mesh.positions[tri.y] + s.mesh.positions[tri.z]) / 3.0f;
        EXPECT_GT(glm::dot(triangleNormal(s.mesh, t), centroid), 0.0f) << "triangle " << t;
        EXPECT_NEAR(triangleArea(s.mesh, t), 2.0f, 1e-5f);
    }
}

TEST_F(Mitsuba, SphereIsWithinTheStatedError) {
    const float r = 2.0f;
    const Scene s = load(R"(<shape type="sphere"><point name="center" x="1" y="2" z="3"/><float name="radius" value="2"/></shape>
)");
    ASSERT_GT(s.mesh.triangles.size(), 100u);
    const glm::vec3 c(1, 2, 3);
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) {
        const glm::uvec3 tri = s.mesh.triangles[t];
        const glm::vec3 a = s.mesh.positions[tri.x], b = s.mesh.positions[tri.y], d = s.mesh.positions[tri.z];
        for (const glm::vec3& p : {a, (a + b + d) / 3.0f, 0.5f * (a + b), 0.5f * (b + d)}) {
            const float dist = glm::length(p - c);
            ASSERT_LE(dist, r * (1 + 1e-5f));
            ASSERT_GE(dist, r * (1 - mitsuba::kTessellationError) - 1e-5f) << "triangle " << t;
        }
        ASSERT_GT(glm::dot(triangleNormal(s.mesh, t), (a + b + d) / 3.0f - c), 0.0f) << "faces inwards: " << t;
    }
}

TEST_F(Mitsuba, CylinderIsAnOpenTubeWithinTheStatedError) {
    // Axis from (1, 0, 0) to (1, 3, 0), radius 0.5, then moved by to_world: every vertex, edge
    // midpoint and centroid lies within the tessellation error of the tube, faces outwards, and
    // the ends are open (no point inside the radius at the caps).
    const Scene s = load(R"(<shape type="cylinder">
  <point name="p0" x="1" y="0" z="0"/><point name="p1" x="1" y="3" z="0"/><float name="radius" value="0.5"/>
  <transform name="to_world"><translate z="2"/></transform>
</shape>
)");
    ASSERT_GT(s.mesh.triangles.size(), 50u);
    const glm::vec3 p0(1, 0, 2);
    const glm::vec3 w(0, 1, 0);
    const float r = 0.5f;
    double area = 0.0;
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) {
        const glm::uvec3 tri = s.mesh.triangles[t];
        const glm::vec3 a = s.mesh.positions[tri.x], b = s.mesh.positions[tri.y], d = s.mesh.positions[tri.z];
        const glm::vec3 centroid = (a + b + d) / 3.0f;
        for (const glm::vec3& p : {a, centroid, 0.5f * (a + b), 0.5f * (b + d)}) {
            const glm::vec3 q = p - p0;
            const float along = glm::dot(q, w);
            const float dist = glm::length(q - along * w);
            ASSERT_GE(along, -1e-5f);
            ASSERT_LE(along, 3.0f + 1e-5f);
            ASSERT_LE(dist, r * (1 + 1e-5f));
            ASSERT_GE(dist, r * (1 - mitsuba::kTessellationError) - 1e-5f) << "triangle " << t;
        }
        const glm::vec3 q = centroid - p0;
        ASSERT_GT(glm::dot(triangleNormal(s.mesh, t), q - glm::dot(q, w) * w), 0.0f) << "faces inwards: " << t;
        area += triangleArea(s.mesh, t);
    }
    // The inscribed polygon's perimeter is within the error bound of the circle's.
    const double side = 2.0 * std::numbers::pi * r * 3.0;
    EXPECT_LE(area, side * (1 + 1e-5));
    EXPECT_GE(area, side * (1 - mitsuba::kTessellationError));
}

TEST_F(Mitsuba, CylinderWithCoincidentEndsIsAnError) {
    const std::string e = error(R"(<shape type="cylinder"><point name="p0" x="1" y="1" z="1"/><point name="p1" x="1" y="1" z="1"/></shape>
)");
    EXPECT_NE(e.find("coincide"), std::string::npos) << e;
    EXPECT_NE(e.find("scene.xml:2"), std::string::npos) << e;
}

TEST_F(Mitsuba, DiskKeepsItsAreaAndEmits) {
    const Scene s = load(R"(<shape type="disk">
  <transform name="to_world"><scale value="0.5"/></transform>
  <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter>
</shape>
)");
    ASSERT_EQ(s.areaLights.size(), 1u);
    EXPECT_NEAR(s.areaLights[0].area, std::numbers::pi_v<float> * 0.25f, 1e-4f);
    expectVec(s.areaLights[0].radiance, {1, 2, 3});
    for (std::uint32_t t = 0; t < s.mesh.triangles.size(); ++t) expectVec(triangleNormal(s.mesh, t), {0, 0, 1});
    const float sagitta = 1.0f - std::cos(std::numbers::pi_v<float> / mitsuba::circleSegments(mitsuba::kTessellationError));
    EXPECT_LE(sagitta, mitsuba::kTessellationError);
}

TEST_F(Mitsuba, IncludeDefaultsAndParameters) {
    write("parts/floor.xml", R"(<scene version="3.0.0">
  <shape type="rectangle"><transform name="to_world"><scale value="$size"/></transform></shape>
</scene>
)");
    const Scene s = load(R"(<default name="size" value="3"/>
<include filename="parts/floor.xml"/>
)");
    expectVec(boundsOf(s).hi, {3, 3, 0}, 1e-5f);
    // A given parameter wins over the default.
    const Scene t = loadMitsuba(dir / "scene.xml", nullptr, {{"size", "5"}});
    expectVec(boundsOf(t).hi, {5, 5, 0}, 1e-5f);
}

TEST_F(Mitsuba, ErrorsNameFileAndLine) {
    EXPECT_NE(error("<shape type=\"rectangle\">\n  <bsdf type=\"diffuse\">\n</shape>\n").find("scene.xml:4"),
              std::string::npos);  // malformed: the mismatched close tag on line 4
    EXPECT_NE(error("\n<shape type=\"teapot\"/>\n").find("scene.xml:3: unknown shape type 'teapot'"), std::string::npos);
    EXPECT_NE(error("<shape type=\"rectangle\">\n  <bsdf type=\"hair\"/>\n</shape>\n").find(":3: unknown BSDF type 'hair'"),
              std::string::npos);
    EXPECT_NE(error("<emitter type=\"sunsky\"/>\n").find(":2: unknown emitter type"), std::string::npos);
    EXPECT_NE(error("<include filename=\"nope.xml\"/>\n").find(":2: included file"), std::string::npos);
    EXPECT_NE(error("<shape type=\"obj\"><string name=\"filename\" value=\"m.obj\"/></shape>\n").find(":2: mesh file"),
              std::string::npos);
    EXPECT_NE(error("<shape type=\"sphere\"><float name=\"radius\" value=\"$r\"/></shape>\n").find("'$r' is not defined"),
              std::string::npos);
    write("a.xml", "<scene version=\"3.0.0\">\n<include filename=\"b.xml\"/>\n</scene>\n");
    write("b.xml", "<scene version=\"3.0.0\">\n\n<include filename=\"a.xml\"/>\n</scene>\n");
    const std::string cycle = error("<include filename=\"a.xml\"/>\n");
    EXPECT_NE(cycle.find("b.xml:3: include cycle"), std::string::npos) << cycle;
}

TEST_F(Mitsuba, MaterialsMapToTheNearestAndWarnOncePerKind) {
    MitsubaLoadReport report;
    const Scene s = load(R"(<bsdf type="roughplastic" id="p1"><float name="alpha" value="0.1"/></bsdf>
<bsdf type="roughplastic" id="p2"><float name="alpha" value="0.3"/></bsdf>
<shape type="rectangle"><ref id="p1"/></shape>
<shape type="rectangle"><ref id="p2"/></shape>
<shape type="rectangle"><bsdf type="conductor"><rgb name="eta" value="0.2"/><rgb name="k" value="3"/></bsdf></shape>
<shape type="rectangle"><bsdf type="twosided"><bsdf type="dielectric"><float name="int_ior" value="1.33"/></bsdf></bsdf></shape>
<shape type="rectangle"><bsdf type="mask"><float name="opacity" value="0.25"/><bsdf type="diffuse"/></bsdf></shape>
<shape type="rectangle"><bsdf type="bumpmap"><bsdf type="diffuse"><rgb name="reflectance" value="0.1, 0.2, 0.3"/></bsdf></bsdf></shape>
)", &report);
    ASSERT_EQ(s.materials.size(), 6u);
    const Material& p1 = s.materials[0];
    EXPECT_EQ(p1.kind, MaterialKind::Diffuse);
    expectVec(p1.kd, glm::vec3(0.5f));
    EXPECT_NEAR(p1.ns, 2.0f / 0.01f - 2.0f, 1e-2f);
    const float f0 = std::pow((1.49f / 1.000277f - 1) / (1.49f / 1.000277f + 1), 2.0f);
    EXPECT_NEAR(p1.ks.x, f0, 1e-4f);
    const Material& mirror = s.materials[2];
    EXPECT_EQ(mirror.kind, MaterialKind::Mirror);
    EXPECT_NEAR(mirror.ks.x, (0.64f + 9.0f) / (1.44f + 9.0f), 1e-4f);  // ((eta-1)^2 + k^2) / ((eta+1)^2 + k^2)
    EXPECT_EQ(s.materials[3].kind, MaterialKind::Glass);
    EXPECT_NEAR(s.materials[3].ior, 1.33f / 1.000277f, 1e-4f);
    EXPECT_EQ(s.materials[4].alphaMode, AlphaMode::Mask);
    EXPECT_NEAR(s.materials[4].alpha, 0.25f, 1e-6f);
    expectVec(s.materials[5].kd, {0.1f, 0.2f, 0.3f});
    // The tracer's models: Mitsuba's plastic and conductor with their parameters.
    EXPECT_EQ(p1.model, BsdfModel::Plastic);
    EXPECT_EQ(p1.distribution, MicrofacetType::Beckmann);
    EXPECT_EQ(p1.alphaU, 0.1f);
    EXPECT_EQ(s.materials[1].alphaV, 0.3f);
    EXPECT_NEAR(p1.ior, 1.49f / 1.000277f, 1e-5f);
    EXPECT_EQ(mirror.model, BsdfModel::Conductor);
    EXPECT_EQ(mirror.alphaU, 0.0f);
    expectVec(mirror.eta, glm::vec3(0.2f));
    expectVec(mirror.k, glm::vec3(3.0f));
    // Only the bumpmap without a texture warns.
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("bumpmap"), std::string::npos);
}

TEST_F(Mitsuba, MicrofacetBsdfsReadTheirParameters) {
    MitsubaLoadReport report;
    const Scene s = load(R"(<shape type="rectangle"><bsdf type="roughconductor"><string name="material" value="Au"/>
<string name="distribution" value="ggx"/><float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.4"/>
<rgb name="specular_reflectance" value="0.9"/><float name="colour" value="1"/></bsdf></shape>
<shape type="rectangle"><bsdf type="roughplastic"><string name="int_ior" value="bk7"/><float name="ext_ior" value="1"/>
<boolean name="nonlinear" value="true"/><float name="alpha" value="0.2"/></bsdf></shape>
<shape type="rectangle"><bsdf type="plastic"/></shape>
<shape type="rectangle"><bsdf type="roughconductor"/></shape>
<shape type="rectangle"><bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/>
<rgb name="specular_transmittance" value="0.9, 0.8, 0.7"/></bsdf></shape>
)", &report);
    ASSERT_EQ(s.materials.size(), 5u);
    const Material& glass = s.materials[4];
    EXPECT_EQ(glass.kind, MaterialKind::Glass);
    EXPECT_EQ(glass.model, BsdfModel::Dielectric);
    EXPECT_EQ(glass.distribution, MicrofacetType::GGX);
    EXPECT_EQ(glass.alphaU, 0.3f);
    EXPECT_NEAR(glass.ior, 1.5046f / 1.000277f, 1e-5f);  // bk7 in air, Mitsuba's defaults
    expectVec(glass.ks, {0.9f, 0.8f, 0.7f});
    const Material& gold = s.materials[0];
    EXPECT_EQ(gold.model, BsdfModel::Conductor);
    EXPECT_EQ(gold.distribution, MicrofacetType::GGX);
    EXPECT_EQ(gold.alphaU, 0.05f);
    EXPECT_EQ(gold.alphaV, 0.4f);
    expectVec(gold.specularReflectance, glm::vec3(0.9f));
    // Gold in RGB: its index is lowest in red (a weak eta, a strong k), so it reflects red most.
    EXPECT_LT(gold.eta.x, gold.eta.z);
    EXPECT_GT(gold.k.x, gold.k.z);
    const Material& p = s.materials[1];
    EXPECT_EQ(p.model, BsdfModel::Plastic);
    EXPECT_TRUE(p.nonlinear);
    EXPECT_NEAR(p.ior, 1.5046f, 1e-4f);
    EXPECT_EQ(s.materials[2].model, BsdfModel::Plastic);
    EXPECT_EQ(s.materials[2].alphaU, 0.0f);  // smooth
    // Mitsuba 3's default conductor is a perfect mirror (eta 0, k 1), Beckmann alpha 0.1.
    const Material& none = s.materials[3];
    expectVec(none.eta, glm::vec3(0.0f));
    expectVec(none.k, glm::vec3(1.0f));
    EXPECT_EQ(none.alphaU, 0.1f);
    EXPECT_EQ(none.distribution, MicrofacetType::Beckmann);
    // The unknown parameter is named with its file and line.
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("scene.xml:4"), std::string::npos) << report.warnings[0];  // <scene> is line 1
    EXPECT_NE(report.warnings[0].find("'colour'"), std::string::npos) << report.warnings[0];
}

TEST_F(Mitsuba, MicrofacetBsdfsRejectBadRoughnessAndIndices) {
    const auto expectError = [&](const std::string& bsdf, const std::string& what) {
        const std::string e = error("<shape type=\"rectangle\">" + bsdf + "</shape>\n");
        EXPECT_NE(e.find("scene.xml:"), std::string::npos) << e;
        EXPECT_NE(e.find(what), std::string::npos) << e;
    };
    expectError("<bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"-0.1\"/></bsdf>", "out of range");
    expectError("<bsdf type=\"roughplastic\"><float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>",
                "isotropic");
    expectError("<bsdf type=\"roughconductor\"><float name=\"alpha_u\" value=\"0.1\"/></bsdf>", "both");
    expectError("<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"phong\"/></bsdf>", "distribution");
    expectError("<bsdf type=\"plastic\"><float name=\"int_ior\" value=\"-1.5\"/></bsdf>", "positive");
    expectError("<bsdf type=\"conductor\"><string name=\"material\" value=\"Unobtainium\"/></bsdf>", "Unobtainium");
    expectError("<bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/><rgb name=\"eta\" value=\"1\"/></bsdf>",
                "either");
    expectError("<bsdf type=\"conductor\"><rgb name=\"k\" value=\"-1\"/></bsdf>", "out of range");
}

TEST_F(Mitsuba, ThinDielectricOneSidedRawBitmapAndRectangleUvAsMitsuba) {
    // One 8-bit texel of 128: its sRGB decode by default, 128 / 255 with raw=true (Mitsuba 3's bitmap).
    std::ofstream(dir / "grey.ppm", std::ios::binary) << "P6 1 1 255\n" << std::string(3, static_cast<char>(128));
    const Scene s = load(R"(<shape type="rectangle"><bsdf type="thindielectric"/></shape>
<shape type="rectangle"><bsdf type="dielectric"/></shape>
<shape type="rectangle"><bsdf type="diffuse"/></shape>
<shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>
<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="grey.ppm"/></texture></bsdf></shape>
<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="grey.ppm"/><boolean name="raw" value="true"/></texture></bsdf></shape>
)");
    ASSERT_EQ(s.materials.size(), 6u);
    EXPECT_EQ(s.materials[0].kind, MaterialKind::Glass);
    EXPECT_TRUE(s.materials[0].thin);
    EXPECT_FALSE(s.materials[1].thin);
    EXPECT_FALSE(s.materials[1].oneSided);     // dielectrics are two-sided
    EXPECT_TRUE(s.materials[2].oneSided);      // Mitsuba's diffuse is black from the back
    EXPECT_FALSE(s.materials[3].oneSided);     // ... unless twosided
    ASSERT_EQ(s.textures.size(), 2u);
    const float v = 128.0f / 255.0f;
    EXPECT_NEAR(s.textures[static_cast<std::size_t>(s.materials[4].diffuseTexture)].rgba[0],
                std::pow((v + 0.055f) / 1.055f, 2.4f), 1e-4f);
    EXPECT_NEAR(s.textures[static_cast<std::size_t>(s.materials[5].diffuseTexture)].rgba[0], v, 1e-6f);
    // Mitsuba's rectangle has uv = local (x, y) / 2 + 1/2, and its v = 0 is the image's top row as
    // aamap's is: local (-1, -1) shows the top-left texel, (1, 1) the bottom-right.
    ASSERT_EQ(s.mesh.uvs.size(), s.mesh.positions.size());
    int corners = 0;
    for (std::size_t i = 0; i < s.mesh.positions.size(); ++i) {
        const glm::vec3 p = s.mesh.positions[i];
        if (glm::length(p - glm::vec3(-1, -1, 0)) < 1e-6f) expectVec(glm::vec3(s.mesh.uvs[i], 0), {0, 0, 0}), ++corners;
        if (glm::length(p - glm::vec3(1, 1, 0)) < 1e-6f) expectVec(glm::vec3(s.mesh.uvs[i], 0), {1, 1, 0}), ++corners;
    }
    EXPECT_GT(corners, 0);
}

TEST_F(Mitsuba, EmittersOfEveryKind) {
    const Scene s = load(R"(<emitter type="point"><point name="position" x="1" y="2" z="3"/><rgb name="intensity" value="4"/></emitter>
<emitter type="spot">
  <transform name="to_world"><lookat origin="0, 5, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
  <float name="cutoff_angle" value="40"/><float name="beam_width" value="30"/>
</emitter>
<emitter type="directional"><vector name="direction" x="0" y="-2" z="0"/><rgb name="irradiance" value="3"/></emitter>
<emitter type="constant"><rgb name="radiance" value="0.5, 0.25, 1"/></emitter>
)");
    ASSERT_EQ(s.pointLights.size(), 2u);
    expectVec(s.pointLights[0].position, {1, 2, 3});
    expectVec(s.pointLights[0].intensity, glm::vec3(4.0f));
    expectVec(s.pointLights[1].spotDirection, {0, -1, 0});
    EXPECT_NEAR(s.pointLights[1].cosOuter, std::cos(glm::radians(40.0f)), 1e-6f);
    EXPECT_NEAR(s.pointLights[1].cosInner, std::cos(glm::radians(30.0f)), 1e-6f);
    ASSERT_EQ(s.directionalLights.size(), 1u);
    expectVec(s.directionalLights[0].direction, {0, -1, 0});
    expectVec(s.directionalLights[0].irradiance, glm::vec3(3.0f));
    ASSERT_TRUE(s.environment.has_value());
    EXPECT_TRUE(s.environment->map.empty());
    expectVec(s.environment->scale, {0.5f, 0.25f, 1.0f});
    EXPECT_NE(error("<emitter type=\"constant\"/>\n<emitter type=\"constant\"/>\n").find(":3: a second environment"),
              std::string::npos);
}

TEST_F(Mitsuba, EnvmapLoadsItsMapAndRotation) {
    // A 2 x 1 Radiance HDR: stb decodes it to linear floats.
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
    hdr += std::string("\x80\x80\x80\x81", 4) + std::string("\x80\x80\x80\x80", 4);  // (1,1,1) and (0.5,0.5,0.5)
    write("sky.hdr", hdr);
    const Scene s = load(R"(<emitter type="envmap">
  <string name="filename" value="sky.hdr"/><float name="scale" value="2"/>
  <transform name="to_world"><rotate y="1" angle="90"/></transform>
</emitter>
)");
    ASSERT_TRUE(s.environment.has_value());
    ASSERT_EQ(s.environment->mapWidth, 2);
    ASSERT_EQ(s.environment->map.size(), 2u);
    EXPECT_NEAR(s.environment->map[0].x, 1.0f, 1e-3f);
    expectVec(s.environment->scale, glm::vec3(2.0f));
    // toLocal undoes the rotation: to_world turns local +Z into world +X.
    const glm::vec3 localOfWorldX = s.environment->toLocal * glm::vec3(1, 0, 0);
    expectVec(localOfWorldX, {0, 0, 1}, 1e-5f);
}

TEST_F(Mitsuba, ShapegroupInstancesPlaceCopies) {
    const Scene s = load(R"(<shape type="shapegroup" id="g"><shape type="cube"/></shape>
<shape type="instance"><ref id="g"/><transform name="to_world"><translate x="-5"/></transform></shape>
<shape type="instance"><ref id="g"/><transform name="to_world"><translate x="5"/></transform></shape>
)");
    EXPECT_EQ(s.mesh.triangles.size(), 24u);
    expectVec(boundsOf(s).lo, {-6, -1, -1});
    expectVec(boundsOf(s).hi, {6, 1, 1});
}

TEST_F(Mitsuba, PlyAsciiAndBinaryThroughAssimp) {
    const std::string header = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                               "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    write("tri.ply", "ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    std::string binary = "ply\nformat binary_little_endian 1.0\n" + header;
    const float v[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
    binary.append(reinterpret_cast<const char*>(v), sizeof v);
    binary += '\x03';
    const int idx[3] = {0, 1, 2};
    binary.append(reinterpret_cast<const char*>(idx), sizeof idx);
    write("tri-bin.ply", binary);
    const Scene s = load(R"(<shape type="ply"><string name="filename" value="tri.ply"/></shape>
<shape type="ply"><string name="filename" value="tri-bin.ply"/></shape>
)");
    ASSERT_EQ(s.mesh.triangles.size(), 2u);
    EXPECT_NEAR(triangleArea(s.mesh, 0), 0.5f, 1e-6f);
    EXPECT_NEAR(triangleArea(s.mesh, 1), 2.0f, 1e-6f);
    expectVec(triangleNormal(s.mesh, 1), {0, 0, 1});
}

TEST_F(Mitsuba, BlendBsdfKeepsBothComponentsOrFallsBackWithAWarning) {
    MitsubaLoadReport report;
    const Scene s = load(R"(<shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="0.25"/>
  <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.4, 0.2"/></bsdf>
  <bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf></bsdf></shape>
<shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="0.75"/>
  <bsdf type="diffuse"/><bsdf type="conductor"/></bsdf></shape>
)",
                         &report);
    ASSERT_EQ(s.materials.size(), 2u);
    const Material& m = s.materials[0];
    EXPECT_EQ(m.model, BsdfModel::Blend);
    ASSERT_EQ(m.blend.size(), 2u);
    EXPECT_FLOAT_EQ(m.blendWeight, 0.25f);
    expectVec(m.blend[0].kd, {0.8f, 0.4f, 0.2f});
    EXPECT_EQ(m.blend[1].model, BsdfModel::Conductor);
    expectVec(m.kd, {0.6f, 0.3f, 0.15f});  // the Snapshot's mix (the conductor has no kd)
    // A smooth conductor has a delta lobe: the heavier component stands in, with a warning.
    EXPECT_EQ(s.materials[1].model, BsdfModel::Conductor);
    EXPECT_TRUE(s.materials[1].blend.empty());
    EXPECT_TRUE(std::any_of(report.warnings.begin(), report.warnings.end(),
                            [](const std::string& w) { return w.find("blendbsdf") != std::string::npos; }));
    EXPECT_NE(error(R"(<shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="1.5"/>
  <bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf></shape>
)").find("weight 1.5"),
              std::string::npos);
}

TEST_F(Mitsuba, NormalAndBumpMapsWrapTheirNestedBsdf) {
    std::ofstream(dir / "normal.ppm", std::ios::binary) << "P6 1 1 255\n" << std::string("\x80\x80\xff", 3);
    std::ofstream(dir / "height.ppm", std::ios::binary) << "P6 2 1 255\n" << std::string("\x00\x00\x00\xff\xff\xff", 6);
    MitsubaLoadReport report;
    const Scene s = load(R"(<bsdf type="diffuse" id="d"><rgb name="reflectance" value="0.2, 0.4, 0.6"/></bsdf>
<shape type="rectangle"><bsdf type="twosided"><bsdf type="normalmap">
  <texture name="normalmap" type="bitmap"><string name="filename" value="normal.ppm"/><boolean name="raw" value="true"/></texture>
  <bsdf type="roughplastic"/></bsdf></bsdf></shape>
<shape type="rectangle"><bsdf type="normalmap"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf>
  <texture name="normalmap" type="bitmap"><string name="filename" value="normal.ppm"/><boolean name="raw" value="true"/></texture></bsdf></shape>
<shape type="rectangle"><bsdf type="bumpmap"><float name="scale" value="0.5"/>
  <texture name="height" type="bitmap"><string name="filename" value="height.ppm"/><boolean name="raw" value="true"/></texture>
  <ref id="d"/></bsdf></shape>
)",
                         &report);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_EQ(s.materials.size(), 3u);
    const Material& outer = s.materials[0];
    EXPECT_EQ(outer.model, BsdfModel::Plastic);
    ASSERT_GE(outer.normalMap, 0);
    EXPECT_EQ(outer.bumpMap, -1);
    EXPECT_FALSE(outer.oneSided);
    EXPECT_TRUE(outer.mapMirroredOnBack);  // twosided outside the map
    // raw: the texel as stored, so 2 rgb - 1 is the tangent-space normal Mitsuba reads.
    const Texture& t = s.textures[static_cast<std::size_t>(outer.normalMap)];
    EXPECT_NEAR(t.rgba[0], 128.0f / 255.0f, 1e-6f);
    EXPECT_NEAR(t.rgba[2], 1.0f, 1e-6f);
    const Material& inner = s.materials[1];
    EXPECT_GE(inner.normalMap, 0);
    EXPECT_FALSE(inner.oneSided);
    EXPECT_FALSE(inner.mapMirroredOnBack);  // twosided inside the map
    const Material& bump = s.materials[2];
    EXPECT_GE(bump.bumpMap, 0);
    EXPECT_EQ(bump.normalMap, -1);
    EXPECT_FLOAT_EQ(bump.bumpScale, 0.5f);
    expectVec(bump.kd, {0.2f, 0.4f, 0.6f});
    EXPECT_TRUE(bump.oneSided);
}

TEST_F(Mitsuba, NormalAndBumpMapBadInputWarnsWithFileAndLine) {
    std::ofstream(dir / "normal.ppm", std::ios::binary) << "P6 1 1 255\n" << std::string("\x80\x80\xff", 3);
    MitsubaLoadReport report;
    const Scene s = load(R"(<shape type="rectangle"><bsdf type="normalmap"><bsdf type="diffuse"><rgb name="reflectance" value="0.3"/></bsdf></bsdf></shape>
<shape type="rectangle"><bsdf type="bumpmap"><texture type="bitmap"><string name="filename" value="normal.ppm"/></texture></bsdf></shape>
<shape type="rectangle"><bsdf type="bumpmap"><texture type="checkerboard"/><bsdf type="diffuse"/></bsdf></shape>
<shape type="rectangle"><bsdf type="normalmap"><texture name="normalmap" type="bitmap"><string name="filename" value="normal.ppm"/></texture><bsdf type="diffuse"/></bsdf></shape>
<shape type="rectangle"><bsdf type="normalmap"><texture name="normalmap" type="bitmap"><string name="filename" value="normal.ppm"/><boolean name="raw" value="true"/></texture>
  <bsdf type="bumpmap"><texture type="bitmap"><string name="filename" value="normal.ppm"/></texture><bsdf type="diffuse"/></bsdf></bsdf></shape>
)",
                         &report);
    ASSERT_EQ(s.materials.size(), 5u);
    const auto warned = [&](const std::string& where, const std::string& what) {
        return std::any_of(report.warnings.begin(), report.warnings.end(), [&](const std::string& w) {
            return w.find(where) != std::string::npos && w.find(what) != std::string::npos;
        });
    };
    // No texture: the nested BSDF alone.
    EXPECT_TRUE(warned("scene.xml:2:", "no nested <texture>; the nested BSDF is used without it"));
    EXPECT_EQ(s.materials[0].normalMap, -1);
    expectVec(s.materials[0].kd, glm::vec3(0.3f));
    // No BSDF: Mitsuba's default diffuse, with the map.
    EXPECT_TRUE(warned("scene.xml:3:", "no nested <bsdf>; Mitsuba's default"));
    expectVec(s.materials[1].kd, glm::vec3(0.5f));
    EXPECT_GE(s.materials[1].bumpMap, 0);
    // A texture that is not a bitmap: no map.
    EXPECT_TRUE(warned("scene.xml:4:", "checkerboard texture for bumpmap is not supported"));
    EXPECT_EQ(s.materials[2].bumpMap, -1);
    // A normal map decoded from sRGB is used as Mitsuba uses it, with a hint.
    EXPECT_TRUE(warned("scene.xml:5:", "raw=true"));
    EXPECT_GE(s.materials[3].normalMap, 0);
    // A map inside a map: the outer one alone.
    EXPECT_TRUE(warned("scene.xml:6:", "inside another one"));
    EXPECT_GE(s.materials[4].normalMap, 0);
    EXPECT_EQ(s.materials[4].bumpMap, -1);
}

TEST_F(Mitsuba, TexturedRoughnessReadsABitmapAndKeepsItsMean) {
    // Two texels, raw: alpha 0.2 and 0.6 (51 and 153 of 255), mean 0.4.
    std::ofstream(dir / "alpha.ppm", std::ios::binary) << "P6 2 1 255\n" << std::string("\x33\x33\x33\x99\x99\x99", 6);
    MitsubaLoadReport report;
    const Scene s = load(R"(<shape type="rectangle"><bsdf type="roughconductor">
  <texture name="alpha" type="bitmap"><string name="filename" value="alpha.ppm"/><boolean name="raw" value="true"/></texture></bsdf></shape>
<shape type="rectangle"><bsdf type="roughplastic">
  <texture name="alpha" type="bitmap"><string name="filename" value="alpha.ppm"/><boolean name="raw" value="true"/></texture></bsdf></shape>
<shape type="rectangle"><bsdf type="roughconductor"><float name="alpha_v" value="0.3"/>
  <texture name="alpha_u" type="bitmap"><string name="filename" value="alpha.ppm"/><boolean name="raw" value="true"/></texture></bsdf></shape>
<shape type="rectangle"><bsdf type="roughconductor"><texture name="alpha" type="checkerboard"/></bsdf></shape>
)",
                         &report);
    ASSERT_EQ(s.materials.size(), 4u);
    for (int i = 0; i < 2; ++i) {
        const Material& m = s.materials[static_cast<std::size_t>(i)];
        ASSERT_GE(m.roughnessTexture, 0);
        EXPECT_NEAR(m.alphaU, 0.4f, 1e-5f);  // the mean: the Snapshot's stand-in
        EXPECT_EQ(m.alphaV, m.alphaU);
        EXPECT_NEAR(s.textures[static_cast<std::size_t>(m.roughnessTexture)].rgba[0], 0.2f, 1e-6f);
    }
    // Anisotropic: the texture's mean on its axis, with a warning.
    EXPECT_EQ(s.materials[2].roughnessTexture, -1);
    EXPECT_NEAR(s.materials[2].alphaU, 0.4f, 1e-5f);
    EXPECT_FLOAT_EQ(s.materials[2].alphaV, 0.3f);
    // Not a bitmap: Mitsuba's default alpha.
    EXPECT_EQ(s.materials[3].roughnessTexture, -1);
    EXPECT_FLOAT_EQ(s.materials[3].alphaU, 0.1f);
    const auto warned = [&](const std::string& where, const std::string& what) {
        return std::any_of(report.warnings.begin(), report.warnings.end(), [&](const std::string& w) {
            return w.find(where) != std::string::npos && w.find(what) != std::string::npos;
        });
    };
    EXPECT_TRUE(warned("scene.xml:7:", "textured alpha_u is replaced by its mean"));
    EXPECT_TRUE(warned("scene.xml:8:", "only a bitmap texture can give the roughness"));
    EXPECT_TRUE(warned("scene.xml:5:", "Mitsuba 3 takes no texture for roughplastic's alpha"));
    EXPECT_EQ(report.warnings.size(), 3u);
}

TEST_F(Mitsuba, LoadSceneDispatchesXml) {
    const fs::path file = write("room.xml", "<scene version=\"2.1.0\"><shape type=\"cube\"/></scene>");
    EXPECT_EQ(loadScene(file.string()).mesh.triangles.size(), 12u);
}

TEST(Spectrum, BandsLandInTheirChannels) {
    const glm::vec3 red = spectrumToRgb({{400, 0}, {590, 0}, {600, 1}, {700, 1}});
    EXPECT_GT(red.r, 3.0f * red.g);
    EXPECT_GT(red.r, 3.0f * red.b);
    const glm::vec3 blue = spectrumToRgb({{400, 1}, {480, 1}, {490, 0}, {700, 0}});
    EXPECT_GT(blue.b, 3.0f * blue.r);
}

// Reflectances read as Mitsuba 3's RGB modes read them (under D65, nothing outside the samples, no
// per-channel rescaling): the values mi.traverse gives in scalar_rgb for the Cornell box's
// measured wall spectra (400-700 nm, 4 nm steps) and a constant 0.78 over 400-700 nm, each
// channel within 1 % of the colour's largest (the colour-matching fit's error). Rescaling per
// channel, as a white-preserving projection would, puts the green wall's red 29 % high and the
// red wall 4 % low.
TEST(Spectrum, ReflectanceReadsAsMitsubaReadsIt) {
    const auto check = [](const std::vector<std::pair<double, double>>& samples, glm::vec3 mitsuba) {
        const glm::vec3 ours = spectrumToRgb(samples);
        const float tolerance = 0.01f * std::max({mitsuba.r, mitsuba.g, mitsuba.b});
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(ours[c], mitsuba[c], tolerance) << "channel " << c;
    };
    // The measured spectra, 400-700 nm in 4 nm steps.
    const auto every4nm = [](std::vector<double> values) {
        std::vector<std::pair<double, double>> samples;
        for (std::size_t i = 0; i < values.size(); ++i) samples.emplace_back(400.0 + 4.0 * static_cast<double>(i), values[i]);
        return samples;
    };
    check(every4nm({0.04, 0.046, 0.048, 0.053, 0.049, 0.05, 0.053, 0.055, 0.057, 0.056, 0.059, 0.057, 0.061,
                 0.061, 0.06, 0.062, 0.062, 0.062, 0.061, 0.062, 0.06, 0.059, 0.057, 0.058, 0.058, 0.058,
                 0.056, 0.055, 0.056, 0.059, 0.057, 0.055, 0.059, 0.059, 0.058, 0.059, 0.061, 0.061, 0.063,
                 0.063, 0.067, 0.068, 0.072, 0.08, 0.09, 0.099, 0.124, 0.154, 0.192, 0.255, 0.287, 0.349,
                 0.402, 0.443, 0.487, 0.513, 0.558, 0.584, 0.62, 0.606, 0.609, 0.651, 0.612, 0.61, 0.65,
                 0.638, 0.627, 0.62, 0.63, 0.628, 0.642, 0.639, 0.657, 0.639, 0.635, 0.642}),
          {0.49132f, 0.0492281f, 0.0509219f});
    check(every4nm({0.092, 0.096, 0.098, 0.097, 0.098, 0.095, 0.095, 0.097, 0.095, 0.094, 0.097, 0.098, 0.096,
                 0.101, 0.103, 0.104, 0.107, 0.109, 0.112, 0.115, 0.125, 0.14, 0.16, 0.187, 0.229, 0.285,
                 0.343, 0.39, 0.435, 0.464, 0.472, 0.476, 0.481, 0.462, 0.447, 0.441, 0.426, 0.406, 0.373,
                 0.347, 0.337, 0.314, 0.285, 0.277, 0.266, 0.25, 0.23, 0.207, 0.186, 0.171, 0.16, 0.148,
                 0.141, 0.136, 0.13, 0.126, 0.123, 0.121, 0.122, 0.119, 0.114, 0.115, 0.117, 0.117, 0.118,
                 0.12, 0.122, 0.128, 0.132, 0.139, 0.144, 0.146, 0.15, 0.152, 0.157, 0.159}),
          {0.0682825f, 0.39776f, 0.0862909f});
    check({{400, 0.78}, {700, 0.78}}, {0.776367f, 0.77981f, 0.776029f});
    // Over the whole visible range a constant is grey (D65 is the sRGB white), and a reflectance
    // never leaves [0, 1].
    const glm::vec3 one = spectrumToRgb({{360, 1}, {830, 1}});
    expectVec(one, glm::vec3(1.0f), 0.01f);
    const glm::vec3 spike = spectrumToRgb({{500, 0}, {520, 40}, {540, 0}});
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(spike[c], 0.0f);
        EXPECT_LE(spike[c], 1.0f);
    }
    // A conductor's k is no reflectance: read the same way, but not clamped at 1.
    expectVec(spectrumToRgb({{360, 3}, {830, 3}}, SpectrumUse::Unbounded), glm::vec3(3.0f), 0.03f);
}

// Emission is absolute, as a spectral render shows it on an sRGB display: equal energy is not grey
// but (1.20, 0.95, 0.91), and the values Mitsuba 3's own RGB modes read from the same spectra
// (mi.traverse of an area emitter in scalar_rgb) are met within the colour-matching fit's error.
TEST(Spectrum, EmissionIsAbsoluteAsMitsubaReadsIt) {
    expectVec(spectrumToRgb({{360, 1}, {830, 1}}, SpectrumUse::Emission), glm::vec3(1.20488f, 0.948228f, 0.909267f), 0.02f);
    const glm::vec3 light = spectrumToRgb({{400, 0}, {500, 8}, {600, 15.6}, {700, 18.4}}, SpectrumUse::Emission);
    EXPECT_NEAR(light.r / 20.7108f, 1.0f, 0.02f) << light.r;
    EXPECT_NEAR(light.g / 10.8546f, 1.0f, 0.02f) << light.g;
    EXPECT_NEAR(light.b / 2.77115f, 1.0f, 0.02f) << light.b;
    // Nothing outside the samples: luminance (Y) is linear in the spectrum, so a band carries only
    // its share of the equal-energy Y of 1.
    const auto luminance = [](glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
    EXPECT_NEAR(luminance(spectrumToRgb({{360, 1}, {830, 1}}, SpectrumUse::Emission)), 1.0f, 1e-3f);
    const float band = luminance(spectrumToRgb({{500, 1}, {600, 1}}, SpectrumUse::Emission));
    EXPECT_GT(band, 0.5f);
    EXPECT_LT(band, 0.95f);
}

TEST(MitsubaXml, SnakeCase) {
    EXPECT_EQ(mitsuba::snakeCase("toWorld"), "to_world");
    EXPECT_EQ(mitsuba::snakeCase("intIOR"), "int_ior");
    EXPECT_EQ(mitsuba::snakeCase("fov_axis"), "fov_axis");
    EXPECT_EQ(mitsuba::snakeCase("diffuseReflectance"), "diffuse_reflectance");
}

}  // namespace
}  // namespace aamap
