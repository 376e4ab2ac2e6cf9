#pragma once
// One textured, alpha-masked quad written as OBJ+MTL and as glTF (the same geometry, uvs and
// texture), for the loader tests and the Snapshot's OBJ-vs-glTF agreement test. The quad spans
// [-1, 1]^2 in the plane z = 0 facing +z; texture (0, 0) is its top-left corner (x = -1, y = 1).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "tests/common/base64.h"
#include "tests/common/temp_dir.h"

namespace aamap::test {

// A side x side RGBA texture whose central half (texels side/4 .. 3 side/4 - 1 on both axes) has
// alpha 0 and a one-texel black/white checker in rgb; around it alpha is 255 and rgb a smooth ramp
// (or uniform grey if `flat`), so any masked texel that showed would make edges.
inline std::vector<std::uint8_t> holeTexture(int side, bool flat) {
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(side) * side * 4);
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            std::uint8_t* p = &rgba[4 * (static_cast<std::size_t>(y) * side + x)];
            const bool hole = x >= side / 4 && x < 3 * side / 4 && y >= side / 4 && y < 3 * side / 4;
            if (hole) {
                const std::uint8_t c = (x + y) % 2 ? 255 : 0;
                p[0] = p[1] = p[2] = c;
                p[3] = 0;
            } else {
                p[0] = flat ? 180 : static_cast<std::uint8_t>(60 + 150 * x / side);
                p[1] = flat ? 180 : static_cast<std::uint8_t>(200 - 100 * y / side);
                p[2] = flat ? 180 : 120;
                p[3] = 255;
            }
        }
    }
    return rgba;
}

inline std::filesystem::path writePng(const TempDir& dir, const std::string& name, int side,
                                      const std::vector<std::uint8_t>& rgba, int channels = 4) {
    const auto file = dir.path() / name;
    std::vector<std::uint8_t> data;
    for (std::size_t i = 0; i < rgba.size(); i += 4)
        for (int c = 0; c < channels; ++c) data.push_back(rgba[i + static_cast<std::size_t>(c)]);
    stbi_write_png(file.string().c_str(), side, side, channels, data.data(), side * channels);
    return file;
}

// quad.obj + quad.mtl: map_Kd and map_d both `texture`, so coverage is its alpha channel.
inline std::filesystem::path writeQuadObj(const TempDir& dir, const std::string& texture) {
    dir.write("quad.mtl", "newmtl masked\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd " + texture + "\nmap_d " + texture + "\n");
    return dir.write("quad.obj",
                     "mtllib quad.mtl\n"
                     "v -1 1 0\nv 1 1 0\nv 1 -1 0\nv -1 -1 0\n"
                     "vt 0 1\nvt 1 1\nvt 1 0\nvt 0 0\n"  // OBJ: v = 0 at the bottom
                     "vn 0 0 1\n"
                     "o quad\nusemtl masked\nf 4/4/1 3/3/1 2/2/1 1/1/1\n");
}

// quad.gltf: the same quad, MASK at 0.5 with `texture` as baseColorTexture (uri, not embedded).
inline std::filesystem::path writeQuadGltf(const TempDir& dir, const std::string& texture,
                                           const std::string& alphaMode = "MASK") {
    std::string buf;
    const auto put = [&](std::initializer_list<float> values) {
        for (float v : values) buf.append(reinterpret_cast<const char*>(&v), sizeof v);
    };
    put({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0});  // 0: positions (48 bytes)
    put({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});      // 48: normals
    put({0, 1, 1, 1, 1, 0, 0, 0});                  // 96: uvs (32 bytes), v = 0 at the top
    for (std::uint16_t i : {0, 1, 2, 0, 2, 3}) buf.append(reinterpret_cast<const char*>(&i), sizeof i);  // 128
    const std::string json = R"({
  "asset": {"version": "2.0"},
  "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"name": "quad", "mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
  "materials": [{"name": "masked", "alphaMode": ")" + alphaMode + R"(", "alphaCutoff": 0.5,
    "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 1,
                             "baseColorTexture": {"index": 0}}}],
  "textures": [{"source": 0}],
  "images": [{"uri": ")" + texture + R"("}],
  "buffers": [{"byteLength": 140, "uri": "data:application/octet-stream;base64,)" + base64(buf) + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 128}, {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
  "accessors": [
    {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
    {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 0, "byteOffset": 96, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 1, "byteOffset": 0, "componentType": 5123, "count": 6, "type": "SCALAR"}]
})";
    return dir.write("quad.gltf", json);
}

}  // namespace aamap::test
