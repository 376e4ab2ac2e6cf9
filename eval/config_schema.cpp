#include "eval/config_schema.h"

#include <algorithm>

#include <fmt/format.h>

#include "passes/snapshot_params.h"
#include "tracer/shading_params.h"

namespace aamap {

// The top-level scalars; their defaults are ExperimentConfig's initializers.
const Schema<ExperimentConfig>& topLevelSchema() {
    using E = ExperimentConfig;
    static const Schema<E> schema = [] {
        const E D{};
        Schema<E> s;
        s.field(&E::viewIndex, "view_index", in(0, 1000000), D.viewIndex,
                "which view of the file (or of the scene)")
            .field(&E::threads, "threads", in(0, 4096), D.threads,
                   "tracer threads, 0 = all; not part of the config hash");
        return s;
    }();
    return schema;
}

// The image's size and exposure, then the tracer's pixel filter keys (declared with the tracer).
const Schema<ImageConfig>& imageSchema() {
    using I = ImageConfig;
    static const Schema<I> schema = [] {
        Schema<I> s;
        s.field(&I::width, "width", in(1, 16384), 512,
                "bounding box; the view's aspect ratio picks the size inside it (square pixels). Unset (both), a "
                "Mitsuba scene's film size is used instead")
            .field(&I::height, "height", in(1, 16384), 512, "bounding box height, as `image.width`")
            .field(&I::exposure, "exposure", above(0.0, 1e6), 1.0,
                   "multiplies radiance before the sRGB PNGs; also the snapshot's greyscale, so the map sees edges "
                   "as the viewer does")
            .include(&I::filter, pixelFilterSchema());
        return s;
    }();
    return schema;
}

const std::vector<ParamSpec>& topLevelParams() { return topLevelSchema().specs(); }
const std::vector<ParamSpec>& imageParams() { return imageSchema().specs(); }

const Schema<MetricsConfig>& metricsSchema() {
    using M = MetricsConfig;
    static const Schema<M> schema = [] {
        Schema<M> s;
        s.field(&M::flip, "flip", true,
                "LDR-FLIP of what the PNGs show: mean, % pixels above the threshold, error map, red overlay")
            .field(&M::flipHdr, "flip_hdr", false,
                   "HDR-FLIP of the linear radiance as well")
            .field(&M::flipThreshold, "flip_threshold", above(0.0, 1.0), 0.1,
                   "FLIP above it counts as an error pixel, and as true aliasing for map quality")
            .field(&M::mseThreshold, "mse_threshold", above(0.0, 1.0), (2.0 / 255.0) * (2.0 / 255.0),
                   "(2/255)^2: a pixel is \"in error by MSE\" when its display-space squared error (mean over R, G, "
                   "B of sRGB values in [0, 1]) reaches it: 2 8-bit code values, the smallest difference that "
                   "survives quantisation (eval/metrics/pixel_error.h)")
            .field(&M::ppd, "ppd", above(0.0, 1000.0), 67.0206,
                   "FLIP's viewing condition, pixels per degree (0.7 m from a 0.7 m wide 4K monitor)")
            .field(&M::mapQuality, "map_quality", true,
                   "aamap recall, precision and flagged fraction; adds a 1-ray uniform render (reused if listed) "
                   "when some render uses the aamap")
            .field(&M::causes, "causes", true,
                   "with `map_quality`: why each error pixel was missed and each extra ray wasted, per render and "
                   "for the map, from the tracer's pixel facts ([experiments.md](experiments.md#causes)); the facts "
                   "cost about one 16-ray shadow-only render and are cached")
            .field(&M::oracle, "oracle", false,
                   "with `map_quality`: every aamap-driven render traced again on the oracle map (true aliasing "
                   "grown to the pixels the reference says need rays, given the full budget), and a table of each "
                   "map's speedup and error beside the oracle's ([experiments.md](experiments.md#oracle))");
        return s;
    }();
    return schema;
}

const Schema<ReportConfig>& reportSchema() {
    static const Schema<ReportConfig> schema = [] {
        Schema<ReportConfig> s;
        s.field(&ReportConfig::plots, "plots", true,
                "run `tools/report_plots.py` with the venv's Python; without one the report says so");
        return s;
    }();
    return schema;
}

const Schema<TimingConfig>& timingSchema() {
    using T = TimingConfig;
    static const Schema<T> schema = [] {
        Schema<T> s;
        s.field(&T::repeats, "repeats", in(1, 100), 1,
                "timed runs of every trace; `times_s.trace` is their median and `times_s.trace_runs` lists them "
                "all. Images are unchanged (each run must give the same image bit for bit) and the cache keys do "
                "not depend on it: a rerun with more repeats traces only the runs the cache lacks "
                "([experiments.md](experiments.md), \"Timing\")")
            .field(&T::interleave, "interleave", true,
                   "round r times every render once before round r + 1 starts, so drift of the machine hits all "
                   "renders alike; `false` runs each render's repeats back to back")
            .field(&T::sameMachine, "same_machine", false,
                   "`--executor ray`: the renders of one rpp (a speedup's baseline and the series it divides) run "
                   "on one worker, so their ratio compares strategies, not machines; the cache keys do not depend "
                   "on it. A local run ignores it ([experiments.md](experiments.md), \"Running on a Ray cluster\")");
        return s;
    }();
    return schema;
}

ImageConfig::ImageConfig() { imageSchema().setDefaults(*this); }
MetricsConfig::MetricsConfig() { metricsSchema().setDefaults(*this); }
ReportConfig::ReportConfig() { reportSchema().setDefaults(*this); }
TimingConfig::TimingConfig() { timingSchema().setDefaults(*this); }

const std::vector<ParamSpec>& metricsParams() { return metricsSchema().specs(); }
const std::vector<ParamSpec>& reportParams() { return reportSchema().specs(); }
const std::vector<ParamSpec>& timingParams() { return timingSchema().specs(); }

namespace {

// A section bound to the part of the config that holds it.
template <class T>
ConfigSection bound(std::string path, const Schema<T>& schema, const T& (*part)(const ExperimentConfig&)) {
    return {std::move(path), schema.specs(),
            [&schema, part](const ExperimentConfig& c) { return schema.values(part(c)); },
            [&schema, part](const ExperimentConfig& c) { return schema.changed(part(c)); }};
}

}  // namespace

const std::vector<ConfigSection>& configSections() {
    using E = ExperimentConfig;
    static const std::vector<ConfigSection> sections = {
        bound<E>("", topLevelSchema(), [](const E& c) -> const E& { return c; }),
        bound<ImageConfig>("image", imageSchema(), [](const E& c) -> const ImageConfig& { return c.image; }),
        bound<SnapshotSettings>("snapshot", snapshotSchema(),
                                [](const E& c) -> const SnapshotSettings& { return c.snapshot; }),
        bound<ShadingSettings>("shading", shadingSchema(),
                               [](const E& c) -> const ShadingSettings& { return c.shading; }),
        bound<IrradianceCacheSettings>("shading.cache", shadingCacheSchema(),
                                       [](const E& c) -> const IrradianceCacheSettings& { return c.shading.cache; }),
        bound<MetricsConfig>("metrics", metricsSchema(), [](const E& c) -> const MetricsConfig& { return c.metrics; }),
        bound<ReportConfig>("report", reportSchema(), [](const E& c) -> const ReportConfig& { return c.report; }),
        bound<TimingConfig>("timing", timingSchema(), [](const E& c) -> const TimingConfig& { return c.timing; }),
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

namespace {

// The type cell of a key's row: "int in [1, 64]", "number in (0, 1]", "bool", "`a`, `b` or `c`".
std::string docType(const ParamSpec& p) {
    if (p.type == ParamType::Bool) return "bool";
    if (p.type == ParamType::Choice) {
        std::string t;
        for (std::size_t i = 0; i < p.choices.size(); ++i)
            t += (i == 0 ? "" : i + 1 == p.choices.size() ? " or " : ", ") + ("`" + p.choices[i] + "`");
        return t;
    }
    return fmt::format("{} in {}", p.type == ParamType::Int ? "int" : "number", p.rangeText());
}

}  // namespace

std::string configKeysMarkdown() {
    std::string out = "| Key | Type, default | Meaning |\n|---|---|---|\n";
    for (const ConfigSection& s : configSections())
        for (const ParamSpec& p : s.params)
            out += fmt::format("| `{}` | {}, `{}` | {} |\n", s.path.empty() ? p.name : s.path + "." + p.name, docType(p),
                               toString(p.defaultParam()), p.doc);
    return out;
}

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
