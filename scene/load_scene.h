#pragma once
// One entry point from a scene spec to the Scene model.
#include <string>

#include "scene/scene.h"

namespace aamap {

// spec: "builtin:<name>" (see builtin_scenes.h) or a file path: .obj, .gltf, .glb or .xml (a
// Mitsuba scene, scene/mitsuba_loader.h; case-insensitive extension). Logs the triangle count and
// the bounds. For an OBJ, a Radiance view file "<stem>.vf" next to it supplies
// Scene::views. Triangles wound against their vertex normals are turned to face where the normals
// point (scene/mesh_orientation.h). Throws InputError for unknown formats and for anything the loaders reject.
Scene loadScene(const std::string& spec);

}  // namespace aamap
