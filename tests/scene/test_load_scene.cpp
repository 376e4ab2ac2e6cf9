#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/load_scene.h"
#include "tests/common/temp_dir.h"

namespace aamap {
namespace {

TEST(LoadScene, BuiltinSpecs) {
    EXPECT_EQ(loadScene("builtin:cornell").name, "cornell");
    EXPECT_EQ(loadScene("builtin:spheres-plane").name, "spheres-plane");
    EXPECT_THROW(loadScene("builtin:nope"), InputError);
}

TEST(LoadScene, ObjWithSiblingViewFile) {
    test::TempDir dir;
    dir.write("room.vf", "rview -vtv -vp 0 0 5 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 30\n");
    const auto obj = dir.write("room.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Scene s = loadScene(obj.string());
    EXPECT_EQ(s.mesh.triangles.size(), 1u);
    EXPECT_EQ(s.source, obj);
    ASSERT_EQ(s.views.size(), 1u);
    EXPECT_EQ(s.views[0].name, "room:0");
    EXPECT_FLOAT_EQ(s.views[0].verticalFovDeg, 30.0f);
}

TEST(LoadScene, UnknownFormatAndMissingFile) {
    try {
        loadScene("scene.xyz");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("unsupported scene format '.xyz'"), std::string::npos);
    }
    EXPECT_THROW(loadScene("/nonexistent/dir/scene.obj"), InputError);
    EXPECT_THROW(loadScene("/nonexistent/dir/scene.gltf"), InputError);
}

}  // namespace
}  // namespace aamap
