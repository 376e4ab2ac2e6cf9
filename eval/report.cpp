#include "eval/report.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "eval/config.h"
#include "eval/evaluate.h"
#include "tracer/strategy.h"
#include "eval/metrics/pixel_causes.h"

namespace aamap {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

double numberOr(const Json& j, const char* key, double fallback) {
    return j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

double renderSeconds(const Json& r) {
    if (!r.contains("times_s") || !r["times_s"].is_object()) return 0.0;
    const Json& t = r["times_s"];
    const auto seconds = [&](const char* key) { return t.contains(key) && t[key].is_number() ? t[key].get<double>() : 0.0; };
    return seconds("trace") + seconds("snapshot_total");
}

namespace {


// The render time's median and the range its timed runs spanned (timing.repeats): the trace runs
// plus the Snapshot's per-frame cost. One run (or a record without trace_runs): min = max = median.
struct TimeRange {
    double median = NAN, min = NAN, max = NAN;
    int runs = 1;
};

TimeRange renderTimeRange(const Json& r) {
    const double snapshot = numberOr(r["times_s"], "snapshot_total", 0);
    TimeRange t{renderSeconds(r), renderSeconds(r), renderSeconds(r), 1};
    const Json& times = r["times_s"];
    if (times.contains("trace_runs") && times["trace_runs"].is_array() && !times["trace_runs"].empty()) {
        const auto runs = times["trace_runs"].get<std::vector<double>>();
        t.min = *std::min_element(runs.begin(), runs.end()) + snapshot;
        t.max = *std::max_element(runs.begin(), runs.end()) + snapshot;
        t.runs = static_cast<int>(runs.size());
    }
    return t;
}

// A speedup b/r as its median ratio and the range the runs allow: from the fastest baseline run
// over the slowest series run (the worst case) to the reverse (the best).
TimeRange speedupRange(const Json& baseline, const Json& r) {
    const TimeRange b = renderTimeRange(baseline), s = renderTimeRange(r);
    if (!(s.median > 0 && s.min > 0)) return {};
    return {b.median / s.median, b.min / s.max, b.max / s.min, std::min(b.runs, s.runs)};
}

// "1.23" for one run, "1.23 (1.10-1.41)" when repeated runs give a spread.
std::string rangeCell(const TimeRange& t, const char* format) {
    if (!std::isfinite(t.median)) return "—";
    const std::string median = fmt::format(fmt::runtime(format), t.median);
    if (t.runs < 2) return median;
    return fmt::format("{} ({}–{})", median, fmt::format(fmt::runtime(format), t.min), fmt::format(fmt::runtime(format), t.max));
}

std::string cell(double v, const char* format = "{:.2f}") { return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : "—"; }

std::vector<int> rppRows(const Json& renders) {
    std::vector<int> rpp;
    for (const Json& r : renders) rpp.push_back(r["max_rays_per_pixel"].get<int>());
    std::sort(rpp.begin(), rpp.end());
    rpp.erase(std::unique(rpp.begin(), rpp.end()), rpp.end());
    return rpp;
}

std::vector<std::string> seriesColumns(const Json& renders) {
    std::vector<std::string> series;
    for (const Json& r : renders) {
        const std::string s = r.value("series", r["strategy"].get<std::string>());
        if (std::find(series.begin(), series.end(), s) == series.end()) series.push_back(s);
    }
    return series;
}

const Json* find(const Json& renders, int rpp, const std::string& series) {
    for (const Json& r : renders)
        if (r["max_rays_per_pixel"].get<int>() == rpp && r.value("series", std::string()) == series) return &r;
    return nullptr;
}

// The baseline of speedups: the first uniform series (the paper's "standard" render).
std::string baselineSeries(const Json& renders) {
    for (const Json& r : renders)
        if (r["strategy"] == baselineStrategyName()) return r.value("series", baselineStrategyName());
    return "";
}


std::string paramsText(const Json& r) {
    std::vector<std::string> parts;
    for (const auto& [k, v] : r["parameters"].items())
        if ((v.is_number() || v.is_string()) && k != "strata" && k != "seed" && k != "shading_area_light_samples" && k != "rpp" &&
            k != "snapshot_key")
            parts.push_back(fmt::format("{}={}", k, v.is_string() ? v.get<std::string>() : v.dump()));
    return fmt::format("{}", fmt::join(parts, ";"));
}

// Tables of causes (eval/metrics/pixel_causes.h): one row for the map (true aliasing it missed,
// flags it wasted) and one per render, a column per cause that occurs anywhere.
void addCauseTables(const Json& results, std::vector<Table>& tables) {
    std::vector<std::pair<std::string, const Json*>> rows;
    if (results.contains("map_quality") && results["map_quality"].contains("causes"))
        rows.emplace_back("aamap (1-ray)", &results["map_quality"]["causes"]);
    for (const Json& r : results["renders"])
        if (r.contains("metrics") && r["metrics"].contains("causes"))
            rows.emplace_back(r["name"].get<std::string>(), &r["metrics"]["causes"]);
    if (rows.empty()) return;
    const double t = numberOr(results["config"]["metrics"], "flip_threshold", 0.1);
    for (const char* kind : {"missed", "wasted"}) {
        const bool missed = std::string(kind) == "missed";
        std::vector<int> used;
        for (int i = 0; i < metrics::kPixelCauses; ++i) {
            const char* k = metrics::key(static_cast<metrics::PixelCause>(i));
            if (std::any_of(rows.begin(), rows.end(), [&](const auto& row) {
                    return (*row.second)[kind].value(k, std::uint64_t{0}) > 0;
                }))
                used.push_back(i);
        }
        Table table{missed ? "causes_missed" : "causes_wasted",
                    missed ? "Causes: why error pixels remain" : "Causes: where extra rays bought nothing",
                    missed ? fmt::format("pixels with LDR-FLIP > {} against the reference, by what the tracer sees in "
                                         "them; aamap row: true aliasing the map did not flag", t)
                           : fmt::format("pixels given more than one primary ray although the 1-ray image is within "
                                         "FLIP {} there; aamap row: flagged pixels that are not truly aliased", t),
                    {"render", "pixels"}, {}};
        for (int i : used) table.header.push_back(metrics::toString(static_cast<metrics::PixelCause>(i)));
        for (const auto& [name, causes] : rows) {
            std::vector<std::string> row{name, std::to_string((*causes).value(std::string(kind) + "_total", std::uint64_t{0}))};
            for (int i : used)
                row.push_back(std::to_string((*causes)[kind].value(metrics::key(static_cast<metrics::PixelCause>(i)),
                                                                    std::uint64_t{0})));
            table.rows.push_back(std::move(row));
        }
        tables.push_back(std::move(table));
    }
}

// Error against ground truth, split: the shading floor's error is the shading mode's bias; each
// render's error against the floor is the antialiasing it still lacks (eval/runner.cpp).
void addGroundTruthTable(const Json& results, std::vector<Table>& tables) {
    const Json& ref = results["reference"];
    if (!ref.contains("shading_floor")) return;
    const std::string floor = ref["shading_floor"].get<std::string>();
    const std::string truth = ref.value("type", std::string()) == toString(ReferenceType::File)
                                  ? "the reference image " + ref.value("path", std::string())
                                  : fmt::format("the {} rpp {} reference", ref.value("rpp", 0), ref.value("mode", std::string()));
    const std::string mode = results["config"].contains("shading") ? results["config"]["shading"].value("mode", std::string())
                                                                    : std::string();
    Table t{"ground_truth", "Error against ground truth: shading bias and antialiasing",
            fmt::format("total: against {}; shading bias: {} ({} shading, the most-sampled uniform render) against it; "
                        "antialiasing: each render against {}, the same shading",
                        truth, floor, mode, floor),
            {"name", "series", "rpp", "time (s)", "total FLIP mean", "total % FLIP", "antialiasing FLIP mean",
             "antialiasing % FLIP", "antialiasing % MSE"},
            {}};
    for (const Json& r : results["renders"]) {
        const Json m = r.contains("metrics") ? r["metrics"] : Json::object();
        const bool isFloor = r["name"].get<std::string>() == floor;
        const Json aa = m.contains("antialiasing") ? m["antialiasing"] : Json::object();
        t.rows.push_back({r["name"].get<std::string>() + (isFloor ? " (shading bias)" : ""), r.value("series", std::string()),
                          std::to_string(r["max_rays_per_pixel"].get<int>()), rangeCell(renderTimeRange(r), "{:.3f}"),
                          cell(numberOr(m, "flip_mean"), "{:.4f}"), cell(numberOr(m, "pct_error_flip")),
                          isFloor ? "0" : cell(numberOr(aa, "flip_mean"), "{:.4f}"), isFloor ? "0" : cell(numberOr(aa, "pct_error_flip")),
                          isFloor ? "0" : cell(numberOr(aa, "pct_error_mse"))});
    }
    tables.push_back(t);
}

// Each aamap-driven render beside the same render on the oracle map (eval/runner.cpp): the oracle
// is the bound, so its speedup and error say how far the map is from the best map.
void addOracleTable(const Json& results, std::vector<Table>& tables) {
    if (!results.contains("oracle")) return;
    const Json& renders = results["renders"];
    const std::string base = baselineSeries(renders);
    const double flipT = numberOr(results["config"]["metrics"], "flip_threshold", 0.1);
    Table t{"oracle", "The map against the oracle map",
            fmt::format("oracle map: true aliasing (1-ray FLIP against the reference above {}), grown until the image "
                        "taking the reference on it and the 1-ray image elsewhere has no new error pixel ({} round(s), "
                        "{}% of the image, {}% error left); given the full budget; its time is the trace alone. "
                        "Speedups over {} at the same rpp; efficiency: the map's speedup as a fraction of the oracle's",
                        readableNumber(flipT), static_cast<int>(numberOr(results["oracle"], "rounds", 0)),
                        cell(100 * numberOr(results["oracle"], "flagged_fraction"), "{:.1f}"),
                        cell(numberOr(results["oracle"], "residual_pct_error_flip"), "{:.2f}"),
                        base.empty() ? std::string("uniform (none in the experiment)") : base),
            {"render", "rpp", "time (s)", "oracle time (s)", "speedup", "oracle speedup", "efficiency", "% FLIP",
             "oracle % FLIP", "mean rpp", "oracle mean rpp"},
            {}};
    for (const Json& run : results["oracle"]["runs"]) {
        const Json& o = run["render"];
        const std::string name = run["map_render"].get<std::string>();
        const auto map = std::find_if(renders.begin(), renders.end(), [&](const Json& r) { return r["name"] == name; });
        if (map == renders.end()) continue;
        const int rpp = (*map)["max_rays_per_pixel"].get<int>();
        const Json* b = base.empty() ? nullptr : find(renders, rpp, base);
        const TimeRange mapSpeedup = b ? speedupRange(*b, *map) : TimeRange{};
        const TimeRange oracleSpeedup = b ? speedupRange(*b, o) : TimeRange{};
        const Json mm = map->contains("metrics") ? (*map)["metrics"] : Json::object();
        const Json om = o.contains("metrics") ? o["metrics"] : Json::object();
        t.rows.push_back({name, std::to_string(rpp), rangeCell(renderTimeRange(*map), "{:.3f}"),
                          rangeCell(renderTimeRange(o), "{:.3f}"), rangeCell(mapSpeedup, "{:.2f}"),
                          rangeCell(oracleSpeedup, "{:.2f}"), cell(mapSpeedup.median / oracleSpeedup.median),
                          cell(numberOr(mm, "pct_error_flip")), cell(numberOr(om, "pct_error_flip")),
                          cell(numberOr(*map, "mean_primary_rpp")), cell(numberOr(o, "mean_primary_rpp"))});
    }
    tables.push_back(t);
}

// A traced reference whose own noise puts more pixels in error than kNoisyFloorPercent
// (eval/evaluate.h): the error-pixel figures measured against it are not reported.
bool noisyReference(const Json& results) {
    if (!results.contains("reference") || !results["reference"].is_object()) return false;
    const Json& ref = results["reference"];
    return ref.contains("noise") && ref["noise"].is_object() && ref["noise"].value("noisy", false);
}

// What every error figure is measured against, and how converged it is.
void addReferenceTable(const Json& results, std::vector<Table>& tables) {
    if (!results.contains("reference") || !results["reference"].is_object()) return;
    const Json& ref = results["reference"];
    const std::string type = ref.value("type", std::string());
    if (type.empty() || type == toString(ReferenceType::None)) return;
    Table t{"reference", "The reference", "", {"reference", "noise floor % FLIP", "noise floor % MSE", "converged", "suggested rpp"}, {}};
    const std::string what = type == toString(ReferenceType::File) ? "the image " + ref.value("path", std::string())
                                            : fmt::format("uniform {} rpp, {} shading", ref.value("rpp", 0), ref.value("mode", std::string()));
    if (!ref.contains("noise") || !ref["noise"].is_object()) {
        t.rows.push_back({what, "—", "—", "not estimated", "—"});
        t.note = type == toString(ReferenceType::File) ? "an image from elsewhere: its convergence is its maker's to state"
                                : "not estimated (one ray per pixel, or a cache entry without its half images)";
    } else {
        const Json& n = ref["noise"];
        const Json& suggested = n["suggested_rpp"];
        t.rows.push_back({what, cell(numberOr(n, "pct_error_flip")), cell(numberOr(n, "pct_error_mse")),
                          n.value("converged", false) ? "yes" : "no",
                          suggested.is_number() ? std::to_string(suggested.get<int>()) : "over " + std::to_string(kMaxSuggestedRpp)});
        t.note = fmt::format("noise floor: the pixels its own noise puts in error (the reference against itself plus half "
                             "the difference of two half images of its samples); converged: at most {}% by FLIP (else "
                             "MSE); suggested rpp: the rays per pixel that would make it so",
                             readableNumber(kConvergedFloorPercent));
    }
    tables.push_back(t);
}

}  // namespace

std::vector<Table> reportTables(const Json& results) {
    const Json& renders = results["renders"];
    const std::vector<int> rpps = rppRows(renders);
    const std::vector<std::string> series = seriesColumns(renders);
    const std::string base = baselineSeries(renders);
    std::vector<Table> tables;

    Table time{"time", "Table 1/2: render time (s) per rays per pixel",
               "time = trace + Snapshot per frame (for aamap-driven series); scene load, BVH build and Snapshot setup, shared by all, "
               "are left out. With timing.repeats > 1: the median, then (min–max) over the timed runs",
               {"rpp"}, {}};
    for (const std::string& s : series) time.header.push_back(s);
    for (int rpp : rpps) {
        std::vector<std::string> row{std::to_string(rpp)};
        for (const std::string& s : series) {
            const Json* r = find(renders, rpp, s);
            row.push_back(r ? rangeCell(renderTimeRange(*r), "{:.3f}") : "");
        }
        time.rows.push_back(row);
    }
    tables.push_back(time);

    Table speed{"speedup", "Table 1/2: speedup over " + (base.empty() ? baselineStrategyName() : base),
                base.empty() ? "no uniform render in the experiment: no baseline"
                             : "baseline time / series time at the same rpp; with timing.repeats > 1, the ratio of medians, "
                               "then (min–max): the fastest baseline run over the slowest series run, and the reverse",
                {"rpp"}, {}};
    for (const std::string& s : series)
        if (s != base) speed.header.push_back(s);
    for (int rpp : rpps) {
        std::vector<std::string> row{std::to_string(rpp)};
        const Json* b = base.empty() ? nullptr : find(renders, rpp, base);
        for (const std::string& s : series) {
            if (s == base) continue;
            const Json* r = find(renders, rpp, s);
            row.push_back(r && b ? rangeCell(speedupRange(*b, *r), "{:.2f}") : "");
        }
        speed.rows.push_back(row);
    }
    tables.push_back(speed);

    const double flipT = numberOr(results["config"]["metrics"], "flip_threshold", 0.1);
    Table error{"error", "Table 3: % error pixels against the reference",
                fmt::format("FLIP: pixels with LDR-FLIP > {}; MSE: pixels whose display-space squared error >= {:.3g}",
                            flipT, numberOr(results["config"]["metrics"], "mse_threshold", 0)),
                {"rpp"}, {}};
    for (const std::string& s : series) {
        error.header.push_back(s + " FLIP");
        error.header.push_back(s + " MSE");
    }
    const bool noisy = noisyReference(results);
    if (noisy)
        error.note = fmt::format("not reported: the reference is noisy (its own noise puts {}% of pixels in error; see "
                                 "The reference)",
                                 readableNumber(numberOr(results["reference"]["noise"], "floor_pct")));
    for (int rpp : rpps) {
        std::vector<std::string> row{std::to_string(rpp)};
        for (const std::string& s : series) {
            const Json* r = find(renders, rpp, s);
            const Json m = r && r->contains("metrics") ? (*r)["metrics"] : Json::object();
            row.push_back(!r ? "" : noisy ? "—" : cell(numberOr(m, "pct_error_flip")));
            row.push_back(!r ? "" : noisy ? "—" : cell(numberOr(m, "pct_error_mse")));
        }
        error.rows.push_back(row);
    }
    tables.push_back(error);
    addReferenceTable(results, tables);

    addGroundTruthTable(results, tables);

    Table all{"renders", "All renders", "cached: reused from an earlier run of this folder",
              {"name", "series", "rpp", "time (s)", "timed runs", "mean rpp", "rays", "PSNR (dB)", "FLIP mean", "% FLIP", "% MSE", "cached"},
              {}};
    for (const Json& r : renders) {
        const Json m = r.contains("metrics") ? r["metrics"] : Json::object();
        all.rows.push_back({r["name"].get<std::string>(), r.value("series", std::string()),
                            std::to_string(r["max_rays_per_pixel"].get<int>()), rangeCell(renderTimeRange(r), "{:.3f}"),
                            std::to_string(renderTimeRange(r).runs), cell(numberOr(r, "mean_primary_rpp")), std::to_string(r["rays"]["total"].get<std::uint64_t>()),
                            m.contains("psnr") && m["psnr"].is_null() ? "inf" : cell(numberOr(m, "psnr")),
                            cell(numberOr(m, "flip_mean"), "{:.4f}"), noisy ? "—" : cell(numberOr(m, "pct_error_flip")),
                            noisy ? "—" : cell(numberOr(m, "pct_error_mse")), r.value("cached", false) ? "yes" : "no"});
    }
    tables.push_back(all);

    if (results.contains("map_quality")) {
        const Json& q = results["map_quality"];
        // own_*: absent in results written before they existed.
        const auto count = [&](const char* key) {
            return q.contains(key) ? std::to_string(q[key].get<std::uint64_t>()) : std::string();
        };
        tables.push_back({"map_quality", "Map quality: the aamap against true aliasing",
                          fmt::format("true aliasing: pixels where FLIP(1-ray, reference) > {}; own: those whose own "
                                      "8-bit display value differs too (FLIP also rises beside a high-contrast "
                                      "error, where the images agree); flagged: aamap > 0",
                                      readableNumber(numberOr(q, "threshold"))),
                          {"recall", "own recall", "precision", "flagged %", "true aliasing %", "true pixels",
                           "own true pixels", "flagged pixels"},
                          {{cell(numberOr(q, "recall"), "{:.3f}"),
                            q.contains("own_recall") ? cell(numberOr(q, "own_recall"), "{:.3f}") : std::string(),
                            cell(numberOr(q, "precision"), "{:.3f}"), cell(100 * numberOr(q, "flagged_fraction")),
                            cell(100 * numberOr(q, "true_fraction")), count("true_pixels"), count("own_true_pixels"),
                            count("flagged_pixels")}}});
    }
    addOracleTable(results, tables);
    addCauseTables(results, tables);
    return tables;
}

const std::vector<std::string>& resultsCsvColumns() {
    static const std::vector<std::string> columns = {
        "name", "series", "strategy", "rpp", "params", "width", "height", "time_s", "trace_s", "snapshot_s",
        "total_s", "time_min_s", "time_max_s", "trace_runs", "speedup", "speedup_min", "speedup_max", "mean_primary_rpp", "rays_primary", "rays_total", "mse", "rmse", "psnr",
        "pct_error_mse", "flip_mean", "pct_error_flip", "flip_hdr_mean", "pct_error_flip_hdr", "cached", "key",
        "git_revision"};
    return columns;
}

std::string resultsCsv(const Json& results) {
    const Json& renders = results["renders"];
    const std::string base = baselineSeries(renders);
    std::string out = fmt::format("{}\n", fmt::join(resultsCsvColumns(), ","));
    const auto value = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); };
    for (const Json& r : renders) {
        const Json m = r.contains("metrics") ? r["metrics"] : Json::object();
        const int rpp = r["max_rays_per_pixel"].get<int>();
        const Json* b = base.empty() ? nullptr : find(renders, rpp, base);
        const TimeRange time = renderTimeRange(r);
        const TimeRange speedup = b ? speedupRange(*b, r) : TimeRange{};
        std::vector<std::string> f = {
            csvField(r["name"].get<std::string>()), csvField(r.value("series", std::string())),
            r["strategy"].get<std::string>(), std::to_string(rpp), csvField(paramsText(r)),
            std::to_string(r["width"].get<int>()), std::to_string(r["height"].get<int>()), value(renderSeconds(r)),
            value(numberOr(r["times_s"], "trace")), value(numberOr(r["times_s"], "snapshot_total")),
            value(numberOr(r["times_s"], "total")), value(time.min), value(time.max), std::to_string(time.runs),
            value(speedup.median), value(speedup.min), value(speedup.max), value(numberOr(r, "mean_primary_rpp")),
            std::to_string(r["rays"]["primary"].get<std::uint64_t>()), std::to_string(r["rays"]["total"].get<std::uint64_t>()),
            value(numberOr(m, "mse")), value(numberOr(m, "rmse")),
            m.contains("psnr") && m["psnr"].is_null() ? "inf" : value(numberOr(m, "psnr")), value(numberOr(m, "pct_error_mse")),
            value(numberOr(m, "flip_mean")), value(numberOr(m, "pct_error_flip")), value(numberOr(m, "flip_hdr_mean")),
            value(numberOr(m, "pct_error_flip_hdr")), r.value("cached", false) ? "1" : "0", r.value("key", std::string()),
            csvField(r["git_revision"].get<std::string>())};
        out += fmt::format("{}\n", fmt::join(f, ","));
    }
    return out;
}

