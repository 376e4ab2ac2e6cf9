#include "eval/compare.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/report.h"
#include "eval/strategies.h"

namespace aamap {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// Dotted keys of every scalar (and list) under the config, but the renders (their records say
// what they are) and the thread count (it changes no image).
void flatten(const Json& j, const std::string& prefix, std::map<std::string, std::string>& out) {
    if (j.is_object()) {
        for (const auto& [k, v] : j.items()) {
            const std::string key = prefix.empty() ? k : prefix + "." + k;
            if (key == "renders" || key == "threads") continue;
            flatten(v, key, out);
        }
        return;
    }
    out[prefix] = j.is_string() ? j.get<std::string>() : j.dump();
}

std::string sceneOf(const ComparedRun& run) { return run.results["config"].value("scene", std::string()); }

// Runs grouped by scene, in the order the scenes first appear.
std::vector<std::vector<const ComparedRun*>> byScene(const std::vector<ComparedRun>& runs) {
    std::vector<std::vector<const ComparedRun*>> groups;
    std::vector<std::string> scenes;
    for (const ComparedRun& r : runs) {
        const auto it = std::find(scenes.begin(), scenes.end(), sceneOf(r));
        if (it == scenes.end()) {
            scenes.push_back(sceneOf(r));
            groups.push_back({&r});
        } else {
            groups[static_cast<std::size_t>(it - scenes.begin())].push_back(&r);
        }
    }
    return groups;
}

// The error a trade is read by: % pixels above the FLIP threshold, else above the MSE threshold.
std::string errorKey(const std::vector<const ComparedRun*>& group) {
    for (const ComparedRun* run : group)
        for (const Json& r : run->results["renders"])
            if (r.contains("metrics") && r["metrics"].contains("pct_error_flip")) return "pct_error_flip";
    return "pct_error_mse";
}

// What a run's errors are measured against: the traced reference's cache key, else the file.
std::string referenceIdentity(const ComparedRun& run) {
    const Json& ref = run.results.contains("reference") ? run.results["reference"] : Json();
    if (!ref.is_object()) return "none";
    if (ref.contains("render") && ref["render"].contains("key")) return ref["render"]["key"].get<std::string>();
    return ref.value("type", std::string()) + ":" + ref.value("path", std::string());
}

// "mitsuba-cbox/scene.xml" rather than the whole path, or a bare "scene.xml".
std::string sceneTitle(const std::string& scene) {
    const fs::path p(scene);
    return p.has_parent_path() ? (p.parent_path().filename() / p.filename()).string() : scene;
}

std::string plotFile(std::size_t sceneIndex) { return fmt::format("plots/compare_error_vs_time_{}.png", sceneIndex); }

}  // namespace

Table paretoTable(const std::vector<const ComparedRun*>& group, std::size_t sceneIndex) {
    const std::string key = errorKey(group);
    struct Point {
        double seconds, error;
        const ComparedRun* run;
        const Json* render;
    };
    std::vector<Point> points;
    for (const ComparedRun* run : group)
        for (const Json& r : run->results["renders"])
            if (r.contains("metrics") && r["metrics"].contains(key) && r["metrics"][key].is_number())
                points.push_back({renderSeconds(r), r["metrics"][key].get<double>(), run, &r});
    std::sort(points.begin(), points.end(),
              [](const Point& a, const Point& b) { return a.seconds != b.seconds ? a.seconds < b.seconds : a.error < b.error; });
    Table t{fmt::format("pareto-{}", sceneIndex), "Speed against accuracy across the runs",
            fmt::format("the renders that no faster render matches in {}, fastest first: the best setting at each error "
                        "level; time = trace + Snapshot",
                        key == "pct_error_flip" ? "% pixels above the FLIP threshold" : "% pixels above the MSE threshold"),
            {"run", "series", "render", "time (s)", key == "pct_error_flip" ? "% error (FLIP)" : "% error (MSE)", "FLIP mean"},
            {}};
    std::set<std::string> references;
    for (const ComparedRun* run : group) references.insert(referenceIdentity(*run));
    if (references.size() > 1)
        t.note += "; the runs are measured against different references, so their errors do not compare: give them "
                  "one (a `path` reference, or `reference.type: file`)";
    double best = std::numeric_limits<double>::infinity();
    for (const Point& p : points) {
        if (!(p.error < best)) continue;
        best = p.error;
        const Json& m = (*p.render)["metrics"];
        t.rows.push_back({p.run->label, p.render->value("series", std::string()), p.render->value("name", std::string()),
                          readableNumber(p.seconds), readableNumber(p.error),
                          m.contains("flip_mean") && m["flip_mean"].is_number() ? readableNumber(m["flip_mean"].get<double>()) : "—"});
    }
    return t;
}

