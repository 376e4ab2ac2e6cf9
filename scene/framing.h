#pragma once
// Views made without a view file: from a camera description (position, look-at point, up,
// field of view), or one that frames the scene's bounds, as glTF viewers do for a model without
// a camera.
#include "scene/lights.h"
#include "scene/scene.h"

namespace aamap {

// A perspective view from `position` towards `lookAt`. horizontalFovDeg is the full angle across
// the image's width; the vertical angle follows from width : height, so the view fills a
// width x height image with square pixels. Throws std::invalid_argument when position equals
// lookAt, up is zero or parallel to the view direction, the angle is outside (0, 180) or the
// size is not positive.
View lookAtView(glm::vec3 position, glm::vec3 lookAt, glm::vec3 up, float horizontalFovDeg, int width, int height);

// A view of the whole scene for a width x height image: the bounds' centre seen from the front
// (+Z) and a little above (+Y up), far enough back that the bounding sphere fits the narrower
// of the 45-degree angles. An empty scene gets a view of the origin from (0, 0, 1).
View framingView(const Bounds& bounds, int width, int height);

}  // namespace aamap
