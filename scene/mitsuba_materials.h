#pragma once
// Mitsuba BSDFs to aamap materials. What aamap represents exactly: diffuse (constant or bitmap
// reflectance), smooth and thin dielectrics as glass, mask as an alpha cut-out, one-sidedness (a
// BSDF outside twosided is black from the back), and for the tracer Mitsuba's conductor,
// roughconductor, plastic and roughplastic (Material::model, docs/tracer.md "BSDFs"; the Snapshot
// shows them through kd, ks, ns: Lambert plus a Phong lobe, ns = 2 / alpha^2 - 2, ks = F0).
// Their unknown parameters are warnings, out-of-range roughness or indices errors (file:line); a
// bitmap `alpha` is a per-texel roughness (Material::roughnessTexture).
// blendbsdf of two rough or diffuse BSDFs with a float weight is exact in the tracer (BsdfModel::Blend).
// roughdielectric is a Glass with a microfacet interface that path mode samples (the direct and
// cache modes and the Snapshot see it smooth); thindielectric is exact (a thin Glass sheet).
// What it approximates (one warning per kind, naming the approximation):
// normalmap and bumpmap are exact: the nested BSDF with Material::normalMap / bumpMap, which tilt
// the shading normal as Mitsuba 3 does (a missing texture or BSDF is a warning, file:line).
// - twosided: the nested BSDF (aamap shades both sides); coating/roughcoating: the (first) nested BSDF; blendbsdf of a smooth, textured or
//   masked BSDF (or with a textured weight): the component of larger weight (weight 0.5); null:
//   fully cut out;
// - phong/ward: kd plus a Phong lobe.
// An unknown BSDF type is an error (file:line).
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "scene/mitsuba_xml.h"
#include "scene/scene.h"
#include "scene/texture_loader.h"

namespace aamap::mitsuba {

class MaterialBuilder {
public:
    MaterialBuilder(const Document& doc, Scene& scene, Warnings& warnings)
        : doc_(doc), scene_(scene), warnings_(warnings), textures_(scene.textures) {}

    // The index in Scene::materials for a <bsdf> (nullptr: Mitsuba's default, diffuse 0.5),
    // emitting `radiance` (an area emitter on the shape; zero for none). Each distinct pair is
    // converted once.
    std::uint32_t material(const Element* bsdf, glm::vec3 radiance);

    // Follows a <ref> to the element it names (file:line error if there is none).
    const Element& resolve(const Element& e) const;

private:
    Material convert(const Element& bsdf, int depth);
    // blendbsdf: the two components and the weight (Material::blend), or, where the tracer cannot
    // mix them, the component of larger weight with a warning.
    Material blend(const Element& bsdf, int depth);
    // normalmap / bumpmap: the nested BSDF with its map (warnings, file:line, for what is missing).
    Material perturbation(const Element& bsdf, int depth);
    // A colour or a bitmap texture property: sets kd (or ks) and, for a texture, the texture index.
    glm::vec3 colourOrTexture(const Element& bsdf, const char* name, glm::vec3 fallback, int* texture);
    int bitmap(const Element& texture, bool coverage);
    // Microfacet BSDFs: warn (file:line) for each parameter the type does not have.
    void warnUnknownParameters(const Element& bsdf, const std::string& type);
    // distribution, alpha or alpha_u / alpha_v (anisotropic types only) into m; errors at file:line.
    void microfacetParameters(const Element& bsdf, Material& m, bool anisotropic);
    // A bitmap roughness texture into m.roughnessTexture; returns its mean alpha (warnings, file:line).
    float texturedRoughness(const Element& property, Material& m);
    // int_ior / ext_ior: positive and different, or an error at file:line.
    float relativeIor(const Element& bsdf, float interior);

    const Document& doc_;
    Scene& scene_;
    Warnings& warnings_;
    TextureCache textures_;
    std::map<std::pair<const Element*, std::array<float, 3>>, std::uint32_t> converted_;
};

}  // namespace aamap::mitsuba