std::vector<fs::path> experimentFolders(const fs::path& dir) {
    const fs::path file = dir / "sweep.json";
    if (!fs::is_regular_file(file)) return {dir};
    std::ifstream in(file);
    if (!in) throw InputError(file, "cannot read");
    std::vector<fs::path> folders;
    try {
        const Json sweep = Json::parse(in);
        for (const Json& v : sweep.at("variants")) folders.push_back(dir / v.at("folder").get<std::string>());
    } catch (const nlohmann::json::exception& e) {
        throw InputError(file, fmt::format("not a sweep's index: {}", e.what()));
    }
    if (folders.empty()) throw InputError(file, "the sweep has no finished variant yet");
    return folders;
}

std::vector<ComparedRun> loadComparedRuns(const std::vector<fs::path>& given) {
    if (given.empty()) throw InputError("compare", "needs at least one experiment folder");
    std::vector<fs::path> dirs;
    for (const fs::path& dir : given)
        for (fs::path& folder : experimentFolders(dir)) dirs.push_back(std::move(folder));
    std::vector<ComparedRun> runs;
    std::vector<std::map<std::string, std::string>> flat;
    for (const fs::path& dir : dirs) {
        const fs::path file = dir / "results.json";
        std::ifstream in(file);
        if (!in) throw InputError(file, "cannot read (is it an experiment's output folder?)");
        ComparedRun run;
        run.dir = dir;
        try {
            run.results = Json::parse(in);
        } catch (const nlohmann::json::exception& e) {
            throw InputError(file, e.what());
        }
        if (!run.results.contains("config") || !run.results.contains("renders"))
            throw InputError(file, "not an aamap results document (no 'config' or 'renders')");
        flat.emplace_back();
        flatten(run.results["config"], "", flat.back());
        runs.push_back(std::move(run));
    }
    std::set<std::string> keys;
    for (const auto& f : flat)
        for (const auto& [k, v] : f) keys.insert(k);
    for (const std::string& k : keys) {
        bool same = true;
        const auto valueIn = [&](const std::map<std::string, std::string>& f) {
            const auto it = f.find(k);
            return it == f.end() ? std::optional<std::string>() : std::optional<std::string>(it->second);
        };
        for (const auto& f : flat)
            if (valueIn(f) != valueIn(flat[0])) same = false;
        if (same) continue;
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const auto it = flat[i].find(k);
            runs[i].differs.emplace_back(k, it == flat[i].end() ? std::string("-") : it->second);
        }
    }
    // Short values: a path's last two parts; a list or a mapping by its order of appearance.
    std::map<std::string, std::vector<std::string>> seen;  // key -> its distinct structured values
    for (ComparedRun& run : runs) {
        for (const auto& [k, v] : run.differs) {
            std::string shortValue = v;
            if (!v.empty() && (v.front() == '[' || v.front() == '{')) {
                auto& values = seen[k];
                auto it = std::find(values.begin(), values.end(), v);
                if (it == values.end()) it = values.insert(values.end(), v);
                shortValue = fmt::format("#{}", it - values.begin() + 1);
            } else if (v.find('/') != std::string::npos) {
                shortValue = sceneTitle(v);
            }
            run.shortDiffers.emplace_back(k, std::move(shortValue));
        }
        const bool others = std::any_of(run.differs.begin(), run.differs.end(), [](const auto& d) { return d.first != "scene"; });
        std::vector<std::string> parts;
        for (const auto& [k, v] : run.shortDiffers)
            if (k != "scene" || !others) parts.push_back(k + "=" + v);
        run.label = parts.empty() ? run.dir.filename().string() : fmt::format("{}", fmt::join(parts, ", "));
    }
    return runs;
}

