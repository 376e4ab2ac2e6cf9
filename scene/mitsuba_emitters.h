#pragma once
// Mitsuba emitters and the perspective sensor, into the scene model.
// - area (inside a shape): its radiance becomes the shape's emission (one-sided, along the normal).
// - point: position (or to_world's origin), intensity in W/sr -> a PointLight.
// - spot: to_world (the cone looks down local +Z), intensity, cutoff_angle (20 deg) and
//   beam_width (3/4 of cutoff) -> a spot PointLight; between the two cones aamap's smooth glTF
//   falloff replaces Mitsuba's linear one (one warning).
// - directional: direction (or to_world's +Z), irradiance -> a DirectionalLight.
// - envmap: filename (EXR or Radiance HDR), scale, to_world's rotation -> Scene::environment.
// - constant: radiance -> Scene::environment without a map.
// - perspective (and thinlens, as a pinhole): fov with fov_axis (x, y, diagonal, smaller,
//   larger) or focal_length (35 mm film), to_world, the film's width and height (768 x 576 by
//   default) -> Scene::views and Scene::imageWidth/imageHeight. near_clip and far_clip are read
//   but the renderers choose their own planes from the scene's bounds.
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "scene/mitsuba_xml.h"
#include "scene/scene.h"

namespace aamap::mitsuba {

// The radiance of an <emitter type="area"> (error for another type inside a shape).
glm::vec3 areaRadiance(const Element& emitter, Warnings& warnings);

// A scene-level emitter (point, spot, directional, envmap, constant). Throws InputError (file:line) for an unknown type, a
// second environment, or an unreadable map.
void addEmitter(const Element& emitter, Scene& scene, Warnings& warnings);

// A <sensor>: its view and film size. Throws InputError for an unsupported sensor type.
void addSensor(const Element& sensor, Scene& scene, Warnings& warnings);

}  // namespace aamap::mitsuba
