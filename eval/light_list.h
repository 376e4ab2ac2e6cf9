#pragma once
// The one parser of the light schema (docs/lights.md), for both a light file (a YAML list) and the
// config's inline `lights:` list. Every problem is an InputError at file:line:col of the entry.
// The schema itself and its conversion into scene lights live in scene/light_file.h.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "eval/yaml_reader.h"
#include "scene/light_file.h"

namespace aamap {

// A YAML list of light entries (null: none); `path` names the list in messages ("lights").
std::vector<LightSpec> readLightList(const yaml::Context& ctx, const YAML::Node& node, const std::string& path);

// A light file: a YAML list of light entries. Throws InputError (file:line:col) for bad YAML or a
// bad entry, and InputError(file) when it cannot be read.
std::vector<LightSpec> loadLightFile(const std::filesystem::path& file);

// Every key a light entry may have (for the config's --set paths).
std::vector<std::string> lightKeys();

// The entry with the keys its type uses, in schema order (canonical config JSON and its hash).
nlohmann::ordered_json lightJson(const LightSpec& light);

}  // namespace aamap
