#include "scene/gltf_prescan.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/memory_budget.h"

namespace aamap::detail {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::uint64_t readU32(const char* p) {
    std::uint32_t v = 0;
    std::memcpy(&v, p, 4);  // GLB is little-endian, as is every machine this builds on
    return v;
}

// A non-negative integer member, else 0 (bad types are the loader's to report).
std::uint64_t count(const json& object, const char* key) {
    if (!object.is_object()) return 0;
    const auto it = object.find(key);
    if (it == object.end() || !it->is_number()) return 0;
    const double v = it->get<double>();
    return v > 0 && v < 1.8e19 ? static_cast<std::uint64_t>(v) : 0;
}

const json* element(const json& root, const char* array, std::uint64_t index) {
    const auto it = root.find(array);
    if (it == root.end() || !it->is_array() || index >= it->size()) return nullptr;
    return &(*it)[index];
}

std::uint64_t componentBytes(std::uint64_t componentType) {
    switch (componentType) {
        case 5120: case 5121: return 1;
        case 5122: case 5123: return 2;
        default: return 4;
    }
}

std::uint64_t typeComponents(const json& accessor) {
    const auto it = accessor.find("type");
    if (it == accessor.end() || !it->is_string()) return 1;
    const std::string t = it->get<std::string>();
    if (t == "VEC2") return 2;
    if (t == "VEC3") return 3;
    if (t == "VEC4" || t == "MAT2") return 4;
    if (t == "MAT3") return 9;
    if (t == "MAT4") return 16;
    return 1;
}

// The bytes buffer i really has: the GLB BIN chunk, the size of its .bin file, or its data URI.
std::uint64_t presentBufferBytes(const json& buffer, const fs::path& file, std::uint64_t binChunk) {
    const std::uint64_t declared = count(buffer, "byteLength");
    const auto uri = buffer.is_object() ? buffer.find("uri") : buffer.end();
    if (uri == buffer.end() || !uri->is_string()) return std::min(declared, binChunk);
    const std::string u = uri->get<std::string>();
    if (u.starts_with("data:")) return std::min(declared, u.size() * 3 / 4);
    std::error_code ec;
    const std::uint64_t size = fs::file_size(file.parent_path() / u, ec);
    return ec ? 0 : std::min(declared, size);
}

}  // namespace

std::uint64_t GltfPrescan::estimateBytes() const {
    // The file and its parsed JSON (a DOM is several times its text), the decoded buffers, the
    // accessors read as floats (position, normal, uv: 32 B per vertex; 12 B of indices per
    // triangle), and the mesh and BVH as for OBJ (~400 B per triangle).
    return fileBytes + 8 * jsonBytes + bufferBytes + 32 * vertices + 412 * triangles;
}

GltfPrescan prescanGltf(const fs::path& file) {
    GltfPrescan p;
    std::error_code ec;
    p.fileBytes = fs::file_size(file, ec);
    if (ec) return GltfPrescan{};
    std::ifstream in(file, std::ios::binary);
    std::string text;
    std::uint64_t binChunk = 0;
    char header[20];
    if (in.read(header, 20) && std::memcmp(header, "glTF", 4) == 0) {
        const std::uint64_t jsonLength = readU32(header + 12);
        if (readU32(header + 16) != 0x4E4F534Au || jsonLength > p.fileBytes - 20) return p;  // not "JSON"
        text.resize(jsonLength);
        if (!in.read(text.data(), static_cast<std::streamsize>(jsonLength))) return p;
        in.seekg(static_cast<std::streamoff>((jsonLength + 3) / 4 * 4 + 20));
        char chunk[8];
        if (in.read(chunk, 8) && readU32(chunk + 4) == 0x004E4942u)  // "BIN\0"
            binChunk = std::min<std::uint64_t>(readU32(chunk), p.fileBytes);
    } else {
        text.resize(p.fileBytes);
        in.clear();
        in.seekg(0);
        if (!in.read(text.data(), static_cast<std::streamsize>(p.fileBytes))) return p;
    }
    p.jsonBytes = text.size();
    const json root = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (!root.is_object()) return p;

    std::vector<std::uint64_t> bufferBytes;
    if (const auto b = root.find("buffers"); b != root.end() && b->is_array())
        for (const json& buffer : *b) bufferBytes.push_back(presentBufferBytes(buffer, file, binChunk));
    for (std::uint64_t b : bufferBytes) p.bufferBytes += b;

    // An accessor's element count, clamped to what its buffer view can hold.
    const auto elements = [&](std::uint64_t index) -> std::uint64_t {
        const json* accessor = element(root, "accessors", index);
        if (!accessor || !accessor->is_object()) return 0;
        const std::uint64_t n = count(*accessor, "count");
        if (!accessor->contains("bufferView")) return std::min<std::uint64_t>(n, 1u << 20);  // zeros or sparse
        const json* view = element(root, "bufferViews", count(*accessor, "bufferView"));
        if (!view || !view->is_object()) return 0;
        const std::uint64_t buffer = count(*view, "buffer");
        const std::uint64_t bytes = buffer < bufferBytes.size() ? std::min(count(*view, "byteLength"), bufferBytes[buffer]) : 0;
        return std::min(n, bytes / (componentBytes(count(*accessor, "componentType")) * typeComponents(*accessor)));
    };
    const auto meshes = root.find("meshes");
    const auto nodes = root.find("nodes");
    if (meshes == root.end() || !meshes->is_array() || nodes == root.end() || !nodes->is_array()) return p;
    for (const json& node : *nodes) {
        if (!node.is_object() || !node.contains("mesh")) continue;
        const json* mesh = element(root, "meshes", count(node, "mesh"));
        if (!mesh || !mesh->is_object() || !mesh->contains("primitives") || !(*mesh)["primitives"].is_array()) continue;
        for (const json& primitive : (*mesh)["primitives"]) {
            if (!primitive.is_object()) continue;
            const auto attributes = primitive.find("attributes");
            const std::uint64_t vertices =
                attributes != primitive.end() && attributes->is_object() ? elements(count(*attributes, "POSITION")) : 0;
            p.vertices += vertices;
            p.triangles += (primitive.contains("indices") ? elements(count(primitive, "indices")) : vertices) / 3;
        }
    }
    return p;
}

void checkGltfMemoryBudget(const fs::path& file) {
    // A .gltf is read and parsed whole just to count: check that part first.
    std::error_code ec;
    const std::uint64_t size = fs::file_size(file, ec);
    if (!ec && file.extension() != ".glb" && file.extension() != ".GLB")
        checkMemoryBudget(9 * size, "loading " + file.string(), fmt::format("{:.3g} MiB of JSON", size / 1048576.0));
    const GltfPrescan p = prescanGltf(file);
    checkMemoryBudget(p.estimateBytes(), "loading " + file.string(),
                      fmt::format("{} triangles, {} vertices, {:.3g} MiB of buffers: parser, mesh and BVH", p.triangles,
                                  p.vertices, p.bufferBytes / 1048576.0));
}

}  // namespace aamap::detail