namespace {

// A run's headline: per series that is not the baseline, at the largest rpp it shares with the
// baseline, its speedup and error; the baseline's error there.
struct Headline {
    std::string series;
    int rpp = 0;
    double speedup = NAN, error = NAN, baselineError = NAN;
    // With metrics.oracle: the speedup as a fraction of the same render's on the oracle map.
    double efficiency = NAN;
};

// The render `name` traced again on the oracle map (results.json "oracle"), or null.
const Json* oracleTwin(const Json& results, const std::string& name) {
    if (!results.contains("oracle") || !results["oracle"].contains("runs")) return nullptr;
    for (const Json& run : results["oracle"]["runs"])
        if (run.value("map_render", std::string()) == name && run.contains("render")) return &run["render"];
    return nullptr;
}

double metricOf(const Json& render, const std::string& key) {
    if (!render.contains("metrics") || !render["metrics"].contains(key) || !render["metrics"][key].is_number()) return NAN;
    return render["metrics"][key].get<double>();
}

bool noisyReference(const ComparedRun& run) {
    const Json& results = run.results;
    return results.contains("reference") && results["reference"].is_object() && results["reference"].contains("noise") &&
           results["reference"]["noise"].value("noisy", false);
}

std::vector<Headline> headlines(const ComparedRun& run, const std::string& errorMetric) {
    const Json& renders = run.results["renders"];
    std::string base;
    for (const Json& r : renders)
        if (r.value("strategy", std::string()) == baselineStrategyName()) {
            base = r.value("series", std::string());
            break;
        }
    std::vector<Headline> out;
    if (base.empty()) return out;
    const auto at = [&](const std::string& series, int rpp) -> const Json* {
        for (const Json& r : renders)
            if (r.value("series", std::string()) == series && r.value("max_rays_per_pixel", 0) == rpp) return &r;
        return nullptr;
    };
    const bool noisy = noisyReference(run);
    for (const Json& r : renders) {
        const std::string series = r.value("series", std::string());
        if (series == base || std::any_of(out.begin(), out.end(), [&](const Headline& h) { return h.series == series; }))
            continue;
        Headline h{series};
        for (const Json& other : renders)
            if (other.value("series", std::string()) == series && at(base, other.value("max_rays_per_pixel", 0)))
                h.rpp = std::max(h.rpp, other.value("max_rays_per_pixel", 0));
        if (h.rpp == 0) continue;
        const Json& s = *at(series, h.rpp);
        const Json& b = *at(base, h.rpp);
        if (renderSeconds(s) > 0) h.speedup = renderSeconds(b) / renderSeconds(s);
        if (const Json* o = oracleTwin(run.results, s.value("name", std::string())); o && renderSeconds(*o) > 0)
            h.efficiency = h.speedup / (renderSeconds(b) / renderSeconds(*o));
        if (!noisy) {
            h.error = metricOf(s, errorMetric);
            h.baselineError = metricOf(b, errorMetric);
        }
        out.push_back(h);
    }
    return out;
}

}  // namespace

