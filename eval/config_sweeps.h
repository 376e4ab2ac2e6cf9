#pragma once
// Sweeps of settings outside the renders list: a list where a setting of the scene, the image,
// the Snapshot, the shading or the reference takes one value (`scene: [a.obj, b.obj]`,
// `snapshot: {blur_radius: [1, 2]}`) makes the experiment the cartesian product of those lists,
// or of groups of them that vary together (`zip`).
// Each point of it is one ordinary experiment (a *variant*); `aamap run` runs them one after the
// other into sub-folders of OUTDIR that share one render cache, so what a variant shares with
// another (the Snapshot when only the shading differs, a uniform render when only the Snapshot
// differs) is traced once. Internal to eval/config.cpp.
#include <functional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "eval/yaml_reader.h"

namespace aamap::detail {

struct ConfigSweep {
    std::string key;                // dotted: "scene", "snapshot.blur_radius"
    std::vector<YAML::Node> values;  // the list's items, with their marks (errors point at them)
};

// The sweeps of a config document, in document order. Fails (file:line:col) on an empty list or
// a value listed twice.
std::vector<ConfigSweep> findConfigSweeps(const yaml::Context& ctx, const YAML::Node& root);

// `zip: [[snapshot.blur_radius, snapshot.gain], ...]` at the top of the document: swept keys that
// vary together (lists of one length; the i-th variant takes the i-th value of each) rather than
// as a cartesian product. Returns the groups as indices into `sweeps`, every sweep in exactly
// one group (alone when not zipped), in the order of each group's first sweep, and removes the
// `zip` entry from the document (it is not a setting). Fails (file:line:col) on a key that is not
// swept, a key in two groups, a group of one, or lists of different lengths.
std::vector<std::vector<std::size_t>> takeZipGroups(const yaml::Context& ctx, YAML::Node& root,
                                                    const std::vector<ConfigSweep>& sweeps);

// Calls `variant(root, choice)` for each point of the cartesian product of the groups, the first
// group varying slowest (the sweeps of one group move together); `choice` holds the index of each
// sweep's value. The document is set in place (each swept entry refers to its chosen list item,
// so every node keeps its file:line mark; a deep copy would lose them) and stays so after the
// last call. Fails when there are more than `maxVariants`.
void forEachConfigVariant(const yaml::Context& ctx, YAML::Node& root, const std::vector<ConfigSweep>& sweeps,
                          const std::vector<std::vector<std::size_t>>& groups, std::size_t maxVariants,
                          const std::function<void(const YAML::Node& doc, const std::vector<std::size_t>& choice)>& variant);

}  // namespace aamap::detail
