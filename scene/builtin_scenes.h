#pragma once
// Scenes built in code, so that the default experiment and many tests need no files.
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace aamap {

// "cornell": the published Cornell box (www.graphics.cornell.edu/online/box/data.html), in metres,
//            with its camera as the default view.
// "spheres-plane": a diffuse, a mirror and a glass sphere on a floor under a square area light.
// Throws InputError naming the known scenes for any other name.
Scene builtinScene(std::string_view name);

std::vector<std::string> builtinSceneNames();

}  // namespace aamap
