#include "scene/mitsuba_materials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "scene/text_util.h"

namespace aamap::mitsuba {
namespace {

constexpr int kMaxBsdfDepth = 16;  // nested twosided/mask/bumpmap wrappers


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

// Mitsuba's named conductors as its RGB variants see them: each material's measured spectral eta
// and k (Mitsuba's data/ior/<name>.eta.spd, .k.spd) reduced to one linear sRGB value per channel
// the way Mitsuba 3 does when an rgb variant loads them (spectrum_list_to_srgb: the spectrum
// integrated against the CIE 1931 matching functions, XYZ to linear sRGB, negative channels
// clamped to 0). The values were read back from Mitsuba 3.6's llvm_ad_rgb variant (the BSDF's
// eta and k parameters after loading material=<name>); "none" is eta 0, k 1, a perfect mirror.
struct ComplexIor {
    glm::vec3 eta, k;
};
std::optional<ComplexIor> namedConductor(const std::string& name) {
    static const std::map<std::string, ComplexIor> table = {
        {"none", {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}}},
        {"a-C", {{2.944046f, 2.227136f, 1.968162f}, {0.887465f, 0.799299f, 0.815290f}}},
        {"Ag", {{0.155276f, 0.116728f, 0.138388f}, {4.828354f, 3.122222f, 2.146901f}}},
        {"Al", {{1.657501f, 0.880405f, 0.521244f}, {9.223811f, 6.269502f, 4.837004f}}},
        {"AlAs", {{3.605296f, 3.232938f, 2.216319f}, {0.000679f, 0.000000f, 0.007513f}}},
        {"AlSb", {{0.000000f, 4.139375f, 4.669254f}, {0.000000f, 0.094009f, 1.300570f}}},
        {"Au", {{0.143036f, 0.375307f, 1.442045f}, {3.982997f, 2.385556f, 1.603359f}}},
        {"Be", {{4.185012f, 3.185029f, 2.784061f}, {3.835466f, 3.010122f, 2.868994f}}},
        {"Cr", {{4.369668f, 2.916505f, 1.654905f}, {5.206547f, 4.231306f, 3.754699f}}},
        {"Cu", {{0.201005f, 0.923750f, 1.102215f}, {3.913262f, 2.453045f, 2.142090f}}},
        {"Cu2O", {{3.551773f, 2.949870f, 2.751875f}, {0.114207f, 0.193897f, 0.606134f}}},
        {"CuO", {{3.247541f, 2.447805f, 2.210220f}, {0.521090f, 0.570031f, 0.722179f}}},
        {"Hg", {{2.398939f, 1.440028f, 0.909570f}, {6.327587f, 4.371925f, 3.421764f}}},
        {"HgTe", {{4.779040f, 3.231196f, 2.659901f}, {1.631613f, 1.580810f, 1.729287f}}},
        {"Ir", {{3.086300f, 2.082191f, 1.617915f}, {5.592153f, 4.067088f, 3.267312f}}},
        {"K", {{0.064043f, 0.046410f, 0.038185f}, {2.104200f, 1.348940f, 0.913126f}}},
        {"Li", {{0.265791f, 0.195618f, 0.220949f}, {3.540155f, 2.311123f, 1.668607f}}},
        {"MgO", {{2.089584f, 1.650723f, 1.594879f}, {0.000000f, 0.000000f, 0.000000f}}},
        {"Mo", {{4.483974f, 3.525131f, 2.776310f}, {4.111437f, 3.420827f, 3.150607f}}},
        {"Na_palik", {{0.060269f, 0.056141f, 0.061988f}, {3.179273f, 2.112490f, 1.579041f}}},
        {"Nb", {{3.420074f, 2.790093f, 2.395629f}, {3.441395f, 2.737666f, 2.579746f}}},
        {"Ni_palik", {{2.367305f, 1.663373f, 1.467078f}, {4.498812f, 3.050153f, 2.345439f}}},
        {"Rh", {{2.585793f, 1.860216f, 1.554263f}, {6.782260f, 4.702987f, 3.976073f}}},
        {"Se", {{4.058311f, 2.842935f, 2.820853f}, {0.754050f, 0.638444f, 0.521808f}}},
        {"Se-e", {{5.722849f, 4.165736f, 4.081338f}, {0.871136f, 1.105157f, 1.565320f}}},
        {"SiC", {{3.172342f, 2.525972f, 2.479371f}, {0.000001f, 0.000000f, 0.000010f}}},
        {"Ta", {{2.062721f, 2.392939f, 2.627929f}, {2.408360f, 1.741486f, 1.947028f}}},
        {"Te", {{7.390234f, 4.482105f, 2.637106f}, {3.256022f, 3.527059f, 3.292054f}}},
        {"Te-e", {{7.508907f, 4.296429f, 2.369988f}, {5.583929f, 4.947205f, 3.997592f}}},
        {"TiC", {{3.700528f, 2.837422f, 2.582287f}, {3.265635f, 2.351589f, 2.172791f}}},
        {"TiN", {{1.648450f, 1.150516f, 1.379823f}, {3.368328f, 1.943498f, 1.102068f}}},
        {"TiO2", {{3.456610f, 2.801736f, 2.905175f}, {0.000105f, 0.000000f, 0.000653f}}},
        {"TiO2-e", {{3.106565f, 2.513168f, 2.582444f}, {0.000030f, 0.000000f, 0.000183f}}},
        {"V_palik", {{4.277582f, 3.512949f, 2.761071f}, {3.491301f, 2.889455f, 3.111522f}}},
        {"VC", {{3.657566f, 2.752736f, 2.532672f}, {3.068301f, 2.198687f, 1.963193f}}},
        {"VN", {{2.865602f, 2.119189f, 1.940091f}, {3.032243f, 2.056116f, 1.616306f}}},
        {"W", {{4.370817f, 3.300246f, 2.998407f}, {3.500641f, 2.604874f, 2.273233f}}},
    };
    // Mitsuba's names are case-sensitive file names; accept any case, as the rest of the loader does.
    for (const auto& [key, value] : table)
        if (text::toLower(key) == text::toLower(name)) return value;
    return std::nullopt;
}

// GGX/Beckmann roughness alpha -> a Phong exponent with a similar highlight (the Snapshot's stand-in).
float phongExponent(float alpha) {
    const float a = std::max(alpha, 1e-3f);
    return std::max(2.0f / (a * a) - 2.0f, 0.0f);
}

// Each microfacet BSDF's parameters (Mitsuba 3's names); others are ignored with a warning.
const std::set<std::string>& knownParameters(const std::string& type) {
    static const std::map<std::string, std::set<std::string>> table = {
        {"conductor", {"material", "eta", "k", "specular_reflectance"}},
        {"roughconductor",
         {"material", "eta", "k", "specular_reflectance", "distribution", "alpha", "alpha_u", "alpha_v",
          "sample_visible"}},
        {"plastic", {"int_ior", "ext_ior", "diffuse_reflectance", "specular_reflectance", "nonlinear"}},
        {"roughplastic",
         {"int_ior", "ext_ior", "diffuse_reflectance", "specular_reflectance", "nonlinear", "distribution", "alpha",
          "sample_visible"}},
        {"roughdielectric",
         {"int_ior", "ext_ior", "specular_reflectance", "specular_transmittance", "distribution", "alpha", "alpha_u",
          "alpha_v", "sample_visible"}},
    };
    static const std::set<std::string> none;
    const auto it = table.find(type);
    return it == table.end() ? none : it->second;
}

}  // namespace