std::optional<Table> snapshotCostTable(const Json& results) {
    if (!results.contains("snapshot") || !results["snapshot"].is_object()) return std::nullopt;
    const Json& s = results["snapshot"];
    Table t{"snapshot_cost", "Snapshot cost", "", {"", "value"}, {}};
    if (s.contains("width") && s.contains("height"))
        t.rows.push_back({"resolution", fmt::format("{} × {}", s["width"].get<int>(), s["height"].get<int>())});
    t.rows.push_back({"per frame (ms)", readableNumber(1000 * numberOr(s, "total_s"))});
    if (s.contains("readback_s")) t.rows.push_back({"of which readback (ms)", readableNumber(1000 * numberOr(s, "readback_s"))});
    if (s.contains("setup_s")) t.rows.push_back({"setup, once (ms)", readableNumber(1000 * numberOr(s, "setup_s"))});
    const Json passes = s.value("passes_gpu_ms", Json::object());  // items() must not outlive it
    std::vector<std::string> perPass;
    for (const auto& [pass, ms] : passes.items())
        if (ms.is_number()) perPass.push_back(fmt::format("{} {}", pass, readableNumber(ms.get<double>())));
    if (!perPass.empty()) t.rows.push_back({"GPU per pass (ms)", fmt::format("{}", fmt::join(perPass, ", "))});
    t.note = fmt::format("on {}{}; per frame is what Table 1/2 adds to each aamap-driven render's trace",
                         s.value("vulkan_device", std::string("the Vulkan device")),
                         s.value("cached", false) ? ", measured when it was first made (reused from the cache)" : "");
    return t;
}

