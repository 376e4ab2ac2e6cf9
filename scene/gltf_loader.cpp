#include "scene/gltf_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <regex>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>
#include <spdlog/spdlog.h>
#include <tiny_gltf.h>  // declarations only; libtinygltf holds the implementation

#include "core/error.h"
#include "scene/gltf_accessors.h"
#include "scene/gltf_prescan.h"
#include "scene/lights.h"
#include "scene/texture_loader.h"

namespace aamap {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxNodeDepth = 256;  // glTF forbids cycles; a corrupt file must not recurse forever

double extensionNumber(const tinygltf::ExtensionMap& extensions, const char* extension, const char* key, double fallback) {
    const auto it = extensions.find(extension);
    if (it == extensions.end() || !it->second.Has(key)) return fallback;
    const tinygltf::Value& v = it->second.Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

// URIs in glTF are percent-encoded ("my%20texture.png").
std::string decodeUri(std::string_view uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += static_cast<char>(std::stoi(std::string(uri.substr(i + 1, 2)), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

glm::mat4 localMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        glm::dmat4 m;
        std::copy(node.matrix.begin(), node.matrix.end(), glm::value_ptr(m));  // column-major, like glm
        return glm::mat4(m);
    }
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3) m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4) {
        m *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    }
    if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return glm::mat4(m);
}

// sRGB-encoded texels (8 or 16 bit, 1-4 channels) as tinygltf decoded them -> linear RGBA.
std::optional<Texture> linearTexture(const tinygltf::Image& image, const fs::path& path) {
    const std::size_t texels = static_cast<std::size_t>(image.width) * image.height;
    const int channels = image.component, bytes = image.bits == 16 ? 2 : 1;
    if (channels < 1 || channels > 4 || image.image.size() < texels * channels * bytes) return std::nullopt;
    const auto linear = [](float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); };
    Texture t;
    t.path = path;
    t.width = image.width;
    t.height = image.height;
    t.rgba.resize(texels * 4);
    for (std::size_t i = 0; i < texels; ++i) {
        float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        for (int c = 0; c < channels; ++c) {
            const std::size_t at = (i * channels + c) * bytes;
            v[c] = bytes == 2 ? static_cast<float>(image.image[at] | image.image[at + 1] << 8) / 65535.0f
                              : static_cast<float>(image.image[at]) / 255.0f;
        }
        const bool grey = channels <= 2;
        t.rgba[i * 4 + 0] = linear(v[0]);
        t.rgba[i * 4 + 1] = linear(grey ? v[0] : v[1]);
        t.rgba[i * 4 + 2] = linear(grey ? v[0] : v[2]);
        t.rgba[i * 4 + 3] = channels == 2 ? v[1] : channels == 4 ? v[3] : 1.0f;
    }
    return t;
}

class GltfBuilder {
public:
    GltfBuilder(const fs::path& file, const tinygltf::Model& model, Scene& scene)
        : file_(file), model_(model), scene_(scene), textures_(scene.textures) {}

    void build() {
        for (const tinygltf::Material& m : model_.materials) scene_.materials.push_back(convertMaterial(m));
        std::vector<int> roots;
        if (!model_.scenes.empty()) {
            const int s = model_.defaultScene >= 0 && static_cast<std::size_t>(model_.defaultScene) < model_.scenes.size()
                              ? model_.defaultScene : 0;
            roots = model_.scenes[s].nodes;
        } else {  // no scene: every node that is nobody's child
            std::vector<bool> child(model_.nodes.size(), false);
            for (const auto& n : model_.nodes) {
                for (int c : n.children) {
                    if (c >= 0 && static_cast<std::size_t>(c) < child.size()) child[c] = true;
                }
            }
            for (std::size_t i = 0; i < child.size(); ++i) {
                if (!child[i]) roots.push_back(static_cast<int>(i));
            }
        }
        for (int root : roots) visit(root, glm::mat4(1.0f), 0);
        if (!hasUVs_) scene_.mesh.uvs.clear();
        if (degenerate_ > 0) warn(fmt::format("skipped {} zero-area triangles", degenerate_));
        scene_.areaLights = buildAreaLights(scene_, objectNames_);
    }

private:
    void warn(const std::string& message) { spdlog::warn("{}: {}", file_.string(), message); }

