// report.html: self-contained apart from the images beside it (relative links), no scripts.
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "eval/metrics/pixel_causes.h"
#include "eval/report.h"

namespace aamap {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

// A linked thumbnail, or nothing when the file is absent.
std::string figure(const fs::path& outDir, const std::string& file, const std::string& caption) {
    if (!fs::is_regular_file(outDir / file)) return "";
    return fmt::format(R"(<figure><a href="{0}"><img src="{0}" alt="{1}"></a><figcaption>{1}</figcaption></figure>)",
                       escape(file), escape(caption));
}

std::string tableHtml(const Table& t) {
    std::string h = fmt::format("<h2 id=\"{}\">{}</h2>\n<table>\n<tr>", t.id, escape(t.title));
    for (const std::string& c : t.header) h += "<th>" + escape(c) + "</th>";
    h += "</tr>\n";
    for (const auto& row : t.rows) {
        h += "<tr>";
        for (const std::string& c : row) h += "<td>" + escape(c) + "</td>";
        h += "</tr>\n";
    }
    return h + fmt::format("</table>\n<p class=\"note\">{}</p>\n", escape(t.note));
}

const char* const kStyle = R"(body{font-family:sans-serif;margin:2em;max-width:1400px}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #bbb;padding:.2em .6em;text-align:right}
th{background:#eee}.note{color:#555;font-size:90%}.warn{background:#fff3cd;border:1px solid #e0b400;padding:.6em}
figure{display:inline-block;margin:.3em;vertical-align:top}figure img{width:240px;image-rendering:pixelated}
figcaption{font-size:85%;text-align:center}.plots img{width:560px}pre{background:#f6f6f6;padding:.6em;overflow:auto})";

}  // namespace

std::string htmlReport(const Json& results, const std::vector<Table>& tables, const PlotRun& plots,
                       const fs::path& outDir) {
    std::string h = fmt::format("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>aamap report {}</title>"
                                "<style>{}</style></head><body>\n<h1>aamap experiment report</h1>\n",
                                escape(results.value("config_hash", std::string())), kStyle);
    const Json& renders = results["renders"];
    std::string machine;
    if (!renders.empty())
        machine = fmt::format("{} ({}, {} threads)", renders[0]["machine"]["cpu_model"].get<std::string>(),
                              renders[0]["machine"]["hostname"].get<std::string>(), renders[0]["machine"]["threads"].get<int>());
    h += fmt::format("<p>scene <code>{}</code>, view <code>{}</code>, config hash <code>{}</code>, git revision "
                     "<code>{}</code>, machine {}. Data: <a href=\"results.json\">results.json</a>, "
                     "<a href=\"results.csv\">results.csv</a>, <a href=\"report.md\">report.md</a>.</p>\n",
                     renders.empty() ? "" : escape(renders[0]["scene"].get<std::string>()),
                     renders.empty() ? "" : escape(renders[0]["view"].get<std::string>()),
                     escape(results.value("config_hash", std::string())),
                     escape(results.value("git_revision", std::string())), escape(machine));
    for (const Json& w : results["warnings"]) h += "<p class=\"warn\">" + escape(w.get<std::string>()) + "</p>\n";
    if (!plots.warning.empty()) h += "<p class=\"warn\">" + escape(plots.warning) + "</p>\n";

    for (const Table& t : tables) h += tableHtml(t);

    h += "<h2 id=\"plots\">Plots</h2>\n<div class=\"plots\">";
    for (const std::string& f : plots.files) h += figure(outDir, f, fs::path(f).stem().string());
    if (plots.files.empty()) h += "<p>(none)</p>";
    h += "</div>\n<p class=\"note\">time_vs_rpp: Figures 6-7, one line per series with its least-squares fit and "
         "R&sup2;. error_vs_time: the speed-accuracy trade, the Pareto front marked.</p>\n";

    h += "<h2 id=\"maps\">Snapshot, aamap and rays per pixel</h2>\n<div>";
    h += figure(outDir, "snapshot.png", "snapshot") + figure(outDir, "laplacian.png", "|Laplacian|") +
         figure(outDir, "aamap.png", "aamap");
    for (const Json& r : renders)
        if (r["strategy"] != "uniform")
            h += figure(outDir, r["name"].get<std::string>() + ".rpp.png", r["name"].get<std::string>() + " rays/pixel");
    if (results.contains("map_quality"))
        h += figure(outDir, "aliasing.png", "aliasing: white hit, red missed, blue false alarm");
    const bool causes = results.contains("map_quality") && results["map_quality"].contains("causes");
    if (causes) h += figure(outDir, "causes.png", "causes of the map's misses (bright) and waste (dark)");
    h += "</div>\n";
    if (causes) {
        h += "<p class=\"note\">Cause colours (NAME.causes.png, causes.png; missed pixels bright, wasted ones dark): ";
        for (int i = 0; i < metrics::kPixelCauses; ++i) {
            const auto cause = static_cast<metrics::PixelCause>(i);
            const glm::u8vec3 c = metrics::colour(cause);
            h += fmt::format("<span style=\"background:#000;color:rgb({},{},{});padding:0 4px\">&#9632; {}</span> ", c.r, c.g,
                             c.b, metrics::toString(cause));
        }
        h += "</p>\n";
    }

    h += "<h2 id=\"images\">Renders against the reference (Figure 8: FLIP error in red)</h2>\n";
    if (results.contains("reference") && results["reference"].contains("render"))
        h += "<div>" + figure(outDir, "reference.png", "reference") + "</div>\n";
    for (const Json& r : renders) {
        const std::string n = r["name"].get<std::string>();
        h += "<div>" + figure(outDir, n + ".png", n) + figure(outDir, n + ".overlay.png", n + ": FLIP in red") +
             figure(outDir, n + ".flip.png", n + ": FLIP map") + figure(outDir, n + ".rpp.png", n + ": rays/pixel") +
             figure(outDir, n + ".causes.png", n + ": causes") + "</div>\n";
    }
    h += "<h2 id=\"config\">Config</h2>\n<pre>" + escape(results["config"].dump(2)) + "</pre>\n</body></html>\n";
    return h;
}

}  // namespace aamap

namespace aamap {

// For other pages built from the same tables (aamap compare).
std::string htmlEscape(const std::string& s) { return escape(s); }
std::string htmlTable(const Table& t) { return tableHtml(t); }

}  // namespace aamap
