#include "scene/obj_loader.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <unordered_map>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>
#include <tiny_obj_loader.h>

#include "core/error.h"
#include "core/memory_budget.h"
#include "scene/lights.h"
#include "scene/obj_prescan.h"
#include "scene/polygon.h"
#include "scene/texture_loader.h"

namespace aamap {
namespace fs = std::filesystem;

namespace {

// Every warning goes to spdlog when it happens and into the report for callers and tests.
void addWarning(std::vector<std::string>& warnings, std::string message) {
    spdlog::warn("{}", message);
    warnings.push_back(std::move(message));
}

std::string readWholeFile(const fs::path& file, const char* what) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw InputError(file, fmt::format("{} not found", what));
    if (fs::is_directory(file, ec)) throw InputError(file, fmt::format("{} is a directory, not a file", what));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file, fmt::format("cannot open {}", what));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw InputError(file, fmt::format("cannot read {}", what));
    return text;
}

// Finds MTL files next to the OBJ (case-insensitively, backslashes allowed), pre-scans them,
// and remembers which folder each material came from so map_Kd resolves relative to its MTL.
class MtlReader : public tinyobj::MaterialReader {
public:
    MtlReader(const fs::path& objFile, std::vector<std::string>& warnings) : objFile_(objFile), warnings_(warnings) {}

    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* matMap, std::string* warn, std::string* err) override {
        try {
            const auto path = resolveCaseInsensitive(objFile_.parent_path(), name);
            if (!path) {
                addWarning(warnings_, fmt::format("{}: material library '{}' not found; using default materials",
                                                  objFile_.string(), name));
                return false;
            }
            const std::string text = readWholeFile(*path, "material library");
            detail::prescanMtl(*path, text);
            std::istringstream in(text);
            const std::size_t before = materials->size();
            tinyobj::LoadMtl(matMap, materials, &in, warn, err);
            for (std::size_t i = before; i < materials->size(); ++i) folders_[i] = path->parent_path();
            libraries_[before] = *path;
            return true;
        } catch (...) {
            // Never throw through tinyobjloader's frames; rethrown once LoadObj returns.
            if (!error_) error_ = std::current_exception();
            return false;
        }
    }

    void rethrow() const {
        if (error_) std::rethrow_exception(error_);
    }
    fs::path folderOf(std::size_t material) const {
        const auto it = folders_.find(material);
        return it != folders_.end() ? it->second : objFile_.parent_path();
    }
    fs::path libraryOf(std::size_t material) const {
        auto it = libraries_.upper_bound(material);
        return it == libraries_.begin() ? objFile_ : std::prev(it)->second;
    }

private:
    fs::path objFile_;
    std::vector<std::string>& warnings_;
    std::map<std::size_t, fs::path> folders_;
    std::map<std::size_t, fs::path> libraries_;  // first material index -> MTL file
    std::exception_ptr error_;
};