    Material convertMaterial(const tinygltf::Material& m) {
        Material out;
        out.name = m.name;
        const auto& pbr = m.pbrMetallicRoughness;
        const glm::vec3 base(pbr.baseColorFactor.size() >= 3 ? glm::vec3(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2])
                                                              : glm::vec3(1.0f));
        const auto metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
        const auto roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
        out.kd = base * (1.0f - metallic);
        out.ks = base * metallic;
        out.ns = std::min(2.0f / std::max(std::pow(roughness, 4.0f), 1e-6f) - 2.0f, 10000.0f);
        if (m.emissiveFactor.size() == 3) {
            const auto strength = static_cast<float>(extensionNumber(m.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0));
            out.ke = glm::vec3(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]) * strength;
        }
        out.ior = static_cast<float>(extensionNumber(m.extensions, "KHR_materials_ior", "ior", 1.5));
        if (extensionNumber(m.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0) > 0.0) {
            out.kind = MaterialKind::Glass;
        } else if (metallic >= 0.99f && roughness <= 0.05f && pbr.metallicRoughnessTexture.index < 0) {
            out.kind = MaterialKind::Mirror;
        }
        if (pbr.baseColorTexture.index >= 0) out.diffuseTexture = texture(pbr.baseColorTexture.index, m.name);
        // Coverage: baseColorFactor.a times the base-colour texture's alpha.
        if (m.alphaMode == "MASK") out.alphaMode = AlphaMode::Mask;
        else if (m.alphaMode == "BLEND") out.alphaMode = AlphaMode::Blend;
        else if (!m.alphaMode.empty() && m.alphaMode != "OPAQUE")
            throw InputError(file_, fmt::format("material '{}' has alphaMode '{}' (expected OPAQUE, MASK or BLEND)",
                                                m.name, m.alphaMode));
        out.alpha = pbr.baseColorFactor.size() == 4 ? static_cast<float>(std::clamp(pbr.baseColorFactor[3], 0.0, 1.0)) : 1.0f;
        out.alphaCutoff = static_cast<float>(m.alphaCutoff);
        if (out.alphaMode != AlphaMode::Opaque) out.alphaTexture = out.diffuseTexture;
        return out;
    }

    int texture(int textureIndex, const std::string& materialName) {
        if (static_cast<std::size_t>(textureIndex) >= model_.textures.size()) {
            throw InputError(file_, fmt::format("material '{}' uses texture {}, which does not exist", materialName, textureIndex));
        }
        const int source = model_.textures[textureIndex].source;
        if (source < 0 || static_cast<std::size_t>(source) >= model_.images.size()) {
            warn(fmt::format("texture {} has no image; using the base colour", textureIndex));
            return -1;
        }
        if (const auto it = byImage_.find(source); it != byImage_.end()) return it->second;
        const tinygltf::Image& image = model_.images[source];
        int index = -1;
        if (!image.image.empty()) {
            auto decoded = linearTexture(image, image.uri.empty() ? fs::path(image.name) : file_.parent_path() / image.uri);
            if (decoded) {
                index = static_cast<int>(scene_.textures.size());
                scene_.textures.push_back(std::move(*decoded));
            } else {
                warn(fmt::format("image {} has an unexpected pixel layout; using the base colour", source));
            }
        } else if (!image.uri.empty() && !image.uri.starts_with("data:")) {
            // tinygltf could not open it: retry with a case-insensitive lookup (warns if missing).
            index = textures_.get(file_.parent_path(), decodeUri(image.uri), file_);
        } else {
            warn(fmt::format("image {} could not be decoded; using the base colour", source));
        }
        byImage_[source] = index;
        return index;
    }

    void visit(int nodeIndex, const glm::mat4& parent, int depth) {
        if (nodeIndex < 0 || static_cast<std::size_t>(nodeIndex) >= model_.nodes.size()) {
            throw InputError(file_, fmt::format("node {} does not exist", nodeIndex));
        }
        if (depth > kMaxNodeDepth) throw InputError(file_, "the node hierarchy is too deep (a cycle?)");
        const tinygltf::Node& node = model_.nodes[nodeIndex];
        const glm::mat4 world = parent * localMatrix(node);
        if (node.mesh >= 0) addMesh(node, world);
        if (node.camera >= 0) addCamera(node, world);
        if (const auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end() && it->second.Has("light")) {
            addLight(it->second.Get("light").GetNumberAsInt(), world);
        }
        for (int child : node.children) visit(child, world, depth + 1);
    }

    void addMesh(const tinygltf::Node& node, const glm::mat4& world) {
        if (static_cast<std::size_t>(node.mesh) >= model_.meshes.size()) {
            throw InputError(file_, fmt::format("node '{}' uses mesh {}, which does not exist", node.name, node.mesh));
        }
        const tinygltf::Mesh& mesh = model_.meshes[node.mesh];
        const auto objectId = static_cast<std::uint32_t>(objectNames_.size());
        objectNames_.push_back(!node.name.empty() ? node.name : !mesh.name.empty() ? mesh.name : fmt::format("node{}", objectId));
        const glm::mat3 normalMatrix = glm::inverseTranspose(glm::mat3(world));
        const bool mirrored = glm::determinant(glm::mat3(world)) < 0.0f;
        for (const tinygltf::Primitive& prim : mesh.primitives) {
            const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
                warn(fmt::format("mesh '{}': skipped a primitive of points or lines", mesh.name));
                continue;
            }
            const auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end()) throw InputError(file_, fmt::format("mesh '{}' has a primitive without POSITION", mesh.name));
            const std::vector<float> p = detail::readFloats(model_, pos->second, 3, file_);
            if (std::any_of(p.begin(), p.end(), [](float v) { return !std::isfinite(v); })) {
                throw InputError(file_, fmt::format("mesh '{}': POSITION accessor {} holds a NaN or infinite value", mesh.name, pos->second));
            }
            const std::size_t count = p.size() / 3;
            std::vector<float> n, uv;
            if (const auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) n = detail::readFloats(model_, it->second, 3, file_);
            if (const auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) uv = detail::readFloats(model_, it->second, 2, file_);
            if ((!n.empty() && n.size() != p.size()) || (!uv.empty() && uv.size() / 2 != count)) {
                throw InputError(file_, fmt::format("mesh '{}': attribute counts differ from POSITION", mesh.name));
            }
            hasUVs_ = hasUVs_ || !uv.empty();
            std::vector<std::uint32_t> idx;
            if (prim.indices >= 0) {
                idx = detail::readIndices(model_, prim.indices, file_);
            } else {
                idx.resize(count);
                for (std::size_t i = 0; i < count; ++i) idx[i] = static_cast<std::uint32_t>(i);
            }
            for (std::uint32_t i : idx) {
                if (i >= count) throw InputError(file_, fmt::format("mesh '{}': index {} is out of range ({} vertices)", mesh.name, i, count));
            }
            const std::uint32_t materialId = materialFor(prim.material);
            for (std::size_t t = 0; t + 2 < idx.size(); t += (mode == TINYGLTF_MODE_TRIANGLES ? 3 : 1)) {
                std::array<std::uint32_t, 3> tri = {idx[t], idx[t + 1], idx[t + 2]};
                if (mode == TINYGLTF_MODE_TRIANGLE_FAN) tri = {idx[0], idx[t + 1], idx[t + 2]};
                if (mode == TINYGLTF_MODE_TRIANGLE_STRIP && t % 2 == 1) std::swap(tri[0], tri[1]);
                if (mirrored) std::swap(tri[1], tri[2]);
                addTriangle(tri, p, n, uv, world, normalMatrix, materialId, objectId);
            }
        }
    }

    void addTriangle(const std::array<std::uint32_t, 3>& tri, const std::vector<float>& p, const std::vector<float>& n,
                     const std::vector<float>& uv, const glm::mat4& world, const glm::mat3& normalMatrix,
                     std::uint32_t materialId, std::uint32_t objectId) {
        std::array<glm::vec3, 3> pos;
        for (int k = 0; k < 3; ++k) pos[k] = glm::vec3(world * glm::vec4(p[3 * tri[k]], p[3 * tri[k] + 1], p[3 * tri[k] + 2], 1.0f));
        const glm::vec3 c = glm::cross(pos[1] - pos[0], pos[2] - pos[0]);
        const float len = glm::length(c);
        if (!(len > 0.0f) || !std::isfinite(len)) {  // zero-area or non-finite: dropped and counted
            ++degenerate_;
            return;
        }
        TriangleMesh& mesh = scene_.mesh;
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        for (int k = 0; k < 3; ++k) {
            glm::vec3 normal = c / len;
            if (!n.empty()) {
                const glm::vec3 v = normalMatrix * glm::vec3(n[3 * tri[k]], n[3 * tri[k] + 1], n[3 * tri[k] + 2]);
                if (glm::length(v) > 0.0f && std::isfinite(glm::length(v))) normal = glm::normalize(v);
            }
            mesh.positions.push_back(pos[k]);
            mesh.normals.push_back(normal);
            mesh.uvs.push_back(uv.empty() ? glm::vec2(0.0f) : glm::vec2(uv[2 * tri[k]], uv[2 * tri[k] + 1]));
        }
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.materialIds.push_back(materialId);
        mesh.objectIds.push_back(objectId);
    }

    std::uint32_t materialFor(int material) {
        if (material >= 0 && static_cast<std::size_t>(material) < model_.materials.size()) return static_cast<std::uint32_t>(material);
        if (material >= 0) throw InputError(file_, fmt::format("a primitive uses material {}, which does not exist", material));
        if (defaultMaterial_ < 0) {  // glTF's default: white, fully rough dielectric
            defaultMaterial_ = static_cast<int>(scene_.materials.size());
            scene_.materials.push_back({.name = "default", .kd = glm::vec3(1.0f)});
        }
        return static_cast<std::uint32_t>(defaultMaterial_);
    }

    void addCamera(const tinygltf::Node& node, const glm::mat4& world) {
        if (static_cast<std::size_t>(node.camera) >= model_.cameras.size()) {
            throw InputError(file_, fmt::format("node '{}' uses camera {}, which does not exist", node.name, node.camera));
        }
        const tinygltf::Camera& cam = model_.cameras[node.camera];
        if (cam.type != "perspective") {
            warn(fmt::format("camera {} is {}; only perspective cameras become views", node.camera, cam.type));
            return;
        }
        if (!(cam.perspective.yfov > 0.0 && cam.perspective.yfov < 3.14)) {
            warn(fmt::format("camera {} has yfov {} outside (0, pi); skipped", node.camera, cam.perspective.yfov));
            return;
        }
        View v;
        v.name = !cam.name.empty() ? cam.name : !node.name.empty() ? node.name : fmt::format("{}:camera{}", file_.stem().string(), node.camera);
        v.position = glm::vec3(world[3]);
        v.direction = glm::normalize(glm::vec3(world * glm::vec4(0, 0, -1, 0)));
        v.up = glm::normalize(glm::vec3(world * glm::vec4(0, 1, 0, 0)));
        const double halfV = cam.perspective.yfov / 2.0;
        const double aspect = cam.perspective.aspectRatio > 0.0 ? cam.perspective.aspectRatio : 1.0;
        v.verticalFovDeg = static_cast<float>(glm::degrees(2.0 * halfV));
        v.horizontalFovDeg = static_cast<float>(glm::degrees(2.0 * std::atan(aspect * std::tan(halfV))));
        scene_.views.push_back(v);
    }

    void addLight(int index, const glm::mat4& world) {
        if (index < 0 || static_cast<std::size_t>(index) >= model_.lights.size()) {
            throw InputError(file_, fmt::format("KHR_lights_punctual light {} does not exist", index));
        }
        const tinygltf::Light& light = model_.lights[index];
        if (light.type == "directional") {
            warn(fmt::format("directional light '{}' is not supported; skipped", light.name));
            return;
        }
        const glm::vec3 colour = light.color.size() == 3 ? glm::vec3(light.color[0], light.color[1], light.color[2]) : glm::vec3(1.0f);
        PointLight p{light.name.empty() ? fmt::format("light{}", index) : light.name, glm::vec3(world[3]),
                     colour * static_cast<float>(light.intensity), glm::vec3(0.0f)};
        if (light.type == "spot") {
            // The cone points down the node's local -Z; angles are half-angles from that axis.
            const glm::vec3 axis = glm::vec3(world * glm::vec4(0, 0, -1, 0));
            const double inner = light.spot.innerConeAngle, outer = light.spot.outerConeAngle;
            if (!(glm::length(axis) > 0.0f) || !(outer > 0.0) || !(inner >= 0.0) || inner > outer) {
                warn(fmt::format("spot light '{}' has cone angles inner {} outer {} (need 0 <= inner <= outer, outer > 0) "
                                 "or a degenerate transform; skipped", p.name, inner, outer));
                return;
            }
            p.spotDirection = glm::normalize(axis);
            p.cosInner = static_cast<float>(std::cos(inner));
            p.cosOuter = static_cast<float>(std::cos(outer));
        }
        scene_.pointLights.push_back(std::move(p));
    }

    const fs::path& file_;
    const tinygltf::Model& model_;
    Scene& scene_;
    TextureCache textures_;
    std::map<int, int> byImage_;
    std::vector<std::string> objectNames_;
    int defaultMaterial_ = -1;
    std::size_t degenerate_ = 0;
    bool hasUVs_ = false;
};

