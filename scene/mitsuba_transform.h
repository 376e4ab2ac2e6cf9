#pragma once
// Mitsuba <transform> elements to matrices. The children apply in order, each after the ones
// before it (M = child_n * ... * child_1): translate, rotate (axis and angle in degrees), scale,
// matrix (16 numbers row by row, or 9 for the linear part) and lookat (origin, target, up; the
// local +Z looks at the target, +Y is up, +X is to the left, as Mitsuba's cameras have it).
#include <glm/mat4x4.hpp>

#include "scene/mitsuba_xml.h"

namespace aamap::mitsuba {

// Throws InputError (file:line) for an unknown child, malformed numbers, a zero rotation axis, a
// lookat whose up is parallel to its direction, or a singular result.
glm::mat4 readTransform(const Element& transform);

// The transform property `name` of `parent` (to_world, say), or the identity when absent.
glm::mat4 transformProperty(const Element& parent, const char* name = "to_world");

}  // namespace aamap::mitsuba
