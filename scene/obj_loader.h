#pragma once
// Wavefront OBJ + MTL loading (tinyobjloader, behind a validating pre-scan).
//
// Conventions of the resulting Scene:
// - Materials: Kd, Ks, Ns, Ke, Ni; illum 3 and 5 -> Mirror, 7 -> Glass, else Diffuse. map_Kd is
//   loaded (case-insensitive file lookup, sRGB -> linear); a missing texture is a warning and Kd
//   is used. Faces without a material get an appended "default" material.
// - Normals: the file's vertex normals where a face has them all, else the flat face normal.
// - UVs: present if the file has any `vt`; stored with v = 0 at the top image row (the Texture
//   and glTF/Vulkan convention), i.e. OBJ's v is flipped. Faces without `vt` get (0, 0).
// - Polygons are triangulated; zero-area triangles are dropped and counted (one warning).
// - objectIds = tinyobjloader shape index (`o`/`g`); emissive triangles become AreaLights per
//   (shape, material).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace aamap {

struct ObjLoadReport {
    std::size_t degenerateTriangles = 0;  // zero-area triangles skipped
    std::vector<std::string> warnings;    // every warning, as also logged through spdlog
    std::vector<std::string> objectNames; // per objectId
};

// Throws InputError ("file:line:col: problem") for a missing or unreadable file, malformed
// numbers, non-finite coordinates, or out-of-range face indices, in the OBJ or its MTL files.
Scene loadObj(const std::filesystem::path& file, ObjLoadReport* report = nullptr);

}  // namespace aamap