// nlohmann's parse errors say "at line L, column C"; keep that location in the InputError.
[[noreturn]] void throwLoadError(const fs::path& file, const std::string& error) {
    const std::string first = error.substr(0, error.find('\n'));
    std::smatch m;
    if (std::regex_search(first, m, std::regex("line ([0-9]+), column ([0-9]+)"))) {
        throw InputError(file, std::stoi(m[1]), std::stoi(m[2]), first);
    }
    throw InputError(file, first.empty() ? "tinygltf could not load the file" : first);
}

}  // namespace

Scene loadGltf(const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) throw InputError(file, "glTF file not found");
    detail::checkGltfMemoryBudget(file);  // before tinygltf reads the buffers
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warnText;
    const bool binary = file.extension() == ".glb" || file.extension() == ".GLB";
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warnText, file.string())
                           : loader.LoadASCIIFromFile(&model, &err, &warnText, file.string());
    if (!ok) throwLoadError(file, err);
    for (std::size_t start = 0, end; start < warnText.size(); start = end + 1) {
        end = std::min(warnText.find('\n', start), warnText.size());
        const std::string line = warnText.substr(start, end - start);
        // Images tinygltf cannot open are retried case-insensitively later, which warns if needed.
        const bool image = line.starts_with("File not found") || line.starts_with("Failed to load external 'uri' for image");
        if (!line.empty()) image ? spdlog::debug("{}: {}", file.string(), line) : spdlog::warn("{}: {}", file.string(), line);
    }
    Scene scene;
    scene.name = file.stem().string();
    scene.source = file;
    GltfBuilder(file, model, scene).build();
    if (scene.mesh.triangles.empty()) spdlog::warn("{}: the file has no triangles", file.string());
    return scene;
}

}  // namespace aamap