void MaterialBuilder::warnUnknownParameters(const Element& bsdf, const std::string& type) {
    const std::set<std::string>& known = knownParameters(type);
    for (const Element& c : bsdf.children) {
        const std::string name = c.name();
        if (name.empty() || c.tag == "bsdf" || known.count(name) != 0) continue;
        warnings_.once(type + "-parameter-" + name,
                       fmt::format("{}: {} has no parameter '{}'; it is ignored", c.location(), type, name));
    }
}

// The microfacet distribution and roughness of a rough BSDF, with Mitsuba's rules: beckmann by
// default, alpha 0.1; alpha_u and alpha_v come together and exclude alpha.
void MaterialBuilder::microfacetParameters(const Element& bsdf, Material& m, bool anisotropic) {
    const std::string distribution = text::toLower(stringProperty(bsdf, "distribution", "beckmann"));
    if (distribution == "ggx") {
        m.distribution = MicrofacetType::GGX;
    } else if (distribution == "beckmann") {
        m.distribution = MicrofacetType::Beckmann;
    } else {
        fail(*bsdf.property("distribution"),
             fmt::format("unknown microfacet distribution '{}' (beckmann or ggx)", distribution));
    }
    const bool hasU = bsdf.property("alpha_u") != nullptr, hasV = bsdf.property("alpha_v") != nullptr;
    if (hasU || hasV) {
        if (!anisotropic) fail(bsdf, fmt::format("{} is isotropic: alpha_u / alpha_v are not supported", bsdf.type()));
        if (!hasU || !hasV) fail(bsdf, "alpha_u and alpha_v must both be given");
        if (bsdf.property("alpha") != nullptr) fail(bsdf, "give either alpha or alpha_u / alpha_v, not both");
        const auto read = [&](const char* name) {
            const Element* p = bsdf.property(name);
            if (p->tag != "texture" && p->tag != "ref") return floatProperty(bsdf, name, 0.1f);
            // Anisotropic textured roughness: each axis at its texture's mean.
            const float mean = texturedRoughness(*p, m);
            m.roughnessTexture = -1;
            warnings_.once("textured-alpha-uv", fmt::format("{}: a textured {} is replaced by its mean, {}", p->location(),
                                                            name, mean));
            return mean;
        };
        m.alphaU = read("alpha_u");
        m.alphaV = read("alpha_v");
    } else if (const Element* alpha = bsdf.property("alpha"); alpha != nullptr && (alpha->tag == "texture" || alpha->tag == "ref")) {
        m.alphaU = m.alphaV = texturedRoughness(*alpha, m);
    } else {
        m.alphaU = m.alphaV = floatProperty(bsdf, "alpha", 0.1f);
    }
    for (const char* name : {"alpha", "alpha_u", "alpha_v"}) {
        const Element* p = bsdf.property(name);
        if (p != nullptr && (p->tag == "texture" || p->tag == "ref")) continue;
        const float value = name[5] == 'u' ? m.alphaU : name[5] == 'v' ? m.alphaV : m.alphaU;
        if (p != nullptr && !(std::isfinite(value) && value >= 0.0f))
            fail(*p, fmt::format("roughness {} = {} is out of range (a finite alpha >= 0)", name, value));
    }
    if (!booleanProperty(bsdf, "sample_visible", true))
        warnings_.once("sample_visible", fmt::format("{}: sample_visible=false is ignored: visible normals are always "
                                                     "sampled (the image is the same, the noise differs)", bsdf.location()));
}

