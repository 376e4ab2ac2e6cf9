#pragma once
#include <initializer_list>
// Readers for the config sections that grew their own rules: renders (with sweeps), reference,
// metrics, report. Internal to eval/config.cpp.
#include <string>
#include <vector>

#include "eval/config.h"
#include "eval/yaml_reader.h"

namespace aamap::detail {

// Render names become file stems beside these outputs; a render may not shadow them.
const std::vector<std::string>& reservedNames();

// Expands the renders list (cartesian product of list values) and checks names.
std::vector<RenderConfig> readRenders(const yaml::Context& ctx, const YAML::Node& renders);
ReferenceConfig readReference(const yaml::Context& ctx, const YAML::Node& node, const std::vector<RenderConfig>& renders);
MetricsConfig readMetrics(const yaml::Context& ctx, const YAML::Node& node);
ReportConfig readReport(const yaml::Context& ctx, const YAML::Node& node);
// `camera`: position and look_at required, up (0, 1, 0) and fov (45) optional.
CameraConfig readCamera(const yaml::Context& ctx, const YAML::Node& node);

std::string lower(std::string s);
bool readBool(const yaml::Context& ctx, yaml::MapReader& m, const std::string& key, bool fallback);
// A shading mode by shading.mode's names (unset when absent); an unknown name fails at its file:line:col.
std::optional<ShadingMode> readShadingMode(const yaml::Context& ctx, yaml::MapReader& m, const std::string& key);

}  // namespace aamap::detail
