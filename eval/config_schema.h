#pragma once
// The scalar config sections, declared once each by the layer whose settings they are
// (passes/snapshot_params.h, tracer/shading_params.h, and here the ones eval/ owns), and what is
// generated from them: the reader (readSection), the --set keys and the --help lines.
#include <string>
#include <vector>

#include "core/params.h"
#include "eval/yaml_reader.h"

namespace aamap {

const std::vector<ParamSpec>& topLevelParams();  // view_index, threads
const std::vector<ParamSpec>& imageParams();
const std::vector<ParamSpec>& metricsParams();
const std::vector<ParamSpec>& reportParams();
const std::vector<ParamSpec>& timingParams();

struct ConfigSection {
    std::string path;  // "snapshot", "shading.cache"; "" for the top-level scalars
    const std::vector<ParamSpec>& params;
};
// Every schema-declared section, in the order of the config's documentation.
const std::vector<ConfigSection>& configSections();

// "snapshot.scale", ..., "view_index": every schema key as --set names it.
std::vector<std::string> sectionKeys();
// The --help lines of the sections ("  snapshot: {scale: 1.5, ..., map: luminance|geometric|combined}").
std::string sectionHelpLines();

// Reads every key of `params` from the mapping (absent keys: the default), with the config's
// file:line:col errors; the reader's allowed keys must include them.
ParamValues readSection(const yaml::Context& ctx, yaml::MapReader& map, const std::vector<ParamSpec>& params);
// The names of `params`, plus `extra` keys the section holds (a subsection).
std::vector<std::string> sectionKeyNames(const std::vector<ParamSpec>& params, std::vector<std::string> extra = {});

}  // namespace aamap
