#pragma once
// Reads an environment map (an equirectangular EXR or Radiance HDR, linear RGB) into an
// EnvironmentLight: the one reader behind the Mitsuba `envmap` emitter and the light file's
// `environment` type. 8-bit images are refused: they hold no radiance.
#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace aamap {

// Fills env.mapPath, mapWidth, mapHeight and map. Returns false with `error` set (what is wrong,
// without a file position: the caller knows where the map was named).
bool loadEnvironmentMap(const std::filesystem::path& path, EnvironmentLight& env, std::string& error);

}  // namespace aamap
