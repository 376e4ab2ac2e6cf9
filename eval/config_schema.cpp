#include "eval/config_schema.h"

#include <algorithm>

#include <fmt/format.h>

#include "passes/snapshot_params.h"
#include "tracer/shading_params.h"

namespace aamap {

const std::vector<ParamSpec>& topLevelParams() {
    static const std::vector<ParamSpec> params = {
        intParam("view_index", 0, 1000000, 0, "which view of the file (or of the scene)"),
        intParam("threads", 0, 4096, 0, "tracer threads, 0 = all"),
    };
    return params;
}

const std::vector<ParamSpec>& imageParams() {
    static const std::vector<ParamSpec> params = {
        intParam("width", 1, 16384, 512, "bounding box width; the view's aspect ratio fits inside"),
        intParam("height", 1, 16384, 512, "bounding box height"),
        realParamAbove("exposure", 0.0, 1e6, 1.0, "multiplies radiance before the sRGB PNGs"),
        choiceParam("filter", {"box", "tent", "gaussian"}, "pixel reconstruction filter"),
        realParam("filter_radius", 0.0, 8.0, 0.0, "half-width in pixels; 0: the filter's own"),
        realParamAbove("filter_stddev", 0.0, 4.0, 0.5, "gaussian only: the standard deviation in pixels"),
        choiceParam("filter_mode", {"convolution", "importance"},
                    "convolution: box pixels, then the image convolved with the filter (neighbours share "
                    "samples: less noise); importance: film positions drawn from the filter"),
    };
    return params;
}

const Schema<MetricsConfig>& metricsSchema() {
    using M = MetricsConfig;
    static const Schema<M> schema = [] {
        Schema<M> s;
        s.field(&M::flip, "flip", true, "LDR-FLIP of the displayed images")
            .field(&M::flipHdr, "flip_hdr", false, "HDR-FLIP of the linear radiance as well")
            .field(&M::flipThreshold, "flip_threshold", above(0.0, 1.0), 0.1, "FLIP above it counts as an error pixel")
            .field(&M::mseThreshold, "mse_threshold", above(0.0, 1.0), (2.0 / 255.0) * (2.0 / 255.0),
                   "per-pixel display-space squared error")
            .field(&M::ppd, "ppd", above(0.0, 1000.0), 67.0206, "FLIP viewing condition, pixels per degree")
            .field(&M::mapQuality, "map_quality", true, "aamap recall/precision; adds a 1-ray uniform render")
            .field(&M::causes, "causes", true, "with map_quality: why pixels are missed or wasted")
            .field(&M::oracle, "oracle", false, "with map_quality: each aamap render again with the oracle map, its bound");
        return s;
    }();
    return schema;
}

const Schema<ReportConfig>& reportSchema() {
    static const Schema<ReportConfig> schema = [] {
        Schema<ReportConfig> s;
        s.field(&ReportConfig::plots, "plots", true, "run tools/report_plots.py");
        return s;
    }();
    return schema;
}

const Schema<TimingConfig>& timingSchema() {
    using T = TimingConfig;
    static const Schema<T> schema = [] {
        Schema<T> s;
        s.field(&T::repeats, "repeats", in(1, 100), 1, "timed runs of every trace; the time is their median")
            .field(&T::interleave, "interleave", true, "round r times every render once before round r + 1")
            .field(&T::sameMachine, "same_machine", false, "trace the renders of one rpp on one worker");
        return s;
    }();
    return schema;
}

MetricsConfig::MetricsConfig() { metricsSchema().setDefaults(*this); }
ReportConfig::ReportConfig() { reportSchema().setDefaults(*this); }
TimingConfig::TimingConfig() { timingSchema().setDefaults(*this); }

const std::vector<ParamSpec>& metricsParams() { return metricsSchema().specs(); }
const std::vector<ParamSpec>& reportParams() { return reportSchema().specs(); }
const std::vector<ParamSpec>& timingParams() { return timingSchema().specs(); }

const std::vector<ConfigSection>& configSections() {
    static const std::vector<ConfigSection> sections = {
        {"", topLevelParams()},          {"image", imageParams()},
        {"snapshot", snapshotParams()},  {"shading", shadingParams()},
        {"shading.cache", shadingCacheParams()}, {"metrics", metricsParams()},
        {"report", reportParams()},      {"timing", timingParams()},
    };
    return sections;
}

std::vector<std::string> sectionKeys() {
    std::vector<std::string> keys;
    for (const ConfigSection& s : configSections())
        for (const ParamSpec& p : s.params) keys.push_back(s.path.empty() ? p.name : s.path + "." + p.name);
    return keys;
}

namespace {

// "scale: 1.5", "map: luminance|geometric|combined", "russian_roulette: true"
std::string helpEntry(const ParamSpec& p) {
    if (p.type == ParamType::Choice) return fmt::format("{}: {}", p.name, fmt::join(p.choices, "|"));
    return fmt::format("{}: {}", p.name, toString(p.defaultParam()));
}

}  // namespace

std::string sectionHelpLines() {
    constexpr std::size_t kWidth = 104;
    std::string out;
    for (const ConfigSection& s : configSections()) {
        const std::string open = s.path.empty() ? "  " : "  " + s.path + ": {";
        const std::string indent(open.size(), ' ');
        std::string line = open;
        for (std::size_t i = 0; i < s.params.size(); ++i) {
            const bool last = i + 1 == s.params.size();
            const std::string entry = helpEntry(s.params[i]) + (last ? (s.path.empty() ? "" : "}") : s.path.empty() ? "   " : ", ");
            if (line.size() + entry.size() > kWidth && line.size() > indent.size()) {
                out += line.substr(0, line.find_last_not_of(' ') + 1) + "\n";
                line = indent;
            }
            line += entry;
        }
        out += line + "\n";
    }
    return out;
}

ParamValues readSection(const yaml::Context& ctx, yaml::MapReader& map, const std::vector<ParamSpec>& params) {
    ParamValues values;
    for (const ParamSpec& p : params) {
        switch (p.type) {
            case ParamType::Int: {
                int v = static_cast<int>(p.defaultValue);
                map.getInt(p.name, v, static_cast<long long>(p.lo), static_cast<long long>(p.hi));
                values.set(p.name, v);
                break;
            }
            case ParamType::Real: {
                double v = p.defaultValue;
                map.getDouble(p.name, v, p.lo, p.hi, p.openLo);
                values.set(p.name, v);
                break;
            }
            case ParamType::Choice: {
                std::string v = p.choices.front();
                map.getString(p.name, v);
                if (std::find(p.choices.begin(), p.choices.end(), v) == p.choices.end())
                    ctx.fail(map.node(p.name), map.childPath(p.name),
                             fmt::format("{}: unknown value '{}' (supported: {})", map.childPath(p.name), v,
                                         fmt::join(p.choices, ", ")));
                values.set(p.name, v);
                break;
            }
            case ParamType::Bool: {
                bool v = p.defaultValue != 0;
                const YAML::Node n = map.node(p.name);
                if (n.IsDefined() && !yaml::decodePlain(n, v))
                    ctx.fail(n, map.childPath(p.name), fmt::format("{}: expected true or false, found {}",
                                                                   map.childPath(p.name), yaml::describe(n)));
                values.set(p.name, v);
                break;
            }
        }
    }
    return values;
}

nlohmann::ordered_json toJson(const ParamValues& values) {
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    for (const auto& entry : values.entries())  // not a structured binding: clang's lambdas cannot capture one
        std::visit([&j, &entry](const auto& v) { j[entry.first] = v; }, entry.second);
    return j;
}

std::vector<std::string> sectionKeyNames(const std::vector<ParamSpec>& params, std::vector<std::string> extra) {
    std::vector<std::string> names;
    for (const ParamSpec& p : params) names.push_back(p.name);
    names.insert(names.end(), extra.begin(), extra.end());
    return names;
}

}  // namespace aamap
