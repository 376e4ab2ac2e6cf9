// Mutated input must give a Scene or an InputError, never a crash or another exception.
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/obj_loader.h"
#include "scene/view_file.h"
#include "mutate.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

std::string mutate(const std::string& text, std::mt19937& rng) {
    return test::mutate(text, rng, "0123456789 -+./\t\r\n#efvntgosl\\eE");
}

TEST(Robustness, MutatedObjAndMtl) {
    test::TempDir dir;
    const std::string obj =
        "mtllib m.mtl\no box\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n"
        "usemtl a\nf 1/1/1 2/2/1 3/1/1 4/2/1\ng lamp\nusemtl b\nf -4 -3 -2\nf 1//1 3//1 4//1\n";
    const std::string mtl = "newmtl a\nKd 0.5 0.5 0.5\nNs 10\nillum 5\nnewmtl b\nKe 1 2 3\nd 1\nmap_Kd x.png\n";
    std::mt19937 rng(12345);
    int loaded = 0, rejected = 0;
    for (int i = 0; i < 400; ++i) {
        dir.write("m.mtl", i % 2 ? mutate(mtl, rng) : mtl);
        const auto path = dir.write("m.obj", i % 2 ? obj : mutate(obj, rng));
        try {
            const Scene s = loadObj(path);
            for (const glm::uvec3& t : s.mesh.triangles) {
                ASSERT_LT(std::max({t.x, t.y, t.z}), s.mesh.positions.size());
            }
            ++loaded;
        } catch (const InputError&) {
            ++rejected;
        }
    }
    EXPECT_GT(loaded, 0);
    EXPECT_GT(rejected, 0);
}

// Every view a mutated line parses to is usable: a finite position, a unit direction and an up
// vector not parallel to it, fields of view in (0, 180) degrees, finite shifts; and the error of
// a rejected line names the file and line.
TEST(Robustness, MutatedViewLines) {
    const std::string line = "rview -vtv -vp 0 1 3.9 -vd 0 0 -1 -vu 0 1 0 -vh 39.3 -vv 39.3 -vs 0 -vl 0";
    std::mt19937 rng(777);
    int parsed = 0, rejected = 0;
    for (int i = 0; i < 2000; ++i) {
        try {
            for (const View& v : parseViewText(mutate(line, rng), "m.vf")) {
                for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(v.position[k]) && std::isfinite(v.direction[k]));
                ASSERT_NEAR(glm::length(v.direction), 1.0f, 1e-4f);
                ASSERT_LT(std::abs(glm::dot(glm::normalize(v.up), v.direction)), 1.0f - 1e-6f);
                ASSERT_TRUE(v.horizontalFovDeg > 0.0f && v.horizontalFovDeg < 180.0f) << v.horizontalFovDeg;
                ASSERT_TRUE(v.verticalFovDeg > 0.0f && v.verticalFovDeg < 180.0f) << v.verticalFovDeg;
                ASSERT_TRUE(std::isfinite(v.shiftX) && std::isfinite(v.shiftY));
                ++parsed;
            }
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("m.vf"), std::string::npos) << e.what();
            ++rejected;
        }
    }
    EXPECT_GT(parsed, 0);
    EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace aamap
