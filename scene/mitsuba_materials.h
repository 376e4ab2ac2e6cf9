#pragma once
// Mitsuba BSDFs to aamap materials. What aamap represents exactly: diffuse (constant or bitmap
// reflectance), smooth conductors as mirrors, smooth and thin dielectrics as glass, mask as an alpha
// cut-out, and one-sidedness (a BSDF outside twosided is black from the back).
// What it approximates (one warning per kind, naming the approximation):
// - plastic/roughplastic: Lambert kd = diffuse_reflectance plus a Phong lobe ks =
//   specular_reflectance * F0(int_ior / ext_ior), ns = 2 / alpha^2 - 2 (smooth: alpha 0.01);
// - roughconductor: a Phong lobe ks = F0(eta, k) * specular_reflectance, ns = 2 / alpha^2 - 2
//   (a mirror when alpha <= 0.05); conductor: a mirror of tint F0;
// - roughdielectric: a smooth solid dielectric (thindielectric is exact: a thin Glass sheet);
// - bumpmap/normalmap: ignored (the nested BSDF is used); twosided: the nested BSDF (aamap shades
//   both sides); coating/roughcoating and blendbsdf: the (first) nested BSDF; null: fully cut out;
// - phong/ward: kd plus a Phong lobe.
// An unknown BSDF type is an error (file:line).
#include <array>
#include <cstdint>
#include <map>
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
    // A colour or a bitmap texture property: sets kd (or ks) and, for a texture, the texture index.
    glm::vec3 colourOrTexture(const Element& bsdf, const char* name, glm::vec3 fallback, int* texture);
    int bitmap(const Element& texture, bool coverage);

    const Document& doc_;
    Scene& scene_;
    Warnings& warnings_;
    TextureCache textures_;
    std::map<std::pair<const Element*, std::array<float, 3>>, std::uint32_t> converted_;
};

}  // namespace aamap::mitsuba