// A roughness texture (a bitmap; its texel's luminance is alpha, as Mitsuba's eval_1): sets
// m.roughnessTexture and returns the texture's mean alpha. Another texture type is a warning and
// Mitsuba's default 0.1.
float MaterialBuilder::texturedRoughness(const Element& property, Material& m) {
    const Element& t = resolve(property);
    if (t.tag != "texture" || t.type() != "bitmap") {
        warnings_.once("textured-alpha-type", fmt::format("{}: only a bitmap texture can give the roughness; alpha "
                                                          "0.1 is used",
                                                          t.location()));
        return 0.1f;
    }
    const int index = bitmap(t, false);
    if (index < 0) return 0.1f;  // unreadable: the loader has warned
    const Texture& tex = scene_.textures[static_cast<std::size_t>(index)];
    const std::size_t texels = static_cast<std::size_t>(tex.width) * static_cast<std::size_t>(tex.height);
    double sum = 0.0;
    for (std::size_t i = 0; i < texels && 4 * i + 2 < tex.rgba.size(); ++i)
        sum += 0.212671 * tex.rgba[4 * i] + 0.715160 * tex.rgba[4 * i + 1] + 0.072169 * tex.rgba[4 * i + 2];
    const float mean = texels > 0 ? static_cast<float>(sum / static_cast<double>(texels)) : 0.1f;
    if (!(std::isfinite(mean) && mean >= 0.0f)) fail(t, fmt::format("roughness texture mean {} is out of range", mean));
    m.roughnessTexture = index;
    return mean;
}

