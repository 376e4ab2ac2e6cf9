#include "eval/config_sections.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <fmt/format.h>

#include "core/error.h"
#include "eval/config_schema.h"
#include "eval/strategies.h"
#include "tracer/shading_params.h"

namespace aamap::detail {
namespace {

using yaml::MapReader;

constexpr int kMaxRpp = 1024;      // 32 x 32; the rays-per-pixel image is 16-bit
constexpr std::size_t kMaxSweep = 4096;  // renders one entry may expand to

bool isFileNameSafe(const std::string& s) {
    return !s.empty() && s.size() <= 64 &&
           std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; });
}

// One swept (or fixed) key of a renders[] entry.
struct Axis {
    std::string key;
    std::vector<ParamValue> values;
    bool listed = false;    // written as a list
    bool explicit_ = false; // written at all
};

// One scalar, decoded as the parameter's type and checked against its schema.
ParamValue readValue(const yaml::Context& ctx, const YAML::Node& n, const std::string& path, const ParamSpec& spec) {
    ParamValue v;
    if (spec.type == ParamType::Choice) {
        if (!n.IsScalar())
            ctx.fail(n, path, fmt::format("{}: expected one of {}, found {}", path, fmt::join(spec.choices, ", "),
                                          yaml::describe(n)));
        v = n.Scalar();
    } else {
        const bool integer = spec.type == ParamType::Int;
        double d = 0;
        long long i = 0;
        const bool ok = integer ? yaml::decodePlain(n, i) : yaml::decodePlain(n, d) && std::isfinite(d);
        if (!ok)
            ctx.fail(n, path, fmt::format("{}: expected {}, found {}", path, integer ? "an integer" : "a finite number",
                                          yaml::describe(n)));
        // An integer beyond int stays a number, so the schema reports it as out of range.
        const bool fits = i >= std::numeric_limits<int>::min() && i <= std::numeric_limits<int>::max();
        v = !integer ? ParamValue(d) : fits ? ParamValue(static_cast<int>(i)) : ParamValue(static_cast<double>(i));
    }
    std::string error;
    const std::optional<ParamValue> checked = spec.check(v, error);
    if (!checked) ctx.fail(n, path, fmt::format("{}: {}", path, error));
    return *checked;
}

// A scalar or a non-empty list of scalars, each checked.
Axis readAxis(const yaml::Context& ctx, MapReader& m, const ParamSpec& spec) {
    const std::string& key = spec.name;
    Axis a{key, {spec.defaultParam()}, false, false};
    const YAML::Node n = m.node(key);
    if (!n.IsDefined()) return a;
    a.explicit_ = true;
    const std::string path = m.childPath(key);
    if (n.IsSequence()) {
        if (n.size() == 0) ctx.fail(n, path, fmt::format("{}: an empty list sweeps nothing", path));
        a.listed = true;
        a.values.clear();
        for (std::size_t i = 0; i < n.size(); ++i) {
            const ParamValue v = readValue(ctx, n[i], fmt::format("{}[{}]", path, i), spec);
            if (std::find(a.values.begin(), a.values.end(), v) != a.values.end())
                ctx.fail(n[i], path, fmt::format("{}: {} is listed twice", path, n[i].Scalar()));
            a.values.push_back(v);
        }
    } else {
        a.values = {readValue(ctx, n, path, spec)};
    }
    return a;
}

// "{rpp}", "{n}" and "{<param>}" in a name or series template.
// fileName: the text becomes a render's file stem, so a value's '.' is written 'p' and '+' is
// dropped ("noise_threshold0p02", "threshold1e06"): letters, digits, '_' and '-' only.
std::string substitute(std::string text, const StrategyParams& values, bool fileName) {
    for (const auto& [key, v] : values.entries()) {
        const std::string token = "{" + key + "}";
        std::string value = toString(v);
        if (fileName) {
            std::replace(value.begin(), value.end(), '.', 'p');
            std::erase(value, '+');
        }
        for (std::size_t at; (at = text.find(token)) != std::string::npos;) text.replace(at, token.size(), value);
    }
    return text;
}

