// Every file in tests/corpus/<parser>/ through its loader. The file name states the outcome:
//   err-*   a one-line InputError that names a file of the corpus (the input or the file it refers
//           to), and no other exception;
//   warn-*  a Scene (or texture) with at least one warning logged, e.g. skipped degenerate triangles;
//   ok-*    success without warnings;
//   lib-*   not run on its own: referred to by another file (an MTL, a texture);
//   mem-*   valid, but over the memory limit kMemLimit: an EnvironmentError from the estimate
//           (core/memory_budget.h) naming the file, the estimate and the limit; loads without it.
// Whatever loads must be usable: finite positions and normals, in-range indices, finite lights.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.h"
#include "eval/config.h"
#include "eval/light_list.h"
#include "scene/gltf_loader.h"
#include "scene/light_file.h"
#include "scene/mitsuba_loader.h"
#include "scene/obj_loader.h"
#include "scene/texture_loader.h"
#include "scene/view_file.h"
#include "warning_counter.h"

namespace aamap {
namespace {
namespace fs = std::filesystem;

const fs::path kCorpus = AAMAP_CORPUS_DIR;

struct CorpusFile {
    std::string parser;  // folder name
    fs::path path;
};

void PrintTo(const CorpusFile& file, std::ostream* out) { *out << file.path; }

std::vector<CorpusFile> corpusFiles() {
    std::vector<CorpusFile> files;
    for (const auto& dir : fs::directory_iterator(kCorpus)) {
        if (!dir.is_directory()) continue;
        for (const auto& entry : fs::directory_iterator(dir.path())) {
            const std::string name = entry.path().filename().string();
            if (name.starts_with("err-") || name.starts_with("warn-") || name.starts_with("ok-")) {
                files.push_back({dir.path().filename().string(), entry.path()});
            }
        }
    }
    std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
    return files;
}

// A scratch folder for the OBJ that reaches an MTL or a texture of the corpus.
struct Scratch {
    fs::path dir = fs::temp_directory_path() / ("aamap_corpus_" + std::to_string(::getpid()));
    Scratch() { fs::create_directories(dir); }
    ~Scratch() { std::error_code ec; fs::remove_all(dir, ec); }
    fs::path write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name, std::ios::binary) << text;
        return dir / name;
    }
};

void expectUsable(const Scene& scene) {
    const TriangleMesh& mesh = scene.mesh;
    for (const glm::vec3& p : mesh.positions) ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    for (const glm::vec3& n : mesh.normals) ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    for (const glm::uvec3& t : mesh.triangles) ASSERT_LT(std::max({t.x, t.y, t.z}), mesh.positions.size());
    for (const AreaLight& light : scene.areaLights) {
        ASSERT_TRUE(std::isfinite(light.area) && light.area > 0.0f) << light.name;
        ASSERT_TRUE(std::isfinite(light.radiance.x + light.radiance.y + light.radiance.z)) << light.name;
    }
}