Table summaryTable(const std::vector<ComparedRun>& runs) {
    std::vector<const ComparedRun*> all;
    for (const ComparedRun& r : runs) all.push_back(&r);
    const std::string metric = errorKey(all);
    const std::string errorName = metric == "pct_error_flip" ? "% error (FLIP)" : "% error (MSE)";
    Table t{"summary", "Summary: one row per run",
            fmt::format("speedup: the baseline's time over the series' at the largest rpp both have (time = trace + "
                        "Snapshot); {}: pixels in error against the run's reference there; recall, precision, "
                        "flagged: the aamap against true aliasing; oracle efficiency: the speedup as a fraction of "
                        "the same render's on the oracle map (metrics.oracle); time: all the run's renders. Bold: the "
                        "best of the column among the runs of one scene",
                        errorName),
            {}, {}};
    for (const auto& [k, v] : runs.front().shortDiffers) t.header.push_back(k);
    // The columns: every series any run has, in order of appearance.
    std::vector<std::pair<std::string, int>> series;  // name, rpp (0 when it differs between runs)
    std::string baseline;
    for (const ComparedRun& run : runs)
        for (const Headline& h : headlines(run, metric)) {
            const auto it = std::find_if(series.begin(), series.end(), [&](const auto& s) { return s.first == h.series; });
            if (it == series.end()) series.emplace_back(h.series, h.rpp);
            else if (it->second != h.rpp) it->second = 0;
        }
    for (const ComparedRun& run : runs)
        for (const Json& r : run.results["renders"])
            if (baseline.empty() && r.value("strategy", std::string()) == baselineStrategyName())
                baseline = r.value("series", std::string());
    // A series measured against the oracle map in some run also gets its efficiency there.
    std::set<std::string> withOracle;
    for (const ComparedRun& run : runs)
        for (const Headline& h : headlines(run, metric))
            if (std::isfinite(h.efficiency)) withOracle.insert(h.series);
    for (const auto& [name, rpp] : series) {
        const std::string at = rpp > 0 ? fmt::format(" @{}", rpp) : "";
        t.header.push_back(fmt::format("{} speedup{}", name, at));
        t.header.push_back(fmt::format("{} {}", name, errorName));
        if (withOracle.count(name)) t.header.push_back(fmt::format("{} oracle efficiency", name));
    }
    if (!series.empty()) t.header.push_back(fmt::format("{} {}", baseline.empty() ? "baseline" : baseline, errorName));
    const std::vector<std::string> mapKeys = {"recall", "precision", "flagged_fraction"};
    const bool map = std::any_of(runs.begin(), runs.end(), [](const ComparedRun& r) { return r.results.contains("map_quality"); });
    if (map)
        for (const char* h : {"recall", "precision", "flagged %"}) t.header.push_back(h);
    t.header.push_back("time (s)");

    std::vector<std::vector<double>> values(runs.size());  // the figures, for the best of each column
    std::vector<bool> higherIsBetter;
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const ComparedRun& run = runs[i];
        std::vector<std::string> row;
        for (const auto& [k, v] : run.shortDiffers) row.push_back(v);
        const std::vector<Headline> hs = headlines(run, metric);
        double baselineError = NAN;
        std::vector<double>& vals = values[i];
        higherIsBetter.clear();
        for (const auto& column : series) {  // not a structured binding: clang's lambdas cannot capture one
            const std::string& name = column.first;
            const auto h = std::find_if(hs.begin(), hs.end(), [&name](const Headline& x) { return x.series == name; });
            vals.push_back(h != hs.end() ? h->speedup : NAN);
            vals.push_back(h != hs.end() ? h->error : NAN);
            higherIsBetter.insert(higherIsBetter.end(), {true, false});
            if (withOracle.count(name)) {
                vals.push_back(h != hs.end() ? h->efficiency : NAN);
                higherIsBetter.push_back(true);
            }
            if (h != hs.end() && std::isfinite(h->baselineError)) baselineError = h->baselineError;
        }
        if (!series.empty()) {
            vals.push_back(baselineError);
            higherIsBetter.push_back(false);
        }
        if (map) {
            const Json& m = run.results.contains("map_quality") ? run.results["map_quality"] : Json::object();
            for (const std::string& k : mapKeys) {
                const double v = m.contains(k) && m[k].is_number() ? m[k].get<double>() : NAN;
                vals.push_back(k == "flagged_fraction" ? 100.0 * v : v);
                higherIsBetter.push_back(k != "flagged_fraction");
            }
        }
        double seconds = 0;
        for (const Json& r : run.results["renders"]) seconds += renderSeconds(r);
        vals.push_back(seconds);
        higherIsBetter.push_back(false);
        t.rows.push_back(std::move(row));
    }
    const std::size_t keyColumns = runs.front().shortDiffers.size();
    for (std::size_t c = 0; c < higherIsBetter.size(); ++c) {
        // The best of the column among the runs of one scene: figures of other scenes do not compare.
        std::map<std::string, double> best;
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const double v = c < values[i].size() ? values[i][c] : NAN;
            if (!std::isfinite(v)) continue;
            const auto [it, added] = best.emplace(sceneOf(runs[i]), v);
            if (!added && (higherIsBetter[c] ? v > it->second : v < it->second)) it->second = v;
        }
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const double v = c < values[i].size() ? values[i][c] : NAN;
            std::string text = readableNumber(v);
            if (std::isfinite(v) && t.header[keyColumns + c].find("speedup") != std::string::npos) text += "x";
            const auto sameScene = std::count_if(runs.begin(), runs.end(), [&](const ComparedRun& r) { return sceneOf(r) == sceneOf(runs[i]); });
            const bool isBest = sameScene > 1 && std::isfinite(v) && v == best[sceneOf(runs[i])];
            t.rows[i].push_back(isBest ? "**" + text + "**" : text);
        }
    }
    return t;
}