// int_ior / ext_ior (numbers or Mitsuba's names): their ratio, checked as Mitsuba does.
float MaterialBuilder::relativeIor(const Element& bsdf, float interior) {
    const float in = iorProperty(bsdf, "int_ior", interior), out = iorProperty(bsdf, "ext_ior", 1.000277f);
    if (!(std::isfinite(in) && std::isfinite(out) && in > 0.0f && out > 0.0f) || in == out) {
        const Element* p = bsdf.property("int_ior");
        fail(p != nullptr ? *p : bsdf,
             fmt::format("int_ior {} and ext_ior {} must be positive and differ", in, out));
    }
    return in / out;
}

namespace {

// What a Blend component can be: one non-delta lobe set that the tracer evaluates without a
// texture (a Lambert or Phong colour, a rough conductor or plastic), not a blend itself.
bool blendable(const Material& c) {
    if (c.diffuseTexture >= 0 || c.alphaMode != AlphaMode::Opaque || !c.blend.empty()) return false;
    if (c.normalMap >= 0 || c.bumpMap >= 0 || c.roughnessTexture >= 0) return false;  // one frame, one alpha per hit
    if (c.model == BsdfModel::Conductor || c.model == BsdfModel::Plastic) return c.alphaU > 0.0f && c.alphaV > 0.0f;
    return c.model == BsdfModel::Classic && c.kind == MaterialKind::Diffuse;
}

}  // namespace

Material MaterialBuilder::blend(const Element& bsdf, int depth) {
    std::vector<const Element*> parts;
    for (const Element& c : bsdf.children)
        if (c.tag == "bsdf" || (c.tag == "ref" && resolve(c).tag == "bsdf")) parts.push_back(&c);
    if (parts.size() != 2) fail(bsdf, fmt::format("blendbsdf needs two nested BSDFs, not {}", parts.size()));
    float w = 0.5f;
    const Element* weight = bsdf.property("weight");
    if (weight == nullptr) fail(bsdf, "blendbsdf needs a weight");
    if (weight->tag == "texture" || weight->tag == "ref") {
        warnings_.once("blend-texture", fmt::format("{}: a textured blendbsdf weight is replaced by 0.5", weight->location()));
    } else {
        w = floatProperty(bsdf, "weight", 0.5f);
        if (!(w >= 0.0f && w <= 1.0f)) fail(*weight, fmt::format("blendbsdf weight {} is not in [0, 1]", w));
    }
    Material a = convert(*parts[0], depth + 1), b = convert(*parts[1], depth + 1);
    if (!blendable(a) || !blendable(b)) {
        warnings_.once("blendbsdf", fmt::format("{}: a blendbsdf of a smooth, textured, masked or blended BSDF is "
                                                "approximated by the component of larger weight",
                                                bsdf.location()));
        return w > 0.5f ? b : a;
    }
    Material m;
    m.model = BsdfModel::Blend;
    m.kind = MaterialKind::Diffuse;
    m.blendWeight = w;
    // The Snapshot's stand-in: the components' Lambert and Phong parameters mixed.
    m.kd = (1.0f - w) * a.kd + w * b.kd;
    m.ks = (1.0f - w) * a.ks + w * b.ks;
    m.ns = glm::max(a.ns, b.ns);
    // Each component is black from its own back; a mixed pair is one-sided only when both are.
    m.oneSided = a.oneSided && b.oneSided;
    m.blend = {std::move(a), std::move(b)};
    return m;
}

