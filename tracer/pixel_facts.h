#pragma once
// Computes the pixel facts (core/pixel_facts.h) for a view: tracer-internal, reached through
// Tracer::pixelFacts.
#include <cstdint>
#include <vector>

#include "scene/camera.h"
#include "tracer/embree_scene.h"
#include "tracer/lights.h"
#include "core/pixel_facts.h"

namespace aamap {

// objects: the object id of each triangle (Scene::mesh.objectIds; empty: one object). threads 0:
// all hardware threads. The result does not depend on the thread count.
PixelFacts tracePixelFacts(const EmbreeScene& geometry, const LightSet& lights, const std::vector<std::uint32_t>& objects,
                           const PinholeCamera& camera, int width, int height, int threads);

}  // namespace aamap