std::vector<std::string> winners(const std::vector<const ComparedRun*>& sceneRuns) {
    std::vector<std::string> lines;
    if (sceneRuns.size() < 2) return lines;
    const std::string metric = errorKey(sceneRuns);
    std::vector<std::string> names;
    for (const ComparedRun* run : sceneRuns)
        for (const Headline& h : headlines(*run, metric))
            if (std::find(names.begin(), names.end(), h.series) == names.end()) names.push_back(h.series);
    for (const std::string& name : names) {
        double lowest = NAN;
        for (const ComparedRun* run : sceneRuns)
            for (const Headline& h : headlines(*run, metric))
                if (h.series == name && std::isfinite(h.error) && !(h.error >= lowest)) lowest = h.error;
        if (!std::isfinite(lowest)) continue;
        const ComparedRun* best = nullptr;
        Headline bestH;
        for (const ComparedRun* run : sceneRuns)
            for (const Headline& h : headlines(*run, metric))
                if (h.series == name && std::isfinite(h.speedup) && h.error <= lowest + kEqualErrorPoints &&
                    (best == nullptr || h.speedup > bestH.speedup)) {
                    best = run;
                    bestH = h;
                }
        if (best == nullptr) continue;
        lines.push_back(fmt::format("{}: **{}** is the fastest within {} points of the lowest error: {}x at {}% "
                                    "error pixels ({} rpp)",
                                    name, best->label, readableNumber(kEqualErrorPoints), readableNumber(bestH.speedup),
                                    readableNumber(bestH.error), bestH.rpp));
    }
    return lines;
}

std::string compareCsv(const std::vector<ComparedRun>& runs) {
    std::vector<std::string> header = {"run"};
    for (const auto& [k, v] : runs.front().differs) header.push_back(k);
    for (const std::string& c : resultsCsvColumns()) header.push_back(c);
    std::string out = fmt::format("{}\n", fmt::join(header, ","));
    for (const ComparedRun& run : runs) {
        std::string prefix = csvField(run.dir.string());
        for (const auto& [k, v] : run.differs) prefix += fmt::format(",{}", csvField(v));
        const std::string csv = resultsCsv(run.results);
        std::size_t start = csv.find('\n') + 1;  // after the run's own header
        for (std::size_t end; (end = csv.find('\n', start)) != std::string::npos; start = end + 1)
            out += fmt::format("{},{}\n", prefix, csv.substr(start, end - start));
    }
    return out;
}

std::string compareMarkdown(const std::vector<ComparedRun>& runs, const std::vector<std::string>& scenePlots) {
    std::string md = fmt::format("# aamap comparison of {} run(s)\n\n", runs.size());
    if (runs.front().differs.empty()) md += "The runs' settings are the same.\n\n";
    md += markdownTable(summaryTable(runs));
    const auto groups = byScene(runs);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto& group = groups[g];
        md += fmt::format("## Scene {}\n\n", sceneOf(*group.front()));
        for (const std::string& line : winners(group)) md += "* " + line + "\n";
        if (group.size() > 1) {
            md += "\n";
            if (g < scenePlots.size() && !scenePlots[g].empty()) md += fmt::format("![error against time]({})\n\n", scenePlots[g]);
            md += markdownTable(paretoTable(group, g), "###");
        }
        for (const ComparedRun* run : group) {
            // Each run's own tables, folded: the summary above answers the comparison.
            md += fmt::format("<details><summary><b>{}</b> ({})</summary>\n\n", run->label, run->dir.string());
            md += fmt::format("### {}\n\n", run->label);
            for (const Json& w : run->results["warnings"]) md += fmt::format("> **warning:** {}\n\n", w.get<std::string>());
            std::string body = markdownReport(run->results, reportTables(run->results));
            body = body.substr(body.find("\n## ") + 1);  // without the run's own title
            std::string demoted;  // its tables one heading level down
            std::size_t start = 0;
            for (std::size_t end; (end = body.find('\n', start)) != std::string::npos; start = end + 1) {
                const std::string line = body.substr(start, end - start);
                demoted += (line.rfind("## ", 0) == 0 ? "##" + line : line) + "\n";
            }
            md += demoted + "\n</details>\n\n";
        }
    }
    return md;
}

