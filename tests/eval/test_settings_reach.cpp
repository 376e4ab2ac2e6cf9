// Every setting reaches its consumer. The keys are not listed here: they are read off the parsed
// config's canonical JSON (every field, defaults filled in) of configs that use every section,
// every strategy and every light type, so a key added to the schema shows up here by itself and
// fails until this table says what it must change. For each key, changing it (through --set, which
// also proves the key is settable) must
//  * change the cache key of exactly the renders it affects (eval/config.h renderKey) and of the
//    Snapshot when it affects the Snapshot (snapshotKey), and leave the others alone;
//  * change what its consumer receives: the Snapshot's settings, the tracer's settings, the
//    strategy's settings, the scene and view the run prepares, the metric figures, the jobs the
//    runner traces.
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "eval/config.h"
#include "eval/evaluate.h"
#include "eval/experiment.h"
#include "eval/light_list.h"
#include "eval/runner.h"
#include "eval/strategies.h"
#include "eval/strategy_settings.h"
#include "scene/light_file.h"
#include "scene/scene.h"
#include "tests/common/temp_dir.h"
#include "tests/eval/fake_backend.h"

namespace aamap {
namespace {

using Json = nlohmann::json;

// Which renders' cache keys a setting must change.
enum class Renders {
    All,         // every render
    UsingAamap,  // the renders whose strategy uses the Snapshot's map
    This,        // the render whose entry holds the key
    None,        // none: the setting never changes a traced image
    Any,         // the key may or may not change (a label, say): not checked
};

struct Change {
    std::string base;  // the base config the key is read from
    const ExperimentConfig& before;
    const ExperimentConfig& after;
    int index;  // the list index of renders.# / lights.# keys, else -1
};

struct Alternative {
    std::vector<std::string> given;  // overrides applied before and after (what the key needs)
    std::vector<std::string> set;    // the change; '#' stands for the key's list index
    Renders renders;
    bool snapshot;  // snapshotKey must change (else it must not)
    std::function<void(const Change&)> reaches;
};

// --- Consumers -------------------------------------------------------------------------------

std::string describe(const StrategySettings& s) {
    std::string text = fmt::format("{} n={} map={}", s.name, s.strata, s.aamap != nullptr);
    for (const auto& [key, value] : s.params.entries()) text += fmt::format(" {}={}", key, toString(value));
    return text;
}

std::string describe(const View& v) {
    return fmt::format("{} {} {} {} {} {} {} {} {} {} {}", v.position.x, v.position.y, v.position.z, v.direction.x,
                       v.direction.y, v.direction.z, v.up.x, v.up.y, v.up.z, v.horizontalFovDeg, v.verticalFovDeg);
}

// What the scene gets from the config's lights (the consumer is addLights).
std::string sceneLights(const ExperimentConfig& c) {
    Scene scene;
    addLights(scene, c.lights);
    std::string s;
    for (const PointLight& p : scene.pointLights)
        s += fmt::format("point {} {} {} {} | {} {} {} | {} {} {} | {} {} {} | {} {};", p.name, p.position.x,
                         p.position.y, p.position.z, p.intensity.x, p.intensity.y, p.intensity.z, p.normal.x,
                         p.normal.y, p.normal.z, p.spotDirection.x, p.spotDirection.y, p.spotDirection.z, p.cosInner,
                         p.cosOuter);
    for (const AreaLight& a : scene.areaLights)
        s += fmt::format("area {} {} {} {} {} {};", a.name, a.radiance.x, a.radiance.y, a.radiance.z, a.area,
                         a.triangles.size());
    for (const DirectionalLight& d : scene.directionalLights)
        s += fmt::format("directional {} {} {} {} | {} {} {};", d.name, d.direction.x, d.direction.y, d.direction.z,
                         d.irradiance.x, d.irradiance.y, d.irradiance.z);
    if (const auto& e = scene.environment) {
        s += fmt::format("environment {} {} {} {} | {}x{} |", e->name, e->scale.x, e->scale.y, e->scale.z, e->mapWidth,
                         e->mapHeight);
        for (const glm::vec3& texel : e->map) s += fmt::format(" {} {} {}", texel.x, texel.y, texel.z);
        for (int col = 0; col < 3; ++col)
            s += fmt::format(" | {} {} {}", e->toLocal[col].x, e->toLocal[col].y, e->toLocal[col].z);
        s += ";";
    }
    for (const glm::vec3& p : scene.mesh.positions) s += fmt::format("{} {} {},", p.x, p.y, p.z);
    return s;
}

// A reference and a test image with a spread of errors: a ramp against its negative.
struct ImagePair {
    ImageRGB reference{32, 16}, test{32, 16};
    ImagePair() {
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 32; ++x) {
                reference.at(x, y) = glm::vec3(0.5f);
                test.at(x, y) = glm::vec3(0.5f + 0.5f * static_cast<float>(x) / 31.0f * ((x + y) % 2 ? 1.0f : -1.0f));
            }
    }
};

Json figures(const ExperimentConfig& c) {
    static const ImagePair images;
    test::TempDir dir;
    std::vector<std::string> outputs;
    return evaluateRender(images.reference, images.test, c.metrics, static_cast<float>(c.image.exposure), dir.path(),
                          "probe", outputs);
}

// A fake backend that records every job it is asked to trace.
class RecordingBackend : public FakeBackend {
public:
    std::vector<RenderConfig> jobs;
    TraceOutput trace(const RenderConfig& r, const ImageGrey* aamap, const std::function<void(int, int)>& progress) override {
        jobs.push_back(r);
        return FakeBackend::trace(r, aamap, progress);
    }
};

// The jobs the runner traces for a config, as "name strategy rpp mode" lines in order.
std::vector<std::string> tracedJobs(const ExperimentConfig& c) {
    test::TempDir dir;
    RecordingBackend backend;
    runExperimentWith(c, dir.path() / "out", backend, RunnerOptions{"test", false});
    std::vector<std::string> jobs;
    for (const RenderConfig& r : backend.jobs) jobs.push_back(fmt::format("{} {} {} {}", r.name, r.strategy, r.rpp, r.shadingMode));
    return jobs;
}

PreparedScene prepared(const ExperimentConfig& c) { return prepareScene(c); }

// Whether a run (with a backend that knows what each pixel sees) reports the map's causes.
bool causesReported(const ExperimentConfig& c) {
    test::TempDir dir;
    RecordingBackend backend;
    backend.withFacts = true;
    const Results results = runExperimentWith(c, dir.path() / "out", backend, RunnerOptions{"test", false});
    return results.mapQuality.contains("causes");
}

// The work items an executor would be handed, with the groups that pin them to one machine.
std::vector<std::string> workGroups(const ExperimentConfig& c) {
    test::TempDir dir;
    std::vector<std::string> groups;
    for (const WorkItem& w : missingWork(c, dir.path(), 1)) groups.push_back(w.key + " " + w.group);
    return groups;
}

// --- The table -------------------------------------------------------------------------------

template <class Get>
std::function<void(const Change&)> differs(Get get) {
    return [get](const Change& ch) {
        EXPECT_NE(get(ch.before, ch.index), get(ch.after, ch.index)) << "the consumer did not receive the new value";
    };
}

template <class Get, class Value>
std::function<void(const Change&)> becomes(Get get, Value value) {
    return [get, value](const Change& ch) {
        EXPECT_EQ(get(ch.after, ch.index), value) << "the consumer did not receive the new value";
        EXPECT_NE(get(ch.before, ch.index), value) << "the alternative equals the default";
    };
}

SnapshotSettings snap(const ExperimentConfig& c, int) { return snapshotSettingsFor(c); }
ShadingSettings shade(const ExperimentConfig& c, int) { return toShadingSettings(c, c.renders.front()); }

std::map<std::string, Alternative> alternatives(const std::filesystem::path& dir) {
    std::map<std::string, Alternative> t;
    const auto viewFile = (dir / "two.vf").string();
    const auto otherLights = (dir / "other_lights.yaml").string();
    // Where the scene comes from: every image and the Snapshot.
    t["scene"] = {{}, {"scene=builtin:spheres-plane"}, Renders::All, true,
                  differs([](const ExperimentConfig& c, int) { return prepared(c).scene.name; })};
    t["view"] = {{}, {"view=" + viewFile}, Renders::All, true,
                 differs([](const ExperimentConfig& c, int) { return describe(prepared(c).view); })};
    t["view_index"] = {{"view=" + viewFile}, {"view_index=1"}, Renders::All, true,
                       differs([](const ExperimentConfig& c, int) { return describe(prepared(c).view); })};
    t["camera.position"] = {{}, {"camera.position=[0, 1.2, 4.5]"}, Renders::All, true,
                            differs([](const ExperimentConfig& c, int) { return describe(prepared(c).view); })};
    t["camera.look_at"] = {{}, {"camera.look_at=[0.3, 0.8, 0]"}, Renders::All, true,
                           differs([](const ExperimentConfig& c, int) { return describe(prepared(c).view); })};
    t["camera.up"] = {{}, {"camera.up=[0.2, 1, 0]"}, Renders::All, true,
                      differs([](const ExperimentConfig& c, int) { return describe(prepared(c).view); })};
    t["camera.fov"] = {{}, {"camera.fov=30"}, Renders::All, true,
                       differs([](const ExperimentConfig& c, int) { return describe(prepared(c).view); })};
    t["light_file"] = {{}, {"light_file=" + otherLights}, Renders::All, true,
                       differs([](const ExperimentConfig& c, int) { return sceneLights(c); })};
    t["image.width"] = {{}, {"image.width=96"}, Renders::All, true,
                        differs([](const ExperimentConfig& c, int) { return prepared(c).width; })};
    t["image.height"] = {{}, {"image.height=80"}, Renders::All, true,
                         differs([](const ExperimentConfig& c, int) { return prepared(c).height; })};
    t["image.exposure"] = {{}, {"image.exposure=2.5"}, Renders::All, true,
                           becomes([](const ExperimentConfig& c, int) { return snap(c, 0).filter.exposure; }, 2.5f)};
    // The pixel filter: every traced image, never the Snapshot.
    const auto filter = [](const ExperimentConfig& c, int) { return traceSettingsFor(c, c.renders.front(), 8, 8, -1).filter; };
    t["image.filter"] = {{}, {"image.filter=tent"}, Renders::All, false,
                         becomes([filter](const ExperimentConfig& c, int i) { return filter(c, i).type; }, PixelFilterType::Tent)};
    t["image.filter_radius"] = {{}, {"image.filter_radius=1.5"}, Renders::All, false,
                                becomes([filter](const ExperimentConfig& c, int i) { return filter(c, i).radius; }, 1.5f)};
    t["image.filter_stddev"] = {{"image.filter=gaussian"}, {"image.filter_stddev=0.3"}, Renders::All, false,
                                becomes([filter](const ExperimentConfig& c, int i) { return filter(c, i).stddev; }, 0.3f)};
    t["image.filter_mode"] = {{"image.filter=gaussian"}, {"image.filter_mode=importance"}, Renders::All, false,
                              becomes([filter](const ExperimentConfig& c, int i) { return filter(c, i).mode; },
                                      PixelFilterMode::Importance)};
    // The seed drives every traced sample. The GPU Snapshot has no random numbers, so its key
    // leaves the seed out (the CPU fallback's snapshot is then the one of the first seed run).
    t["seed"] = {{}, {"seed=99"}, Renders::All, false, becomes([](const ExperimentConfig& c, int) {
                     return traceSettingsFor(c, c.renders.front(), 8, 8, -1).seed;
                 }, std::uint64_t{99})};
    t["threads"] = {{}, {"threads=3"}, Renders::None, false, becomes([](const ExperimentConfig& c, int) {
                        return traceSettingsFor(c, c.renders.front(), 8, 8, -1).threads;
                    }, 3)};
    // The Snapshot: its key and the renders that read its map.
    t["snapshot.scale"] = {{}, {"snapshot.scale=2"}, Renders::UsingAamap, true,
                           becomes([](const ExperimentConfig& c, int) { return snap(c, 0).scale; }, 2.0f)};
    t["snapshot.area_light_samples"] = {{}, {"snapshot.area_light_samples=9"}, Renders::UsingAamap, true,
                                        becomes([](const ExperimentConfig& c, int) { return snap(c, 0).areaLightSamples; }, 9)};
    t["snapshot.area_light_solid_angle"] = {{}, {"snapshot.area_light_solid_angle=0.5"}, Renders::UsingAamap, true,
                                            becomes([](const ExperimentConfig& c, int) {
                                                return snap(c, 0).areaLightSolidAngle;
                                            }, 0.5f)};
    t["snapshot.blur_radius"] = {{}, {"snapshot.blur_radius=3"}, Renders::UsingAamap, true,
                                 becomes([](const ExperimentConfig& c, int) { return snap(c, 0).filter.blurRadius; }, 3)};
    t["snapshot.flat_range"] = {{}, {"snapshot.flat_range=0.25"}, Renders::UsingAamap, true,
                                becomes([](const ExperimentConfig& c, int) { return snap(c, 0).filter.flatRange; }, 0.25f)};
    t["snapshot.noise_floor"] = {{}, {"snapshot.noise_floor=0.125"}, Renders::UsingAamap, true,
                                 becomes([](const ExperimentConfig& c, int) { return snap(c, 0).filter.noiseFloor; }, 0.125f)};
    t["snapshot.gain"] = {{}, {"snapshot.gain=3.5"}, Renders::UsingAamap, true,
                          becomes([](const ExperimentConfig& c, int) { return snap(c, 0).filter.gain; }, 3.5f)};
    t["snapshot.environment_lights"] = {{}, {"snapshot.environment_lights=3"}, Renders::UsingAamap, true,
                                        becomes([](const ExperimentConfig& c, int) { return snap(c, 0).environmentLights; }, 3)};
    // The canonical JSON holds every key: the first base ("lists") has each at its default.
    t["snapshot.soft_shadows"] = {{}, {"snapshot.soft_shadows=false"}, Renders::UsingAamap, true,
                                  becomes([](const ExperimentConfig& c, int) { return snap(c, 0).shadows.softShadows; }, false)};
    t["snapshot.map"] = {{}, {"snapshot.map=geometric"}, Renders::UsingAamap, true,
                         becomes([](const ExperimentConfig& c, int) { return snap(c, 0).map; }, passes::AamapSource::Geometric)};
    // Read by the subpixel map only; in the keys whenever it is not at its default.
    t["snapshot.subpixel"] = {{}, {"snapshot.subpixel=4"}, Renders::UsingAamap, true,
                              becomes([](const ExperimentConfig& c, int) { return snap(c, 0).subpixel; }, 4)};
    // Shading: every traced image, never the Snapshot.
    t["shading.area_light_samples"] = {{}, {"shading.area_light_samples=9"}, Renders::All, false,
                                       becomes([](const ExperimentConfig& c, int) { return shade(c, 0).areaLightSamples; }, 9)};
    t["shading.mode"] = {{}, {"shading.mode=path"}, Renders::All, false,
                         becomes([](const ExperimentConfig& c, int) { return shade(c, 0).mode; }, ShadingMode::Path)};
    t["shading.max_depth"] = {{}, {"shading.max_depth=3"}, Renders::All, false,
                              becomes([](const ExperimentConfig& c, int) { return shade(c, 0).maxDepth; }, 3)};
    t["shading.russian_roulette"] = {{}, {"shading.russian_roulette=false"}, Renders::All, false,
                                     becomes([](const ExperimentConfig& c, int) { return shade(c, 0).russianRoulette; }, false)};
    t["shading.roulette_depth"] = {{}, {"shading.roulette_depth=2"}, Renders::All, false,
                                   becomes([](const ExperimentConfig& c, int) { return shade(c, 0).rouletteDepth; }, 2)};
    t["shading.hide_emitters"] = {{}, {"shading.hide_emitters=true"}, Renders::All, false,
                                  becomes([](const ExperimentConfig& c, int) { return shade(c, 0).hideEmitters; }, true)};
    t["shading.max_specular_depth"] = {{}, {"shading.max_specular_depth=2"}, Renders::All, false,
                                       becomes([](const ExperimentConfig& c, int) { return shade(c, 0).maxSpecularDepth; }, 2)};
    t["shading.glossy_reflection_alpha"] = {{}, {"shading.glossy_reflection_alpha=0.5"}, Renders::All, false,
                                            becomes([](const ExperimentConfig& c, int) {
                                                return shade(c, 0).glossyReflectionAlpha;
                                            }, 0.5f)};
    t["shading.light_selection"] = {{}, {"shading.light_selection=power"}, Renders::All, false,
                                    becomes([](const ExperimentConfig& c, int) { return shade(c, 0).lightSelection; },
                                            LightSelection::Power)};
    t["shading.light_sampling"] = {{}, {"shading.light_sampling=area"}, Renders::All, false,
                                   becomes([](const ExperimentConfig& c, int) { return shade(c, 0).lightSampling; },
                                           LightSampling::Area)};
    t["shading.texture_filter"] = {{}, {"shading.texture_filter=none"}, Renders::All, false,
                                   becomes([](const ExperimentConfig& c, int) { return shade(c, 0).textureFilter; },
                                           TextureFilter::None)};
    // The irradiance cache, in cache mode (every render reads it; the other modes' keys leave it out).
    const auto cache = [&](const std::string& key, const std::string& value, auto get, auto expected) {
        t["shading.cache." + key] = {{"shading.mode=cache"}, {"shading.cache." + key + "=" + value}, Renders::All, false,
                                     becomes([get](const ExperimentConfig& c, int) { return get(shade(c, 0)); }, expected)};
    };
    cache("bounces", "3", [](const ShadingSettings& s) { return s.cache.bounces; }, 3);
    cache("divisions", "100", [](const ShadingSettings& s) { return s.cache.divisions; }, 100);
    cache("supersamples", "16", [](const ShadingSettings& s) { return s.cache.supersamples; }, 16);
    cache("accuracy", "0.35", [](const ShadingSettings& s) { return s.cache.accuracy; }, 0.35f);
    cache("resolution", "20", [](const ShadingSettings& s) { return s.cache.resolution; }, 20);
    cache("grid_step", "6", [](const ShadingSettings& s) { return s.cacheGridStep; }, 6);
    // One render's entry: its own key only.
    t["renders.#.name"] = {{}, {"renders.#.name=renamed"}, Renders::None, false,
                           becomes([](const ExperimentConfig& c, int i) { return c.renders[i].name; }, std::string("renamed"))};
    t["renders.#.series"] = {{}, {"renders.#.series=Renamed"}, Renders::None, false,
                             becomes([](const ExperimentConfig& c, int i) { return c.renders[i].series; }, std::string("Renamed"))};
    t["renders.#.strategy"] = {{}, {"renders.#.strategy=rpict", "renders.#.name=other", "renders.#.series=Other"}, Renders::This, false,
                               differs([](const ExperimentConfig& c, int i) {
                                   return describe(toStrategySettings(c.renders[i], nullptr));
                               })};
    t["renders.#.rpp"] = {{}, {"renders.#.rpp=16"}, Renders::This, false, becomes([](const ExperimentConfig& c, int i) {
                              return toStrategySettings(c.renders[i], nullptr).strata;
                          }, 4)};
    // The reference is a job of the runner's own.
    t["reference.type"] = {{}, {"reference.type=none"}, Renders::None, false,
                           differs([](const ExperimentConfig& c, int) { return tracedJobs(c); })};
    t["reference.rpp"] = {{}, {"reference.rpp=16"}, Renders::None, false,
                          differs([](const ExperimentConfig& c, int) { return tracedJobs(c); })};
    t["reference.mode"] = {{}, {"reference.mode=path"}, Renders::None, false,
                           differs([](const ExperimentConfig& c, int) { return tracedJobs(c); })};
    t["reference.path"] = {{"reference.type=file", "reference.path=a.exr"}, {"reference.path=b.exr"}, Renders::None,
                           false, differs([](const ExperimentConfig& c, int) {
                               return c.reference.resolvedPath(c.file)->filename().string();
                           })};
    // Metrics: figures only, never an image.
    t["metrics.flip"] = {{}, {"metrics.flip=false"}, Renders::None, false,
                         differs([](const ExperimentConfig& c, int) { return figures(c).contains("flip_mean"); })};
    t["metrics.flip_hdr"] = {{}, {"metrics.flip_hdr=true"}, Renders::None, false,
                             differs([](const ExperimentConfig& c, int) { return figures(c).contains("flip_hdr_mean"); })};
    t["metrics.flip_threshold"] = {{}, {"metrics.flip_threshold=0.3"}, Renders::None, false,
                                   differs([](const ExperimentConfig& c, int) { return figures(c)["pct_error_flip"].get<double>(); })};
    t["metrics.mse_threshold"] = {{}, {"metrics.mse_threshold=0.05"}, Renders::None, false,
                                  differs([](const ExperimentConfig& c, int) { return figures(c)["pct_error_mse"].get<double>(); })};
    t["metrics.ppd"] = {{}, {"metrics.ppd=10"}, Renders::None, false,
                        differs([](const ExperimentConfig& c, int) { return figures(c)["flip_mean"].get<double>(); })};
    t["metrics.map_quality"] = {{}, {"metrics.map_quality=false"}, Renders::None, false,
                                differs([](const ExperimentConfig& c, int) { return tracedJobs(c); })};
    t["metrics.causes"] = {{}, {"metrics.causes=false"}, Renders::None, false,
                           differs([](const ExperimentConfig& c, int) { return causesReported(c); })};
    t["metrics.oracle"] = {{}, {"metrics.oracle=true"}, Renders::None, false,
                           differs([](const ExperimentConfig& c, int) { return tracedJobs(c); })};
    t["timing.same_machine"] = {{}, {"timing.same_machine=true"}, Renders::None, false,
                                differs([](const ExperimentConfig& c, int) { return workGroups(c); })};
    t["report.plots"] = {{}, {"report.plots=false"}, Renders::None, false,
                         becomes([](const ExperimentConfig& c, int) { return c.report.plots; }, false)};
    t["timing.repeats"] = {{}, {"timing.repeats=3"}, Renders::None, false,
                           differs([](const ExperimentConfig& c, int) { return tracedJobs(c).size(); })};
    t["timing.interleave"] = {{"timing.repeats=3"}, {"timing.interleave=false"}, Renders::None, false,
                              differs([](const ExperimentConfig& c, int) { return tracedJobs(c); })};
    // Lights: every image and the Snapshot, through addLights. In the "lists" base index 0 is a
    // point light, 1 a spot, 2 a quad, 3 a disk; in "infinity" 0 is directional, 1 an environment map.
    const auto light = [&](const std::string& key, std::vector<std::string> set, Renders renders = Renders::All) {
        t["lights.#." + key] = {{}, std::move(set), renders, true,
                                differs([](const ExperimentConfig& c, int) { return sceneLights(c); })};
    };
    light("type", {"lights.0.type=spot", "lights.0.direction=[0, -1, 0]"});
    light("name", {"lights.#.name=renamed"}, Renders::Any);
    light("position", {"lights.#.position=[0.1, 1.2, 0.3]"});
    light("intensity", {"lights.#.intensity=[7, 6, 5]"});
    light("radiance", {"lights.#.radiance=[7, 6, 5]"});
    light("power", {"lights.#.power=[70, 60, 50]"});
    light("normal", {"lights.#.normal=[0, -1, 0.5]"});
    light("direction", {"lights.#.direction=[0.2, -1, 0]"});
    light("inner_angle", {"lights.#.inner_angle=10"});
    light("outer_angle", {"lights.#.outer_angle=30"});
    light("up", {"lights.#.up=[1, 0, 0]"});
    light("size", {"lights.#.size=[0.3, 0.2]"});
    light("radius", {"lights.#.radius=0.2"});
    light("segments", {"lights.#.segments=12"});
    light("irradiance", {"lights.#.irradiance=[3, 2, 1]"});
    light("map", {"lights.#.map=" + (dir / "sky2.exr").string()});
    light("scale", {"lights.#.scale=2.5"});
    light("rotation", {"lights.#.rotation=45"});
    return t;
}

// A value of a strategy parameter other than its default, inside its declared range.
std::optional<std::string> otherValue(const ParamSpec& p) {
    if (p.type == ParamType::Choice) {
        if (p.choices.size() < 2) return std::nullopt;
        return p.choices[1];  // the first is the default
    }
    if (p.lo == p.hi) return std::nullopt;
    const bool integer = p.type == ParamType::Int;
    double v = p.defaultValue < p.hi ? (integer ? p.defaultValue + 1 : (p.defaultValue + p.hi) / 2) : p.lo;
    if (!integer && p.defaultValue < p.hi && p.hi > 1e3) v = p.defaultValue + 1;  // a finite, readable value
    return formatNumber(v);
}

// --- The walk --------------------------------------------------------------------------------

// Dotted paths of every leaf of the canonical JSON; list items by index, a render's `params`
// folded into the render ("renders.3.spacing", as --set spells them).
void leaves(const Json& j, const std::string& path, std::vector<std::string>& out) {
    if (j.is_object()) {
        for (const auto& [k, v] : j.items()) {
            if (k == "params") leaves(v, path, out);
            else leaves(v, path.empty() ? k : path + "." + k, out);
        }
    } else if (j.is_array() && !j.empty() && j.front().is_object()) {
        for (std::size_t i = 0; i < j.size(); ++i) leaves(j[i], fmt::format("{}.{}", path, i), out);
    } else {
        out.push_back(path);
    }
}

// "renders.3.spacing" -> ("renders.#.spacing", 3).
std::pair<std::string, int> generic(const std::string& key) {
    for (const char* list : {"renders.", "lights."}) {
        if (!key.starts_with(list)) continue;
        const std::size_t start = std::string(list).size(), dot = key.find('.', start);
        return {std::string(list) + "#" + key.substr(dot), std::stoi(key.substr(start, dot - start))};
    }
    return {key, -1};
}

std::string replaceIndex(std::string text, int index) {
    if (const std::size_t at = text.find('#'); at != std::string::npos) text.replace(at, 1, std::to_string(index));
    return text;
}

class SettingsReach : public ::testing::Test {
protected:
    void SetUp() override {
        dir_.write("two.vf", "rview -vtv -vp 0 1.1 3.7 -vd 0 0 -1 -vu 0 1 0 -vh 40 -vv 40\n"
                             "rview -vtv -vp 0.5 1.2 3.5 -vd -0.1 -0.1 -1 -vu 0 1 0 -vh 35 -vv 35\n");
        dir_.write("lights.yaml", "- {type: point, name: bulb, position: [0, 1.5, 0], intensity: [2, 2, 2]}\n");
        dir_.write("other_lights.yaml", "- {type: point, name: bulb, position: [0, 1.5, 0], intensity: [3, 2, 2]}\n");
        // Every strategy once, every light type, the default sections.
        std::string renders;
        for (const StrategyDescriptor& s : strategyRegistry())
            renders += fmt::format("  - {{strategy: {}, rpp: 4}}\n", s.name);
        bases_["lists"] = "scene: builtin:cornell\n"
                          "lights:\n"
                          "  - {type: point, name: p, position: [0, 1.5, 0], intensity: [2, 2, 2]}\n"
                          "  - {type: spot, name: s, position: [0, 1.9, 0], direction: [0, -1, 0], intensity: [3, 3, 3]}\n"
                          "  - {type: quad, name: q, position: [0, 1.95, 0], normal: [0, -1, 0], up: [0, 0, 1],\n"
                          "     size: [0.5, 0.4], radiance: [4, 4, 4]}\n"
                          "  - {type: disk, name: d, position: [0.5, 1.95, 0.5], normal: [0, -1, 0], radius: 0.1,\n"
                          "     power: [10, 10, 10]}\n"
                          "renders:\n" + renders;
        // The keys that appear only when set: a camera, a light file, non-default timing.
        bases_["camera"] = "scene: builtin:cornell\n"
                           "camera: {position: [0, 1, 3.9], look_at: [0, 1, 0]}\n"
                           "snapshot: {map: combined}\n"
                           "image: {filter: gaussian}\n"  // the filter keys appear only when not the box
                           "shading: {texture_filter: none, hide_emitters: true}\n"  // likewise, when not the default
                           "light_file: lights.yaml\n"
                           "timing: {repeats: 2}\n"
                           "renders:\n  - {strategy: uniform, rpp: 4}\n  - {strategy: aamap, rpp: 4}\n";
        // Lights at infinity, and the keys that appear only when not at their defaults.
        ImageRGB sky(8, 4), otherSky(8, 4);
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 8; ++x) {
                sky.at(x, y) = glm::vec3(0.2f + 0.1f * static_cast<float>(x), 0.5f, 1.0f - 0.2f * static_cast<float>(y));
                otherSky.at(x, y) = sky.at(x, y) * 1.5f;
            }
        writeExr(dir_.path() / "sky.exr", sky);
        writeExr(dir_.path() / "sky2.exr", otherSky);
        bases_["infinity"] = "scene: builtin:cornell\n"
                             "lights:\n"
                             "  - {type: directional, name: sun, direction: [0.3, -1, 0.2], irradiance: [2, 2, 2]}\n"
                             "  - {type: environment, name: sky, map: sky.exr, scale: 1.5, rotation: 30, up: [0, 1, 0]}\n"
                             "snapshot: {environment_lights: 2, soft_shadows: false, map: subpixel, subpixel: 3}\n"
                             "shading: {mode: cache, cache: {bounces: 2, divisions: 64, supersamples: 32, accuracy: 0.25,\n"
                             "          resolution: 32, grid_step: 8}}\n"
                             "metrics: {causes: false, oracle: true}\n"
                             "timing: {same_machine: true}\n"
                             "renders:\n  - {strategy: uniform, rpp: 4}\n  - {strategy: aamap, rpp: 4}\n";
    }