// Loads one corpus file the way a user's run would reach it.
void load(const CorpusFile& file, const Scratch& scratch) {
    const std::string abs = fs::absolute(file.path).string();
    if (file.parser == "obj") {
        expectUsable(loadObj(file.path));
    } else if (file.parser == "mtl") {
        expectUsable(loadObj(scratch.write("uses.obj", "mtllib " + abs + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n")));
    } else if (file.parser == "gltf" || file.parser == "glb") {
        expectUsable(loadGltf(file.path));
    } else if (file.parser == "mitsuba") {
        expectUsable(loadMitsuba(file.path));
    } else if (file.parser == "view") {
        const auto views = loadViewFile(file.path);
        ASSERT_FALSE(views.empty());
    } else if (file.parser == "config") {
        loadConfig(file.path);
    } else if (file.parser == "light") {
        Scene scene;
        addLights(scene, loadLightFile(file.path));
        expectUsable(scene);
    } else if (file.parser == "texture") {
        std::string error;
        const auto texture = loadTexture(file.path, &error);
        if (texture) {
            ASSERT_EQ(texture->rgba.size(), static_cast<std::size_t>(texture->width) * texture->height * 4);
            for (float v : texture->rgba) ASSERT_TRUE(std::isfinite(v));
        } else {
            EXPECT_FALSE(error.empty());
        }
        // Through a scene: a bad image is a warning and the material keeps its Kd.
        scratch.write("uses.mtl", "newmtl m\nKd 1 1 1\nmap_Kd " + abs + "\n");
        expectUsable(loadObj(scratch.write("uses.obj", "mtllib uses.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl m\nf 1/1 2/1 3/1\n")));
    } else {
        FAIL() << "no loader for corpus folder " << file.parser;
    }
}

class Corpus : public ::testing::TestWithParam<CorpusFile> {};

TEST_P(Corpus, ErrorOrCountedWarning) {
    const CorpusFile& file = GetParam();
    const std::string name = file.path.filename().string();
    Scratch scratch;
    test::WarningCounter warnings;
    bool threw = false;
    try {
        load(file, scratch);
    } catch (const InputError& e) {
        threw = true;
        const std::string message = e.what();
        EXPECT_TRUE(name.starts_with("err-")) << "unexpected error: " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
        // Names the input, or the file it refers to (scratch OBJs only ever refer to the corpus).
        EXPECT_TRUE(message.find(name) != std::string::npos || message.find("corpus") != std::string::npos)
            << "does not name the file: " << message;
        std::cout << "  error:   " << message << "\n";
    }
    // Any other exception escapes and fails the test.
    if (threw) return;
    const auto logged = warnings.messages();
    for (const auto& w : logged) std::cout << "  warning: " << w << "\n";
    if (name.starts_with("err-")) ADD_FAILURE() << name << " loaded; expected an InputError";
    if (name.starts_with("warn-")) {
        EXPECT_FALSE(logged.empty()) << name << " loaded without a warning";
    }
    if (name.starts_with("ok-")) {
        EXPECT_TRUE(logged.empty()) << name << " logged warnings";
    }
}

std::string testName(const ::testing::TestParamInfo<CorpusFile>& info) {
    std::string name = info.param.parser + "_" + info.param.path.filename().string();
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return name;
}

INSTANTIATE_TEST_SUITE_P(Files, Corpus, ::testing::ValuesIn(corpusFiles()), testName);

// A scene too large for the memory limit fails before loading, with the estimate and the limit.
TEST(MemoryBudget, TooLargeSceneFailsEarly) {
    Scratch scratch;
    const fs::path obj = scratch.write("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3\n");
    ::setenv("AAMAP_MEMORY_LIMIT", "100", 1);
    try {
        loadObj(obj);
        ADD_FAILURE() << "loaded past the limit";
    } catch (const EnvironmentError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("big.obj"), std::string::npos) << message;
        EXPECT_NE(message.find("MiB available (AAMAP_MEMORY_LIMIT)"), std::string::npos) << message;
    }
    ::setenv("AAMAP_MEMORY_LIMIT", "100000000", 1);
    EXPECT_EQ(loadObj(obj).mesh.triangles.size(), 2u);
    ::unsetenv("AAMAP_MEMORY_LIMIT");
}

// The memory estimate of glTF/GLB scenes (scene/gltf_prescan.h) on the mem-* files.
TEST(MemoryBudget, GltfOverTheLimitFailsEarly) {
    constexpr const char* kMemLimit = "524288";  // 512 KiB: the mem-* files need 0.9 to 1.2 MiB
    int files = 0;
    for (const char* parser : {"gltf", "glb"}) {
        for (const auto& entry : fs::directory_iterator(kCorpus / parser)) {
            const std::string name = entry.path().filename().string();
            if (!name.starts_with("mem-")) continue;
            ++files;
            ::setenv("AAMAP_MEMORY_LIMIT", kMemLimit, 1);
            try {
                loadGltf(entry.path());
                ADD_FAILURE() << name << " loaded past the limit";
            } catch (const EnvironmentError& e) {
                const std::string message = e.what();
                std::cout << "  error:   " << message << "\n";
                EXPECT_NE(message.find(name), std::string::npos) << message;
                EXPECT_NE(message.find("2048 triangles"), std::string::npos) << message;
                EXPECT_NE(message.find(" MiB (2048 triangles"), std::string::npos) << message;  // the estimate
                EXPECT_NE(message.find("the 0.5 MiB available (AAMAP_MEMORY_LIMIT)"), std::string::npos) << message;
                EXPECT_EQ(message.find('\n'), std::string::npos) << message;
            }
            ::setenv("AAMAP_MEMORY_LIMIT", "67108864", 1);
            EXPECT_EQ(loadGltf(entry.path()).mesh.triangles.size(), 2048u) << name;
            ::unsetenv("AAMAP_MEMORY_LIMIT");
        }
    }
    EXPECT_GE(files, 2);
}

TEST(CorpusFolder, CoversEveryParser) {
    for (const char* parser : {"obj", "mtl", "gltf", "glb", "view", "config", "texture", "light"}) {
        EXPECT_TRUE(fs::is_directory(kCorpus / parser)) << parser;
    }
}

}  // namespace
}  // namespace aamap
