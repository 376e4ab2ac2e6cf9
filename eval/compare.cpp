#include "eval/compare.h"

#include <algorithm>
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
    for (ComparedRun& run : runs) {
        std::vector<std::string> parts;
        for (const auto& [k, v] : run.differs) parts.push_back(k + "=" + v);
        run.label = parts.empty() ? run.dir.filename().string() : fmt::format("{}", fmt::join(parts, ", "));
    }
    return runs;
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
    const auto groups = byScene(runs);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto& group = groups[g];
        md += fmt::format("## Scene {}\n\n", sceneOf(*group.front()));
        if (group.size() > 1) {
            md += markdownTable(paretoTable(group, g), "###");
            if (g < scenePlots.size() && !scenePlots[g].empty()) md += fmt::format("![error against time]({})\n\n", scenePlots[g]);
        }
        for (const ComparedRun* run : group) {
            md += fmt::format("### {} ({})\n\n", run->label, run->dir.string());
            for (const Json& w : run->results["warnings"]) md += fmt::format("> **warning:** {}\n\n", w.get<std::string>());
            std::string body = markdownReport(run->results, reportTables(run->results));
            body = body.substr(body.find("\n## ") + 1);  // without the run's own title
            std::string demoted;  // its tables one heading level down
            std::size_t start = 0;
            for (std::size_t end; (end = body.find('\n', start)) != std::string::npos; start = end + 1) {
                const std::string line = body.substr(start, end - start);
                demoted += (line.rfind("## ", 0) == 0 ? "##" + line : line) + "\n";
            }
            md += demoted;
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
    Table overview{"runs", "Runs", "what tells the runs apart; each links to its own report", {"run"}, {}};
    for (const auto& [k, v] : runs.front().differs) overview.header.push_back(k);
    overview.header.push_back("report");
    for (const ComparedRun& run : runs) {
        std::vector<std::string> row = {run.dir.string()};
        for (const auto& [k, v] : run.differs) row.push_back(v);
        row.push_back(fs::relative(run.dir / "report.html", outDir).string());
        overview.rows.push_back(std::move(row));
    }
    h += htmlTable(overview);
    const auto groups = byScene(runs);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto& group = groups[g];
        h += fmt::format("<h2>Scene {}</h2>\n", htmlEscape(sceneOf(*group.front())));
        if (group.size() > 1) {
            h += htmlTable(paretoTable(group, g));
            if (g < scenePlots.size() && !scenePlots[g].empty())
                h += fmt::format("<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"error against time\" style=\"max-width:100%\"></a>"
                                 "<figcaption>Error against time, every run's series (labels: rpp)</figcaption></figure>\n",
                                 htmlEscape(scenePlots[g]));
        }
        for (const ComparedRun* run : group) {
            h += fmt::format("<h3>{} (<a href=\"{}\">report</a>)</h3>\n", htmlEscape(run->label),
                             htmlEscape(fs::relative(run->dir / "report.html", outDir).string()));
            for (const Json& w : run->results["warnings"])
                h += "<p class=\"warn\">" + htmlEscape(w.get<std::string>()) + "</p>\n";
            for (Table t : reportTables(run->results)) {
                t.id = fmt::format("{}-{}", t.id, static_cast<std::size_t>(run - runs.data()));
                h += htmlTable(t);
            }
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