Material convertMaterial(const tinyobj::material_t& m) {
    Material out;
    out.name = m.name;
    out.kd = {m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    out.ks = {m.specular[0], m.specular[1], m.specular[2]};
    out.ns = m.shininess;
    out.ke = {m.emission[0], m.emission[1], m.emission[2]};
    out.ior = m.ior > 0.0f ? m.ior : 1.5f;
    if (m.illum == 3 || m.illum == 5) out.kind = MaterialKind::Mirror;
    if (m.illum == 7) out.kind = MaterialKind::Glass;
    return out;
}

struct VertexKey {
    int v, vn, vt;
    bool operator==(const VertexKey&) const = default;
};
struct VertexKeyHash {
    std::size_t operator()(const VertexKey& k) const {
        return std::hash<long long>()((static_cast<long long>(k.v) * 73856093) ^ (static_cast<long long>(k.vn) * 19349663) ^
                                      (static_cast<long long>(k.vt) * 83492791));
    }
};

// Turns tinyobjloader's shapes (untriangulated faces) into the merged triangle mesh.
class MeshBuilder {
public:
    MeshBuilder(const fs::path& file, const tinyobj::attrib_t& attrib, TriangleMesh& mesh)
        : file_(file), attrib_(attrib), mesh_(mesh), hasUVs_(!attrib.texcoords.empty()) {}

    void addFace(std::span<const tinyobj::index_t> face, std::uint32_t materialId, std::uint32_t objectId) {
        std::vector<glm::vec3> points;
        for (const tinyobj::index_t& index : face) {
            checkIndex(index.vertex_index, attrib_.vertices.size() / 3, "vertex");
            checkIndex(index.normal_index, attrib_.normals.size() / 3, "normal", true);
            checkIndex(index.texcoord_index, attrib_.texcoords.size() / 2, "texture coordinate", true);
            points.push_back(position(index.vertex_index));
        }
        for (const auto& tri : triangulatePolygon(points)) {
            const glm::vec3 a = points[tri[0]], b = points[tri[1]], c = points[tri[2]];
            const glm::vec3 n = glm::cross(b - a, c - a);
            const float len = glm::length(n);
            if (!(len > 0.0f) || !std::isfinite(len)) {
                ++degenerate_;
                continue;
            }
            const glm::vec3 flat = n / len;
            bool smooth = true;
            for (int k : tri) smooth = smooth && validNormal(face[k].normal_index);
            glm::uvec3 out;
            for (int j = 0; j < 3; ++j) out[j] = vertex(face[tri[j]], smooth, flat);
            mesh_.triangles.push_back(out);
            mesh_.materialIds.push_back(materialId);
            mesh_.objectIds.push_back(objectId);
        }
    }

    std::size_t degenerate() const { return degenerate_; }

private:
    void checkIndex(int index, std::size_t count, const char* what, bool optional = false) const {
        if ((optional && index == -1) || (index >= 0 && static_cast<std::size_t>(index) < count)) return;
        throw InputError(file_, fmt::format("a face uses {} index {} but the file has {}", what, index + 1, count));
    }

    glm::vec3 position(int i) const {
        return {attrib_.vertices[3 * i], attrib_.vertices[3 * i + 1], attrib_.vertices[3 * i + 2]};
    }
    glm::vec3 normal(int i) const {
        return {attrib_.normals[3 * i], attrib_.normals[3 * i + 1], attrib_.normals[3 * i + 2]};
    }
    bool validNormal(int i) const {
        if (i < 0) return false;
        const float len = glm::length(normal(i));
        return len > 0.0f && std::isfinite(len);
    }

    std::uint32_t vertex(const tinyobj::index_t& index, bool smooth, glm::vec3 flat) {
        const int vt = hasUVs_ ? index.texcoord_index : -1;
        const VertexKey key{index.vertex_index, smooth ? index.normal_index : -1, vt};
        if (smooth) {  // flat vertices are never shared: their normal belongs to one triangle
            if (const auto it = welded_.find(key); it != welded_.end()) return it->second;
        }
        const auto id = static_cast<std::uint32_t>(mesh_.positions.size());
        mesh_.positions.push_back(position(index.vertex_index));
        mesh_.normals.push_back(smooth ? glm::normalize(normal(index.normal_index)) : flat);
        if (hasUVs_) {
            mesh_.uvs.push_back(vt >= 0 ? glm::vec2(attrib_.texcoords[2 * vt], 1.0f - attrib_.texcoords[2 * vt + 1])
                                        : glm::vec2(0.0f));
        }
        if (smooth) welded_.emplace(key, id);
        return id;
    }

    const fs::path& file_;
    const tinyobj::attrib_t& attrib_;
    TriangleMesh& mesh_;
    bool hasUVs_;
    std::size_t degenerate_ = 0;
    std::unordered_map<VertexKey, std::uint32_t, VertexKeyHash> welded_;
};

std::string firstLine(const std::string& text) {
    const auto end = text.find_first_of("\r\n");
    return end == std::string::npos ? text : text.substr(0, end);
}

}  // namespace

