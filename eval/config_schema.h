#pragma once
// The scalar config sections, declared once each by the layer whose settings they are
// (passes/snapshot_params.h, tracer/shading_params.h, and here the ones eval/ owns), and what is
// generated from them: the reader (readSection), the --set keys and the --help lines.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/params.h"
#include "core/schema.h"
#include "eval/config.h"
#include "eval/yaml_reader.h"

namespace aamap {

const Schema<ExperimentConfig>& topLevelSchema();  // view_index, threads
const Schema<ImageConfig>& imageSchema();
const std::vector<ParamSpec>& topLevelParams();  // topLevelSchema().specs()
const std::vector<ParamSpec>& imageParams();     // imageSchema().specs()
// The sections eval/ owns, each bound to its struct (eval/config.h).
const Schema<MetricsConfig>& metricsSchema();
const Schema<ReportConfig>& reportSchema();
const Schema<TimingConfig>& timingSchema();
const std::vector<ParamSpec>& metricsParams();  // metricsSchema().specs()
const std::vector<ParamSpec>& reportParams();
const std::vector<ParamSpec>& timingParams();

struct ConfigSection {
    std::string path;  // "snapshot", "shading.cache"; "" for the top-level scalars
    const std::vector<ParamSpec>& params;
    // Every key's value in a config, read from the field the schema binds it to, and only the keys
    // not at their default (Schema::values and Schema::changed of the section's part of the config).
    std::function<ParamValues(const ExperimentConfig&)> values, changed;
};
// Every schema-declared section, in the order of the config's documentation.
const std::vector<ConfigSection>& configSections();

// "snapshot.scale", ..., "view_index": every schema key as --set names it.
std::vector<std::string> sectionKeys();
// docs/config.md's table of every schema key (type, range, default, doc), as `aamap run
// --list-keys` prints it and tools/update_cli_docs.py copies it.
std::string configKeysMarkdown();
// The --help lines of the sections ("  snapshot: {scale: 1.5, ..., map: luminance|geometric|combined}").
std::string sectionHelpLines();

// Reads every key of `params` from the mapping (absent keys: the default), with the config's
// file:line:col errors; the reader's allowed keys must include them.
ParamValues readSection(const yaml::Context& ctx, yaml::MapReader& map, const std::vector<ParamSpec>& params);
// The generic walk of a bound section: every key of `schema` read from the mapping (absent keys
// keep the struct's value, its default) into the struct's fields.
template <class T>
void readSection(const yaml::Context& ctx, yaml::MapReader& map, const Schema<T>& schema, T& out) {
    schema.fill(out, readSection(ctx, map, schema.specs()));
}

// Typed values as JSON: an int stays an integer, a real a number, a choice its name.
nlohmann::ordered_json toJson(const ParamValues& values);
// A bound section as JSON: every key in declaration order (the canonical form), or (forKey) only
// the keys not at their default, so that a key added later leaves the cache keys of the configs
// that do not set it as they were.
template <class T>
nlohmann::ordered_json sectionJson(const Schema<T>& schema, const T& value, bool forKey) {
    return toJson(forKey ? schema.changed(value) : schema.values(value));
}

// The names of `params`, plus `extra` keys the section holds (a subsection).
std::vector<std::string> sectionKeyNames(const std::vector<ParamSpec>& params, std::vector<std::string> extra = {});

}  // namespace aamap