// normalmap / bumpmap: the nested BSDF with the map's texture in normalMap or bumpMap. What is
// missing or unusable is a warning (file:line) that says what is rendered instead.
Material MaterialBuilder::perturbation(const Element& bsdf, int depth) {
    const std::string type = bsdf.type();
    const Element* inner = nullptr;
    const Element* texture = nullptr;
    for (const Element& c : bsdf.children) {
        if (c.tag != "bsdf" && c.tag != "texture" && c.tag != "ref") continue;
        const Element& r = resolve(c);
        const Element*& slot = r.tag == "bsdf" ? inner : texture;
        if (r.tag != "bsdf" && r.tag != "texture") continue;
        if (slot != nullptr) {
            warnings_.once(type + "-extra-" + r.tag, fmt::format("{}: {} takes one nested <{}>; this one is ignored",
                                                                 c.location(), type, r.tag));
            continue;
        }
        slot = &c;
    }
    Material m;
    if (inner != nullptr) {
        m = convert(*inner, depth + 1);
    } else {
        warnings_.once(type + "-no-bsdf", fmt::format("{}: {} has no nested <bsdf>; Mitsuba's default (a one-sided "
                                                      "diffuse of reflectance 0.5) is used",
                                                      bsdf.location(), type));
        m.name = "default";
        m.kd = glm::vec3(0.5f);
        m.oneSided = true;
    }
    if (m.normalMap >= 0 || m.bumpMap >= 0) {
        warnings_.once("nested-maps", fmt::format("{}: a normal or bump map inside another one is ignored; the outer "
                                                  "{} is used alone",
                                                  bsdf.location(), type));
        m.normalMap = m.bumpMap = -1;
        m.mapMirroredOnBack = false;
    }
    const bool bump = type == "bumpmap";
    const float scale = bump ? floatProperty(bsdf, "scale", 1.0f) : 1.0f;
    if (!std::isfinite(scale)) fail(*bsdf.property("scale"), fmt::format("bumpmap scale {} is not finite", scale));
    if (texture == nullptr) {
        warnings_.once(type + "-no-texture", fmt::format("{}: {} has no nested <texture>; the nested BSDF is used "
                                                         "without it",
                                                         bsdf.location(), type));
        return m;
    }
    const Element& t = resolve(*texture);
    if (t.type() != "bitmap") {
        warnings_.once(type + "-texture-type", fmt::format("{}: a {} texture for {} is not supported (only bitmap); "
                                                           "the nested BSDF is used without the map",
                                                           t.location(), t.type(), type));
        return m;
    }
    if (!bump && texture->name() != "normalmap" && t.name() != "normalmap")
        warnings_.once("normalmap-name", fmt::format("{}: Mitsuba names a normal map's texture 'normalmap'; this "
                                                     "one is used as the map",
                                                     texture->location()));
    if (!bump && !booleanProperty(t, "raw", false))
        warnings_.once("normalmap-srgb", fmt::format("{}: the normal map is decoded from sRGB (raw is false, as Mitsuba "
                                                     "does by default); normal maps usually want raw=true",
                                                     t.location()));
    const int index = bitmap(t, false);
    if (index < 0) return m;  // unreadable: the loader has warned; no map
    (bump ? m.bumpMap : m.normalMap) = index;
    m.bumpScale = scale;
    return m;
}

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
        warnings_.once("texture-transform", fmt::format("{}: texture coordinate transforms are ignored", t.location()));
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
            warnings_.once("checkerboard", fmt::format("{}: checkerboard textures are replaced by their mean colour", t.location()));
            return 0.5f * (colourProperty(t, "color0", glm::vec3(0.4f), warnings_) + colourProperty(t, "color1", glm::vec3(0.2f), warnings_));
        }
        if (texture == nullptr) {
            warnings_.once(std::string("texture-") + name,
                           fmt::format("{}: a texture on '{}' is not supported; using white", t.location(), name));
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
    const auto approximated = [&](const std::string& message) { warnings_.once(type, fmt::format("{}: {}", bsdf.location(), message)); };

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
        // twosided mirrors the directions it hands a map inside it (docs/tracer.md).
        m.mapMirroredOnBack = m.normalMap >= 0 || m.bumpMap >= 0;
    } else if (type == "bumpmap" || type == "normalmap") {
        m = perturbation(bsdf, depth);
    } else if (type == "coating" || type == "roughcoating") {
        approximated(fmt::format("{} is approximated by its (first) nested BSDF", type));
        m = convert(*nested(true), depth + 1);
    } else if (type == "blendbsdf") {
        m = blend(bsdf, depth);
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
        // The tracer shades Mitsuba's model (BsdfModel::Plastic); kd, ks, ns are the Snapshot's
        // Lambert + Phong stand-in (ks = specular x F0, ns = 2 / alpha^2 - 2).
        warnUnknownParameters(bsdf, type);
        const float eta = relativeIor(bsdf, 1.49f);
        m.model = BsdfModel::Plastic;
        m.ior = eta;
        m.nonlinear = booleanProperty(bsdf, "nonlinear", false);
        if (type == "roughplastic") microfacetParameters(bsdf, m, false);
        if (m.roughnessTexture >= 0)
            warnings_.once("textured-alpha-plastic",
                           fmt::format("{}: Mitsuba 3 takes no texture for roughplastic's alpha; aamap shades it per "
                                       "texel",
                                       bsdf.property("alpha")->location()));
        m.kd = colourOrTexture(bsdf, "diffuse_reflectance", glm::vec3(0.5f), &m.diffuseTexture);
        m.specularReflectance = colourProperty(bsdf, "specular_reflectance", glm::vec3(1.0f), warnings_);
        m.ks = m.specularReflectance * fresnelF0(eta);
        m.ns = phongExponent(type == "plastic" ? 0.01f : 0.5f * (m.alphaU + m.alphaV));
    } else if (type == "conductor" || type == "roughconductor") {
        // The tracer shades Mitsuba's model (BsdfModel::Conductor); ks = F0 and ns are the
        // Snapshot's stand-in (a mirror when alpha <= 0.05).
        warnUnknownParameters(bsdf, type);
        const bool hasEtaK = bsdf.property("eta") != nullptr || bsdf.property("k") != nullptr;
        const Element* material = bsdf.property("material");
        if (hasEtaK) {
            if (material != nullptr && text::toLower(stringProperty(bsdf, "material", "none")) != "none")
                fail(*material, "give either eta / k or material, not both");
            m.eta = colourProperty(bsdf, "eta", glm::vec3(0.0f), warnings_, SpectrumUse::Unbounded);
            m.k = colourProperty(bsdf, "k", glm::vec3(1.0f), warnings_, SpectrumUse::Unbounded);
            for (int c = 0; c < 3; ++c)
                if (!(std::isfinite(m.eta[c]) && std::isfinite(m.k[c]) && m.eta[c] >= 0.0f && m.k[c] >= 0.0f))
                    fail(*bsdf.property(bsdf.property("eta") != nullptr ? "eta" : "k"),
                         fmt::format("conductor index eta = {}, k = {} is out of range (finite, >= 0)", m.eta[c], m.k[c]));
        } else {
            // 0.5's default material is copper, 3's a perfect mirror.
            const std::string name = stringProperty(bsdf, "material", doc_.majorVersion == 0 ? "Cu" : "none");
            const auto named = namedConductor(name);
            if (!named) fail(material != nullptr ? *material : bsdf, fmt::format("unknown conductor material '{}'", name));
            m.eta = named->eta;
            m.k = named->k;
        }
        m.model = BsdfModel::Conductor;
        if (type == "roughconductor") microfacetParameters(bsdf, m, true);
        m.specularReflectance = colourProperty(bsdf, "specular_reflectance", glm::vec3(1.0f), warnings_);
        m.ks = conductorF0(m.eta, m.k) * m.specularReflectance;
        const float alpha = 0.5f * (m.alphaU + m.alphaV);
        if (alpha <= 0.05f) {
            m.kind = MaterialKind::Mirror;
        } else {
            m.kd = glm::vec3(0.0f);
            m.ns = phongExponent(alpha);
        }
    } else if (type == "dielectric" || type == "thindielectric" || type == "roughdielectric") {
        m.kind = MaterialKind::Glass;
        m.thin = type == "thindielectric";
        if (type == "roughdielectric") {
            // Path mode samples the microfacet interface; the Snapshot and the direct and cache
            // modes' specular branches see it smooth.
            warnUnknownParameters(bsdf, type);
            m.model = BsdfModel::Dielectric;
            m.ior = relativeIor(bsdf, 1.5046f);
            microfacetParameters(bsdf, m, true);
            if (m.roughnessTexture >= 0) {
                m.roughnessTexture = -1;
                warnings_.once("textured-alpha-dielectric",
                               fmt::format("{}: a textured roughdielectric alpha is replaced by its mean, {}",
                                           bsdf.property("alpha")->location(), m.alphaU));
            }
            m.specularReflectance = colourProperty(bsdf, "specular_reflectance", glm::vec3(1.0f), warnings_);
        } else {
            m.ior = iorProperty(bsdf, "int_ior", 1.5046f) / iorProperty(bsdf, "ext_ior", 1.000277f);
        }
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