std::vector<RenderConfig> expandEntry(const yaml::Context& ctx, const YAML::Node& node, const std::string& path) {
    // The allowed keys depend on the strategy, so read it first.
    std::vector<std::string> keys = {"name", "series", "strategy", "rpp"};
    for (const std::string& p : allStrategyParamNames()) keys.push_back(p);
    MapReader m(ctx, node, path, keys);
    m.require("strategy");
    m.require("rpp");
    std::string strategy;
    m.getString("strategy", strategy);
    const StrategyDescriptor* info = findStrategy(strategy);
    if (info == nullptr) {
        const std::string hint = yaml::closest(strategy, strategyNames());
        ctx.fail(m.node("strategy"), m.childPath("strategy"),
                 fmt::format("{}: unknown strategy '{}'{} (supported: {})", m.childPath("strategy"), strategy,
                             hint.empty() ? "" : fmt::format("; did you mean '{}'?", hint),
                             fmt::join(strategyNames(), ", ")));
    }
    for (const std::string& p : allStrategyParamNames()) {
        if (info->param(p) == nullptr && m.has(p))
            ctx.fail(m.node(p), m.childPath(p),
                     fmt::format("{}: strategy '{}' has no parameter '{}'", m.childPath(p), strategy, p));
    }

    std::vector<Axis> axes;
    axes.push_back(readAxis(ctx, m, intParam("rpp", 1, kMaxRpp, 1, "rays per pixel")));
    for (std::size_t i = 0; i < axes[0].values.size(); ++i) {
        const int rpp = std::get<int>(axes[0].values[i]);
        const int n = static_cast<int>(std::lround(std::sqrt(rpp)));
        if (n * n != rpp)
            ctx.fail(m.node("rpp"), m.childPath("rpp"),
                     fmt::format("{}: {} is not a perfect square; rays per pixel are n x n strata (1, 4, 9, 16, "
                                 "25, 36, ...)", m.childPath("rpp"), rpp));
    }
    for (const ParamSpec& p : info->params) axes.push_back(readAxis(ctx, m, p));

    std::string nameTemplate, seriesTemplate;
    const bool named = m.has("name");
    m.getString("name", nameTemplate);
    m.getString("series", seriesTemplate);
    if (!named) {  // strategy + rpp, then every parameter the entry wrote
        nameTemplate = strategy + "{rpp}";
        for (std::size_t a = 1; a < axes.size(); ++a)
            if (axes[a].explicit_) nameTemplate += "_" + axes[a].key + "{" + axes[a].key + "}";
    } else {  // a swept key the template does not mention is appended, so names stay unique
        for (const Axis& a : axes)
            if (a.listed && nameTemplate.find("{" + a.key + "}") == std::string::npos &&
                !(a.key == "rpp" && nameTemplate.find("{n}") != std::string::npos))
                nameTemplate += "_" + a.key + "{" + a.key + "}";
    }
    if (seriesTemplate.empty()) {  // the strategy and the parameters written, never rpp: rpp is the row
        seriesTemplate = strategy;
        for (std::size_t a = 1; a < axes.size(); ++a)
            if (axes[a].explicit_) seriesTemplate += " " + axes[a].key + "={" + axes[a].key + "}";
    }

    std::size_t count = 1;
    for (const Axis& a : axes) count *= a.values.size();
    if (count > kMaxSweep)
        ctx.fail(node, path, fmt::format("{}: the sweep expands to {} renders (at most {})", path, count, kMaxSweep));
    std::vector<RenderConfig> out;
    for (std::size_t index = 0; index < count; ++index) {
        // Row-major: the first key (rpp) varies slowest.
        StrategyParams values;  // rpp, then the strategy's parameters in schema order
        std::size_t rest = index, stride = count;
        RenderConfig r;
        r.strategy = strategy;
        for (std::size_t a = 0; a < axes.size(); ++a) {
            stride /= axes[a].values.size();
            const ParamValue& v = axes[a].values[rest / stride];
            values.set(axes[a].key, v);
            if (a == 0) r.rpp = std::get<int>(v);
            else r.params.set(axes[a].key, v);
            rest %= stride;
        }
        values.set("n", r.strata());
        r.name = substitute(nameTemplate, values, true);
        r.series = substitute(seriesTemplate, values, false);
        const YAML::Node at = named ? m.node("name") : node;
        if (!isFileNameSafe(r.name))
            ctx.fail(at, m.childPath("name"),
                     fmt::format("{}: '{}' is not a safe file name (use 1-64 letters, digits, '_' or '-')",
                                 m.childPath("name"), r.name));
        const auto& reserved = reservedNames();
        if (std::find(reserved.begin(), reserved.end(), lower(r.name)) != reserved.end())
            ctx.fail(at, m.childPath("name"),
                     fmt::format("{}: '{}' is reserved for another output file ({})", m.childPath("name"), r.name,
                                 fmt::join(reserved, ", ")));
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace

const std::vector<std::string>& reservedNames() {
    static const std::vector<std::string> names = {"snapshot", "laplacian", "aamap",  "results", "reference",
                                                   "one_ray",  "report",    "cache",  "plots"};
    return names;
}

bool readBool(const yaml::Context& ctx, MapReader& m, const std::string& key, bool fallback) {
    const YAML::Node n = m.node(key);
    if (!n.IsDefined()) return fallback;
    bool v = false;
    if (!yaml::decodePlain(n, v))
        ctx.fail(n, m.childPath(key), fmt::format("{}: expected true or false, found {}", m.childPath(key), yaml::describe(n)));
    return v;
}

namespace {

const std::vector<std::pair<std::string, ReferenceType>>& referenceTypeNames() {
    static const std::vector<std::pair<std::string, ReferenceType>> names = {
        {"uniform", ReferenceType::Uniform}, {"file", ReferenceType::File}, {"none", ReferenceType::None}};
    return names;
}

}  // namespace

std::optional<ShadingMode> readShadingMode(const yaml::Context& ctx, MapReader& m, const std::string& key) {
    const YAML::Node n = m.node(key);
    if (!n.IsDefined() || n.IsNull()) return std::nullopt;
    std::string name;
    m.getString(key, name);
    ShadingMode mode{};
    if (!parse(name, mode)) {
        const std::vector<std::string>& names = findParam(shadingParams(), "mode")->choices;  // shading.mode's
        ctx.fail(n, m.childPath(key),
                 fmt::format("{}: unknown value '{}' (supported: {})", m.childPath(key), name, fmt::join(names, ", ")));
    }
    return mode;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::vector<RenderConfig> readRenders(const yaml::Context& ctx, const YAML::Node& renders) {
    if (!renders.IsSequence() || renders.size() == 0)
        ctx.fail(renders, "renders", fmt::format("renders: expected a non-empty list, found {}", yaml::describe(renders)));
    std::vector<RenderConfig> all;
    std::set<std::string> names;
    // The tables have a column per series and a row per rpp: two renders in one cell would hide one.
    std::map<std::pair<std::string, int>, std::size_t> cells;
    for (std::size_t i = 0; i < renders.size(); ++i) {
        const std::string path = fmt::format("renders.{}", i);
        for (RenderConfig& r : expandEntry(ctx, renders[i], path)) {
            if (!names.insert(lower(r.name)).second)
                ctx.fail(renders[i], path,
                         fmt::format("{}: render name '{}' is used twice (names are output file names)", path, r.name));
            const auto [cell, fresh] = cells.emplace(std::make_pair(r.series, r.rpp), all.size());
            if (!fresh) {
                const RenderConfig& other = all[cell->second];
                std::string hint;
                for (const auto& [key, value] : r.params.entries())
                    for (const auto& [otherKey, otherValue] : other.params.entries())
                        if (key == otherKey && value != otherValue && hint.empty())
                            hint = fmt::format("; did you mean series: \"{} {}={{{}}}\"?", r.series, key, key);
                ctx.fail(renders[i], path,
                         fmt::format("{}: renders '{}' and '{}' would share one table cell (series '{}', rpp {}), "
                                     "and the tables would show only one of them: give them different series{}",
                                     path, other.name, r.name, r.series, r.rpp, hint));
            }
            all.push_back(std::move(r));
        }
    }
    return all;
}

ReferenceConfig readReference(const yaml::Context& ctx, const YAML::Node& node, const std::vector<RenderConfig>& renders) {
    MapReader m(ctx, node, "reference", {"type", "rpp", "mode", "path"});
    ReferenceConfig ref;
    if (m.has("type")) {
        std::string type;
        m.getString("type", type);
        const auto& names = referenceTypeNames();
        const auto it = std::find_if(names.begin(), names.end(), [&](const auto& n) { return n.first == type; });
        if (it == names.end()) {
            std::vector<std::string> list;
            for (const auto& n : names) list.push_back(n.first);
            ctx.fail(m.node("type"), m.childPath("type"),
                     fmt::format("reference.type: unknown type '{}' (supported: {})", type, fmt::join(list, ", ")));
        }
        ref.type = it->second;
    }
    // rpp and mode only apply to a traced reference, path only to a file; the others are checked
    // but ignored, so that --set reference.type=... works on any config.
    m.getInt("rpp", ref.rpp, 1, kMaxRpp);
    const int n = static_cast<int>(std::lround(std::sqrt(ref.rpp)));
    if (ref.rpp > 0 && n * n != ref.rpp)
        ctx.fail(m.node("rpp"), "reference.rpp", fmt::format("reference.rpp: {} is not a perfect square", ref.rpp));
    ref.mode = readShadingMode(ctx, m, "mode");
    if (ref.type == ReferenceType::Uniform && ref.rpp == 0)
        for (const RenderConfig& r : renders) ref.rpp = std::max(ref.rpp, r.rpp);
    if (ref.type == ReferenceType::File) m.require("path");
    m.getString("path", ref.path);
    ref.pathLocation = ctx.locate(m.node("path"), "reference.path");
    if (ref.type != ReferenceType::Uniform) {
        ref.rpp = 0;
        ref.mode.reset();
    }
    if (ref.type != ReferenceType::File) ref.path.clear();
    return ref;
}

MetricsConfig readMetrics(const yaml::Context& ctx, const YAML::Node& node) {
    MapReader m(ctx, node, "metrics", sectionKeyNames(metricsParams()));
    MetricsConfig c;
    readSection(ctx, m, metricsSchema(), c);
    return c;
}

ReportConfig readReport(const yaml::Context& ctx, const YAML::Node& node) {
    MapReader m(ctx, node, "report", sectionKeyNames(reportParams()));
    ReportConfig c;
    readSection(ctx, m, reportSchema(), c);
    return c;
}

CameraConfig readCamera(const yaml::Context& ctx, const YAML::Node& node) {
    if (!node.IsMap())
        ctx.fail(node, "camera", fmt::format("camera: expected a mapping {{position, look_at, up, fov}}, found {}",
                                             yaml::describe(node)));
    MapReader m(ctx, node, "camera", {"position", "look_at", "up", "fov"});
    CameraConfig c;
    m.require("position");
    m.require("look_at");
    constexpr double kFar = 1e30;
    m.getVec3("position", c.position, -kFar, kFar);
    m.getVec3("look_at", c.lookAt, -kFar, kFar);
    m.getVec3("up", c.up, -kFar, kFar);
    m.getDouble("fov", c.fov, 0.0, 180.0, true);
    if (c.fov >= 180.0) ctx.fail(m.node("fov"), "camera.fov", "camera.fov: must be below 180 degrees");
    if (c.position == c.lookAt)
        ctx.fail(m.node("look_at"), "camera.look_at", "camera.look_at: equals camera.position; the camera needs a direction");
    const std::array<double, 3> d = {c.lookAt[0] - c.position[0], c.lookAt[1] - c.position[1], c.lookAt[2] - c.position[2]};
    const std::array<double, 3> x = {d[1] * c.up[2] - d[2] * c.up[1], d[2] * c.up[0] - d[0] * c.up[2],
                                     d[0] * c.up[1] - d[1] * c.up[0]};
    const double dd = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double uu = std::sqrt(c.up[0] * c.up[0] + c.up[1] * c.up[1] + c.up[2] * c.up[2]);
    if (!(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) > 1e-6 * dd * uu))
        ctx.fail(m.has("up") ? m.node("up") : node, "camera.up",
                 "camera.up: zero or parallel to the view direction (look_at - position)");
    return c;
}

}  // namespace aamap::detail

namespace aamap {

const char* toString(ReferenceType type) {
    for (const auto& n : detail::referenceTypeNames())
        if (n.second == type) return n.first.c_str();
    return "?";
}

}  // namespace aamap
