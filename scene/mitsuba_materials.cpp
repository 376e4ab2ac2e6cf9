#include "scene/mitsuba_materials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "scene/text_util.h"

namespace aamap::mitsuba {
namespace {

constexpr int kMaxBsdfDepth = 16;  // nested twosided/mask/bumpmap wrappers

std::string at(const Element& e) { return fmt::format("{}:{}", e.file.string(), e.line); }

// Mitsuba's named indices of refraction (a common subset).
float namedIor(const Element& e, const std::string& name) {
    static const std::map<std::string, float> table = {
        {"vacuum", 1.0f},       {"air", 1.000277f},   {"helium", 1.000036f},  {"hydrogen", 1.000132f},
        {"water", 1.333f},      {"water ice", 1.31f}, {"acetone", 1.36f},     {"ethanol", 1.361f},
        {"fused quartz", 1.458f}, {"pyrex", 1.47f},   {"acrylic glass", 1.49f}, {"polypropylene", 1.49f},
        {"bk7", 1.5046f},       {"sodium chloride", 1.544f}, {"amber", 1.55f}, {"pet", 1.575f},
        {"diamond", 2.419f},    {"glycerol", 1.4729f}, {"bromine", 1.661f},    {"carbon tetrachloride", 1.461f},
        {"benzene", 1.501f},    {"silicone oil", 1.52045f},
    };
    const auto it = table.find(text::toLower(name));
    if (it == table.end()) fail(e, fmt::format("unknown index of refraction '{}'", name));
    return it->second;
}

float iorProperty(const Element& bsdf, const char* name, float fallback) {
    const Element* p = bsdf.property(name);
    if (p == nullptr) return fallback;
    if (p->tag == "string") return namedIor(*p, p->attribute("value"));
    return floatProperty(bsdf, name, fallback);
}

float fresnelF0(float eta) { return ((eta - 1.0f) * (eta - 1.0f)) / ((eta + 1.0f) * (eta + 1.0f)); }

glm::vec3 conductorF0(glm::vec3 eta, glm::vec3 k) {
    return ((eta - 1.0f) * (eta - 1.0f) + k * k) / ((eta + 1.0f) * (eta + 1.0f) + k * k);
}

// Normal-incidence reflectance of Mitsuba's named conductors (a common subset).
std::optional<glm::vec3> namedConductor(const std::string& name) {
    static const std::map<std::string, glm::vec3> table = {
        {"none", {1.0f, 1.0f, 1.0f}},        {"ag", {0.972f, 0.960f, 0.915f}}, {"al", {0.913f, 0.922f, 0.924f}},
        {"au", {1.000f, 0.766f, 0.336f}},    {"cu", {0.955f, 0.638f, 0.538f}}, {"cr", {0.549f, 0.556f, 0.554f}},
        {"fe", {0.562f, 0.565f, 0.578f}},    {"ti", {0.542f, 0.497f, 0.449f}}, {"ni", {0.660f, 0.609f, 0.526f}},
        {"pt", {0.673f, 0.637f, 0.585f}},    {"w", {0.504f, 0.498f, 0.478f}},
    };
    const auto it = table.find(text::toLower(name));
    if (it == table.end()) return std::nullopt;
    return it->second;
}

// GGX/Beckmann roughness alpha -> a Phong exponent with a similar highlight.
float phongExponent(float alpha) {
    const float a = std::max(alpha, 1e-3f);
    return std::max(2.0f / (a * a) - 2.0f, 0.0f);
}

float roughness(const Element& bsdf) {
    if (bsdf.property("alpha_u") != nullptr || bsdf.property("alpha_v") != nullptr) {
        return 0.5f * (floatProperty(bsdf, "alpha_u", 0.1f) + floatProperty(bsdf, "alpha_v", 0.1f));
    }
    return floatProperty(bsdf, "alpha", 0.1f);
}

}  // namespace

const Element& MaterialBuilder::resolve(const Element& e) const {
    if (e.tag != "ref") return e;
    const auto it = doc_.byId.find(e.id());
    if (it == doc_.byId.end()) fail(e, fmt::format("<ref id=\"{}\"> names nothing defined", e.id()));
    return *it->second;
}

std::uint32_t MaterialBuilder::material(const Element* bsdf, glm::vec3 radiance) {
    const auto key = std::make_pair(bsdf, std::array<float, 3>{radiance.x, radiance.y, radiance.z});
    if (const auto it = converted_.find(key); it != converted_.end()) return it->second;
    Material m;
    if (bsdf != nullptr) {
        m = convert(*bsdf, 0);
    } else {
        m.name = "default";
        m.kd = glm::vec3(0.5f);
        m.oneSided = true;  // Mitsuba's default BSDF is a one-sided diffuse
    }
    m.ke = radiance;
    if (radiance != glm::vec3(0.0f)) m.name += "+emitter";
    const auto index = static_cast<std::uint32_t>(scene_.materials.size());
    scene_.materials.push_back(std::move(m));
    converted_.emplace(key, index);
    return index;
}

int MaterialBuilder::bitmap(const Element& texture, bool coverage) {
    const Element& t = resolve(texture);
    if (t.tag != "texture") fail(t, fmt::format("expected a <texture>, found <{}>", t.tag));
    if (t.type() != "bitmap") {
        fail(t, fmt::format("texture type '{}' is not supported (only bitmap)", t.type()));
    }
    const std::string file = stringProperty(t, "filename", "");
    if (file.empty()) fail(t, "bitmap texture has no filename");
    if (t.property("to_uv") != nullptr || t.property("uscale") != nullptr || t.property("vscale") != nullptr ||
        t.property("uoffset") != nullptr) {
        warnings_.once("texture-transform", fmt::format("{}: texture coordinate transforms are ignored", at(t)));
    }
    // raw=true: 8-bit texels as they are (Mitsuba's default decodes sRGB); coverage is never decoded.
    const int index = coverage ? textures_.getCoverage(t.file.parent_path(), file, t.file)
                               : textures_.get(t.file.parent_path(), file, t.file, nullptr, booleanProperty(t, "raw", false));
    return index;
}

glm::vec3 MaterialBuilder::colourOrTexture(const Element& bsdf, const char* name, glm::vec3 fallback, int* texture) {
    const Element* p = bsdf.property(name);
    if (p != nullptr && (p->tag == "texture" || p->tag == "ref")) {
        const Element& t = resolve(*p);
        if (t.tag == "texture" && t.type() == "checkerboard") {
            warnings_.once("checkerboard", fmt::format("{}: checkerboard textures are replaced by their mean colour", at(t)));
            return 0.5f * (colourProperty(t, "color0", glm::vec3(0.4f), warnings_) + colourProperty(t, "color1", glm::vec3(0.2f), warnings_));
        }
        if (texture == nullptr) {
            warnings_.once(std::string("texture-") + name,
                           fmt::format("{}: a texture on '{}' is not supported; using white", at(t), name));
            return glm::vec3(1.0f);
        }
        *texture = bitmap(t, false);
        return *texture >= 0 ? glm::vec3(1.0f) : fallback;
    }
    return colourProperty(bsdf, name, fallback, warnings_);
}

Material MaterialBuilder::convert(const Element& element, int depth) {
    const Element& bsdf = resolve(element);
    if (bsdf.tag != "bsdf") fail(bsdf, fmt::format("expected a <bsdf>, found <{}>", bsdf.tag));
    if (depth > kMaxBsdfDepth) fail(bsdf, "BSDFs nest too deeply");
    const std::string type = bsdf.type();
    const auto nested = [&](bool required) -> const Element* {
        for (const Element& c : bsdf.children) {
            if (c.tag == "bsdf") return &c;
            if (c.tag == "ref" && resolve(c).tag == "bsdf") return &c;
        }
        if (required) fail(bsdf, fmt::format("'{}' needs a nested <bsdf>", type));
        return nullptr;
    };
    const auto approximated = [&](const std::string& message) { warnings_.once(type, fmt::format("{}: {}", at(bsdf), message)); };

    Material m;
    m.name = bsdf.id().empty() ? type : bsdf.id();
    // Mitsuba's reflecting BSDFs are one-sided unless wrapped in twosided (dielectrics are two-sided
    // by nature; wrappers inherit what they wrap).
    m.oneSided = type == "diffuse" || type == "plastic" || type == "roughplastic" || type == "conductor" ||
                 type == "roughconductor" || type == "phong" || type == "ward";
    if (type == "diffuse") {
        m.kd = colourOrTexture(bsdf, "reflectance", glm::vec3(0.5f), &m.diffuseTexture);
    } else if (type == "twosided") {
        m = convert(*nested(true), depth + 1);
        m.oneSided = false;
    } else if (type == "bumpmap" || type == "normalmap") {
        approximated(fmt::format("{} is ignored; the nested BSDF is used without it", type));
        m = convert(*nested(true), depth + 1);
    } else if (type == "coating" || type == "roughcoating" || type == "blendbsdf") {
        approximated(fmt::format("{} is approximated by its (first) nested BSDF", type));
        m = convert(*nested(true), depth + 1);
    } else if (type == "mask") {
        m = convert(*nested(true), depth + 1);
        m.alphaMode = AlphaMode::Mask;
        const Element* opacity = bsdf.property("opacity");
        if (opacity != nullptr && (opacity->tag == "texture" || opacity->tag == "ref")) {
            m.alphaTexture = bitmap(*opacity, true);
            m.alpha = 1.0f;
        } else {
            m.alpha = std::clamp(colourProperty(bsdf, "opacity", glm::vec3(0.5f), warnings_).g, 0.0f, 1.0f);
        }
    } else if (type == "null") {
        approximated("the null BSDF (pass-through) is a fully cut-out surface");
        m.alphaMode = AlphaMode::Mask;
        m.alpha = 0.0f;
    } else if (type == "plastic" || type == "roughplastic") {
        const float eta = iorProperty(bsdf, "int_ior", 1.49f) / iorProperty(bsdf, "ext_ior", 1.000277f);
        approximated(fmt::format("{}: the coating is approximated by Lambert plus a Phong lobe "
                                 "(ks = specular x F0, ns = 2/alpha^2 - 2)", type));
        m.kd = colourOrTexture(bsdf, "diffuse_reflectance", glm::vec3(0.5f), &m.diffuseTexture);
        m.ks = colourProperty(bsdf, "specular_reflectance", glm::vec3(1.0f), warnings_) * fresnelF0(eta);
        m.ns = phongExponent(type == "plastic" ? 0.01f : roughness(bsdf));
    } else if (type == "conductor" || type == "roughconductor") {
        glm::vec3 f0;
        if (bsdf.property("eta") != nullptr || bsdf.property("k") != nullptr) {
            f0 = conductorF0(colourProperty(bsdf, "eta", glm::vec3(0.0f), warnings_),
                             colourProperty(bsdf, "k", glm::vec3(1.0f), warnings_));
        } else {
            // 0.5's default material is copper, 2/3's a perfect mirror.
            const std::string name = stringProperty(bsdf, "material", doc_.majorVersion == 0 ? "Cu" : "none");
            const auto named = namedConductor(name);
            if (!named) fail(bsdf, fmt::format("unknown conductor material '{}'", name));
            f0 = *named;
        }
        f0 *= colourProperty(bsdf, "specular_reflectance", glm::vec3(1.0f), warnings_);
        const float alpha = type == "conductor" ? 0.0f : roughness(bsdf);
        approximated(fmt::format("{}: Fresnel reflectance is taken at normal incidence (F0){}", type,
                                 type == "roughconductor" ? "; roughness alpha -> a Phong lobe (ns = 2/alpha^2 - 2), "
                                                            "a mirror for alpha <= 0.05" : ""));
        m.ks = f0;
        if (alpha <= 0.05f) {
            m.kind = MaterialKind::Mirror;
        } else {
            m.kd = glm::vec3(0.0f);
            m.ns = phongExponent(alpha);
        }
    } else if (type == "dielectric" || type == "thindielectric" || type == "roughdielectric") {
        if (type == "roughdielectric") approximated("roughdielectric is approximated by a smooth solid dielectric");
        m.kind = MaterialKind::Glass;
        m.thin = type == "thindielectric";
        m.ior = iorProperty(bsdf, "int_ior", 1.5046f) / iorProperty(bsdf, "ext_ior", 1.000277f);
        m.ks = colourProperty(bsdf, "specular_transmittance", glm::vec3(1.0f), warnings_);
        m.kd = glm::vec3(0.0f);
    } else if (type == "phong" || type == "ward") {
        approximated(fmt::format("{} is approximated by Lambert plus a Phong lobe", type));
        m.kd = colourOrTexture(bsdf, "diffuse_reflectance", glm::vec3(0.5f), &m.diffuseTexture);
        m.ks = colourProperty(bsdf, "specular_reflectance", glm::vec3(0.2f), warnings_);
        m.ns = type == "phong" ? floatProperty(bsdf, "exponent", 30.0f) : phongExponent(floatProperty(bsdf, "alpha_u", 0.1f));
    } else {
        fail(bsdf, fmt::format("unknown BSDF type '{}'", type));
    }
    if (!bsdf.id().empty()) m.name = bsdf.id();
    return m;
}

}  // namespace aamap::mitsuba