std::string compareHtml(const std::vector<ComparedRun>& runs, const fs::path& outDir,
                        const std::vector<std::string>& scenePlots) {
    std::string h = fmt::format(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>aamap comparison</title><style>"
        "body{{font-family:sans-serif;margin:2em;max-width:1400px}}table{{border-collapse:collapse;margin:.5em 0}}"
        "td,th{{border:1px solid #bbb;padding:.2em .6em;text-align:right}}th{{background:#eee}}"
        ".note{{color:#555;font-size:90%}}.warn{{background:#fff3cd;border:1px solid #e0b400;padding:.6em}}"
        "</style></head><body>\n<h1>aamap comparison of {} run(s)</h1>\n",
        runs.size());
    Table summary = summaryTable(runs);
    summary.header.push_back("report");
    for (std::size_t i = 0; i < runs.size(); ++i)
        summary.rows[i].push_back(fs::relative(runs[i].dir / "report.html", outDir).string());
    h += htmlTable(summary);
    const auto groups = byScene(runs);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto& group = groups[g];
        h += fmt::format("<h2>Scene {}</h2>\n", htmlEscape(sceneOf(*group.front())));
        const std::vector<std::string> won = winners(group);
        if (!won.empty()) {
            h += "<ul>\n";
            for (std::string line : won) {
                line = htmlEscape(line);
                for (int open = 1; line.find("**") != std::string::npos; open ^= 1)  // **x** -> <b>x</b>
                    line.replace(line.find("**"), 2, open ? "<b>" : "</b>");
                h += "<li>" + line + "</li>\n";
            }
            h += "</ul>\n";
        }
        if (group.size() > 1) {
            if (g < scenePlots.size() && !scenePlots[g].empty())
                h += fmt::format("<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"error against time\" style=\"max-width:100%\"></a>"
                                 "<figcaption>Error against time, every run's series (labels: rpp)</figcaption></figure>\n",
                                 htmlEscape(scenePlots[g]));
            h += htmlTable(paretoTable(group, g));
        }
        for (const ComparedRun* run : group) {
            h += fmt::format("<details><summary><b>{}</b> (<a href=\"{}\">report</a>)</summary>\n", htmlEscape(run->label),
                             htmlEscape(fs::relative(run->dir / "report.html", outDir).string()));
            for (const Json& w : run->results["warnings"])
                h += "<p class=\"warn\">" + htmlEscape(w.get<std::string>()) + "</p>\n";
            for (Table t : reportTables(run->results)) {
                t.id = fmt::format("{}-{}", t.id, static_cast<std::size_t>(run - runs.data()));
                h += htmlTable(t);
            }
            h += "</details>\n";
        }
    }
    return h + "</body></html>\n";
}

void writeComparison(const std::vector<fs::path>& dirs, const fs::path& outDir, const ComparisonFiles& files,
                     bool plots) {
    const std::vector<ComparedRun> runs = loadComparedRuns(dirs);
    std::error_code ec;
    fs::create_directories(outDir, ec);
    if (ec) throw EnvironmentError(fmt::format("{}: cannot create output folder: {}", outDir.string(), ec.message()));
    // One error-against-time plot per scene with several runs: the runs' trades on one set of axes.
    std::vector<std::string> scenePlots;
    const auto groups = byScene(runs);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        scenePlots.emplace_back();
        if (!plots || groups[g].size() < 2) continue;
        std::vector<std::pair<std::string, fs::path>> labelled;
        for (const ComparedRun* run : groups[g]) labelled.emplace_back(run->label, run->dir);
        const PlotRun plot = runComparisonPlot(outDir, plotFile(g), fmt::format("Speed against accuracy ({}; labels: rpp)",
                                                                                sceneTitle(sceneOf(*groups[g].front()))),
                                               labelled);
        if (!plot.files.empty()) scenePlots.back() = plot.files.front();
    }
    writeTextAtomically(outDir / files.csv, compareCsv(runs));
    writeTextAtomically(outDir / files.markdown, compareMarkdown(runs, scenePlots));
    writeTextAtomically(outDir / files.html, compareHtml(runs, outDir, scenePlots));
    spdlog::info("comparison of {} run(s): {}", runs.size(), (outDir / files.html).string());
}

}  // namespace aamap