Scene loadObj(const fs::path& file, ObjLoadReport* report) {
    ObjLoadReport localReport;
    ObjLoadReport& rep = report ? *report : localReport;
    rep = {};
    const std::string text = readWholeFile(file, "OBJ file");
    const detail::ObjPrescan counts = detail::prescanObj(file, text);
    // Before any big allocation: tinyobjloader's copy (floats, 12 B per face corner), then per face
    // up to two triangles of three unshared 32 B vertices, and the BVH (~64 B per triangle).
    checkMemoryBudget(text.size() + 4 * (3 * counts.positions + 3 * counts.normals + 2 * counts.uvs) + 400 * counts.faces,
                      "loading " + file.string(),
                      fmt::format("{} faces, {} vertices: parser copy, mesh and BVH", counts.faces, counts.positions));

    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> objMaterials;
    std::string warn, err;
    MtlReader mtlReader(file, rep.warnings);
    std::istringstream in(text);
    const bool ok = tinyobj::LoadObj(&attrib, &shapes, &objMaterials, &warn, &err, &in, &mtlReader,
                                     /*triangulate=*/false, /*default_vcols_fallback=*/false);
    mtlReader.rethrow();
    if (!ok) throw InputError(file, firstLine(err.empty() ? std::string("tinyobjloader failed") : err));
    std::istringstream warnLines(warn + err);
    for (std::string line; std::getline(warnLines, line);) {
        if (line.empty()) continue;
        if (line.find("Both `d` and `Tr`") != std::string::npos) {  // common and harmless: d wins
            spdlog::debug("{}: {}", file.string(), line);
            continue;
        }
        addWarning(rep.warnings, fmt::format("{}: {}", file.string(), line));
    }

    Scene scene;
    scene.name = file.stem().string();
    scene.source = file;
    TextureCache textures(scene.textures);
    for (std::size_t i = 0; i < objMaterials.size(); ++i) {
        Material m = convertMaterial(objMaterials[i]);
        if (!objMaterials[i].diffuse_texname.empty()) {
            m.diffuseTexture = textures.get(mtlReader.folderOf(i), objMaterials[i].diffuse_texname,
                                            mtlReader.libraryOf(i), &rep.warnings);
        }
        // Coverage: d (tinyobj turns Tr into d = 1 - Tr) times map_d. A map_d is an alpha mask
        // (foliage cut-outs in Sponza-like scenes); a constant d < 1 is a blend, cut at 0.5.
        m.alpha = std::clamp(static_cast<float>(objMaterials[i].dissolve), 0.0f, 1.0f);
        if (!objMaterials[i].alpha_texname.empty()) {
            m.alphaMode = AlphaMode::Mask;
            m.alphaTexture = textures.getCoverage(mtlReader.folderOf(i), objMaterials[i].alpha_texname,
                                                  mtlReader.libraryOf(i), &rep.warnings);
        } else if (m.alpha < 1.0f) {
            m.alphaMode = AlphaMode::Blend;
        }
        scene.materials.push_back(std::move(m));
    }

    std::uint32_t defaultMaterial = UINT32_MAX;  // appended on first use
    MeshBuilder builder(file, attrib, scene.mesh);
    for (std::size_t s = 0; s < shapes.size(); ++s) {
        const tinyobj::mesh_t& mesh = shapes[s].mesh;
        rep.objectNames.push_back(shapes[s].name.empty() ? fmt::format("shape{}", s) : shapes[s].name);
        std::size_t offset = 0;
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            const std::size_t count = mesh.num_face_vertices[f];
            if (offset + count > mesh.indices.size()) throw InputError(file, "inconsistent face data from tinyobjloader");
            int materialId = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
            if (materialId < 0 || static_cast<std::size_t>(materialId) >= objMaterials.size()) {
                if (defaultMaterial == UINT32_MAX) {
                    defaultMaterial = static_cast<std::uint32_t>(scene.materials.size());
                    scene.materials.push_back(Material{.name = "default"});
                }
                materialId = static_cast<int>(defaultMaterial);
            }
            builder.addFace(std::span(mesh.indices).subspan(offset, count), static_cast<std::uint32_t>(materialId),
                            static_cast<std::uint32_t>(s));
            offset += count;
        }
    }
    rep.degenerateTriangles = builder.degenerate();
    if (rep.degenerateTriangles > 0) {
        addWarning(rep.warnings, fmt::format("{}: skipped {} zero-area triangles", file.string(), rep.degenerateTriangles));
    }
    if (scene.mesh.triangles.empty()) addWarning(rep.warnings, fmt::format("{}: the file has no triangles", file.string()));
    scene.areaLights = buildAreaLights(scene, rep.objectNames);
    return scene;
}

}  // namespace aamap