std::string markdownReport(const Json& results, const std::vector<Table>& tables) {
    std::string md = fmt::format("# aamap experiment report\n\nconfig hash `{}`, git revision `{}`\n\n",
                                 results.value("config_hash", std::string()), results.value("git_revision", std::string()));
    for (const Json& w : results["warnings"]) md += fmt::format("> **warning:** {}\n\n", w.get<std::string>());
    for (const Table& t : tables) md += markdownTable(t);
    if (const std::optional<Table> cost = snapshotCostTable(results)) md += markdownTable(*cost);
    return md;
}

std::string markdownTable(const Table& t, const std::string& heading) {
    std::string rule = "|";
    for (std::size_t i = 0; i < t.header.size(); ++i) rule += "---|";
    std::string md = fmt::format("{} {}\n\n| {} |\n{}\n", heading, t.title, fmt::join(t.header, " | "), rule);
    for (const auto& row : t.rows) md += fmt::format("| {} |\n", fmt::join(row, " | "));
    return md + fmt::format("\n{}\n\n", t.note);
}

namespace {
constexpr const char* kPlotFiles[] = {"plots/time_vs_rpp.png", "plots/error_vs_time.png", "plots/psnr_vs_time.png"};
}  // namespace

namespace {
// Runs tools/report_plots.py with `args` in the venv's Python; `files` (relative to outDir) are
// removed first, so that plots of an earlier run never pass for this one's when the script fails.
PlotRun runPlotScript(const fs::path& outDir, const std::vector<std::string>& args, const std::vector<std::string>& files) {
    PlotRun run;
    const char* envPython = std::getenv("AAMAP_PYTHON");
    const char* envScript = std::getenv("AAMAP_REPORT_PLOTS");
    const fs::path python = envPython && *envPython ? fs::path(envPython) : fs::path(AAMAP_SOURCE_DIR) / ".venv/bin/python";
    const fs::path script = envScript && *envScript ? fs::path(envScript) : fs::path(AAMAP_SOURCE_DIR) / "tools/report_plots.py";
    if (::access(python.c_str(), X_OK) != 0) {
        run.warning = fmt::format("no plots: Python venv not found at {} (run tools/python-env.sh, then `aamap report "
                                  "{}`)", python.string(), outDir.string());
    } else if (!fs::is_regular_file(script)) {
        run.warning = fmt::format("no plots: {} not found", script.string());
    } else {
        for (const std::string& f : files) fs::remove(outDir / f);
        std::vector<std::string> argv = {python.string(), script.string()};
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> cArgv;
        for (std::string& a : argv) cArgv.push_back(a.data());
        cArgv.push_back(nullptr);
        const pid_t pid = ::fork();
        if (pid == 0) {
            ::dup2(STDERR_FILENO, STDOUT_FILENO);  // results go to files; chatter to stderr
            ::execv(python.c_str(), cArgv.data());
            ::_exit(127);
        }
        int status = 0;
        if (pid < 0 || ::waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
            run.warning = fmt::format("no plots: {} {} failed (exit status {}); see the messages above", python.string(),
                                      script.string(), WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        else run.ran = true;
    }
    if (!run.warning.empty()) spdlog::warn("{}", run.warning);
    for (const std::string& f : files)
        if (run.ran && fs::is_regular_file(outDir / f)) run.files.push_back(f);
    return run;
}
}  // namespace

PlotRun runPlots(const fs::path& outDir) {
    return runPlotScript(outDir, {outDir.string()}, {std::begin(kPlotFiles), std::end(kPlotFiles)});
}

PlotRun runComparisonPlot(const fs::path& outDir, const std::string& file, const std::string& title,
                          const std::vector<std::pair<std::string, fs::path>>& runs) {
    std::vector<std::string> args = {"--compare", (outDir / file).string(), title};
    for (const auto& [label, dir] : runs) {
        args.push_back(label);
        args.push_back(dir.string());
    }
    return runPlotScript(outDir, args, {file});
}

void writeReport(const fs::path& outDir, const Json& results, bool plots) {
    const std::vector<Table> tables = reportTables(results);
    writeTextAtomically(outDir / "results.csv", resultsCsv(results));
    writeTextAtomically(outDir / "report.md", markdownReport(results, tables));
    PlotRun plotRun;
    if (plots) plotRun = runPlots(outDir);
    else plotRun.warning = "plots turned off (report.plots: false)";
    writeTextAtomically(outDir / "report.html", htmlReport(results, tables, plotRun, outDir));
    spdlog::info("report: {}", (outDir / "report.html").string());
}

std::string readableNumber(double v) {
    if (!std::isfinite(v)) return "—";
    // A float held in a double (a threshold the metrics stored) reads best as the float's shortest form.
    // Only a short one (a threshold as written: 0.1, 0.025), not a measured float (5.151367).
    const float f = static_cast<float>(v);
    if (static_cast<double>(f) == v) {
        const std::string text = fmt::format("{}", f);
        const std::string mantissa = text.substr(0, text.find_first_of("eE"));
        const auto first = mantissa.find_first_of("123456789");
        int digits = 0;
        if (first != std::string::npos)
            for (std::size_t i = first; i < mantissa.size(); ++i) digits += mantissa[i] >= '0' && mantissa[i] <= '9';
        if (digits <= 4 && text.size() <= 8) return text;
    }
    const double a = std::fabs(v);
    if (a >= 1e6 || (a > 0 && a < 1e-3)) return fmt::format("{:.3g}", v);
    return fmt::format("{}", std::stod(fmt::format("{:.3g}", v)));  // 3 digits, no trailing zeros, no exponent
}

std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

}  // namespace aamap
