#pragma once
// glTF 2.0 (.gltf, .glb) loading through tinygltf.
//
// What maps to what:
// - The default scene's node tree (matrix or TRS transforms) is flattened into world space;
//   each node instance with a mesh gets its own objectId. Mirrored transforms flip the winding.
// - Triangles, strips and fans; points and lines are skipped with a warning. Missing normals ->
//   flat normals. TEXCOORD_0 -> uvs (glTF's v = 0 is already the top row).
// - Materials: baseColorFactor * (1 - metallic) -> kd, baseColor * metallic -> ks, roughness ->
//   Phong ns = 2 / roughness^4 - 2; baseColorTexture -> diffuseTexture (sRGB -> linear);
//   emissiveFactor (x KHR_materials_emissive_strength) -> ke, which makes area lights;
//   KHR_materials_transmission > 0 -> Glass (ior from KHR_materials_ior); metallic >= 0.99 with
//   roughness <= 0.05 -> Mirror. Texture transforms and other textures are ignored.
// - Perspective cameras -> Scene::views (vv = yfov, vh from aspectRatio, else vv).
// - KHR_lights_punctual point and spot lights -> PointLights with intensity = colour * intensity
//   taken as W/sr (no photometric conversion); spots keep their cone (axis = the node's -Z,
//   innerConeAngle / outerConeAngle, glTF's smooth falloff); directional ones are skipped.
#include <filesystem>

#include "scene/scene.h"

namespace aamap {

// Throws InputError for a missing or malformed file (with line and column for JSON syntax errors)
// and for out-of-range accessors, buffers or indices.
Scene loadGltf(const std::filesystem::path& file);

}  // namespace aamap