    ExperimentConfig parse(const std::string& base, const std::vector<std::string>& overrides) const {
        return parseConfig(bases_.at(base), dir_.path() / "exp.yaml", overrides);
    }

    test::TempDir dir_;
    std::map<std::string, std::string> bases_;
};

TEST_F(SettingsReach, EveryKeyChangesItsRendersItsSnapshotAndItsConsumer) {
    std::map<std::string, Alternative> table = alternatives(dir_.path());
    // Strategy parameters: an alternative for each, from the strategies table itself.
    for (const StrategyDescriptor& s : strategyRegistry())
        for (const ParamSpec& p : s.params) {
            const auto value = otherValue(p);
            if (!value) continue;  // reported below, as a key without an alternative
            table.try_emplace(
                "renders.#." + p.name,
                Alternative{{}, {"renders.#." + p.name + "=" + *value}, Renders::This, false,
                            differs([](const ExperimentConfig& c, int i) {
                                const ImageGrey map(4, 4, 0.5f);
                                return describe(toStrategySettings(c.renders[i], &map));
                            })});
        }

    // Every key, the first base (and list index) it appears in.
    std::vector<std::tuple<std::string, std::string, int>> keys;  // generic key, base, index
    std::set<std::string> seen;
    for (const std::string base : {"lists", "camera", "infinity"}) {
        std::vector<std::string> found;
        leaves(Json::parse(parse(base, {}).canonicalJson()), "", found);
        for (const std::string& key : found) {
            const auto [g, index] = generic(key);
            if (seen.insert(g).second) keys.emplace_back(g, base, index);
        }
    }
    // Every strategy parameter must have been found (the base runs every strategy).
    for (const std::string& p : allStrategyParamNames())
        EXPECT_TRUE(seen.contains("renders.#." + p)) << "parameter " << p << " missing from the canonical JSON";
    // Every key --set accepts must be walked: one that the bases never write (a key present only
    // when it is not at its default, say) needs a base that writes it.
    for (const std::string& k : settableKeys())
        EXPECT_TRUE(seen.contains(k)) << "the key " << k << " is in no base config's canonical JSON: walk it";

    for (const auto& [key, base, index] : keys) {
        SCOPED_TRACE(fmt::format("key {} (index {}, base '{}')", key, index, base));
        const auto it = table.find(key);
        if (it == table.end()) {
            ADD_FAILURE() << "no alternative value for the key '" << key
                          << "': add one saying which renders and consumer it must change";
            continue;
        }
        const Alternative& alt = it->second;
        std::vector<std::string> after = alt.given;
        for (const std::string& s : alt.set) after.push_back(replaceIndex(s, index));
        const ExperimentConfig before = parse(base, alt.given);
        ExperimentConfig changed;
        try {
            changed = parse(base, after);
        } catch (const std::exception& e) {
            ADD_FAILURE() << "the alternative does not parse: " << e.what();
            continue;
        }
        if (key != "threads") {
            EXPECT_NE(before.hash(), changed.hash()) << "the config hash ignores it";
        }
        ASSERT_EQ(before.renders.size(), changed.renders.size());
        for (std::size_t r = 0; r < before.renders.size(); ++r) {
            const StrategyDescriptor* info = findStrategy(before.renders[r].strategy);
            bool must = false;
            switch (alt.renders) {
                case Renders::All: must = true; break;
                case Renders::UsingAamap: must = info->usesAamap; break;
                case Renders::This: must = static_cast<int>(r) == index; break;
                case Renders::None: must = false; break;
                case Renders::Any: continue;
            }
            const bool changedKey = renderKey(before, before.renders[r]) != renderKey(changed, changed.renders[r]);
            EXPECT_EQ(changedKey, must) << "render " << before.renders[r].name << ": its cache key "
                                        << (must ? "ignores" : "depends on") << " the setting";
        }
        if (alt.renders != Renders::Any) {
            EXPECT_EQ(snapshotKey(before) != snapshotKey(changed), alt.snapshot)
                << "the Snapshot's cache key " << (alt.snapshot ? "ignores" : "depends on") << " the setting";
        }
        alt.reaches({base, before, changed, index});
    }
}

TEST_F(SettingsReach, EveryStrategyParameterHasAnAlternativeInRange) {
    for (const StrategyDescriptor& s : strategyRegistry())
        for (const ParamSpec& p : s.params) {
            const auto value = otherValue(p);
            ASSERT_TRUE(value) << s.name << "." << p.name << ": no second value in its range";
            EXPECT_NO_THROW(parse("camera", {fmt::format("renders.0.strategy={}", s.name),
                                             fmt::format("renders.0.{}={}", p.name, *value)}))
                << s.name << "." << p.name << "=" << *value;
        }
}

}  // namespace
}  // namespace aamap
