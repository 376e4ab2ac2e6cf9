// report.html: one page beside its images (relative links), readable at 1400 px: what went wrong
// first, then the summary tables, one comparison viewer for every render, the plots, the
// Snapshot's images, and the full per-render table and config folded away. Style and script are
// embedded (eval/report_page/), so the page opens from disk with no network.
#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "eval/metrics/pixel_causes.h"
#include "eval/report.h"
#include "eval/report_page/assets.h"
#include "eval/report_viewer.h"

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

// A linked image with its caption (HTML), or nothing when the file is absent.
std::string figure(const fs::path& outDir, const std::string& file, const std::string& alt, const std::string& captionHtml) {
    if (!fs::is_regular_file(outDir / file)) return "";
    return fmt::format("<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a><figcaption>{2}</figcaption></figure>",
                       escape(file), escape(alt), captionHtml);
}

std::string tableHtml(const Table& t, const char* heading = "h2") {
    std::string h = fmt::format("<{0} id=\"{1}\">{2}</{0}>\n<table>\n<tr>", heading, t.id, escape(t.title));
    for (const std::string& c : t.header) h += "<th>" + escape(c) + "</th>";
    h += "</tr>\n";
    for (const auto& row : t.rows) {
        h += "<tr>";
        for (const std::string& c : row) {  // a cell in Markdown's bold (**x**, the best of a column) is bold here too
            const bool strong = c.size() > 4 && c.starts_with("**") && c.ends_with("**");
            h += strong ? "<td><b>" + escape(c.substr(2, c.size() - 4)) + "</b></td>" : "<td>" + escape(c) + "</td>";
        }
        h += "</tr>\n";
    }
    return h + fmt::format("</table>\n<p class=\"note\">{}</p>\n", escape(t.note));
}


// What the Snapshot cost, as a card beside the summary.
std::string snapshotCard(const Json& results) {
    const std::optional<Table> t = snapshotCostTable(results);
    return t ? "<div class=\"card\">" + tableHtml(*t) + "</div>\n" : "";
}

std::string problemsSection(const Json& results, const PlotRun& plots) {
    std::vector<std::string> items;
    for (const Json& w : results["warnings"]) items.push_back(escape(w.get<std::string>()));
    if (!plots.warning.empty()) items.push_back(escape(plots.warning));
    if (items.empty()) return "<p class=\"ok\">No warnings: every render, metric and plot was made.</p>\n";
    std::string h = fmt::format("<section id=\"problems\" class=\"problems\"><h2>What went wrong ({})</h2><ul>", items.size());
    for (const std::string& i : items) h += "<li>" + i + "</li>";
    return h + "</ul></section>\n";
}

std::string plotsSection(const PlotRun& plots, const fs::path& outDir) {
    std::string h = "<section id=\"plots\"><h2>Plots</h2>\n";
    if (plots.files.empty()) return h + "<p class=\"note\">No plots (see the top of the page for why).</p></section>\n";
    h += "<div class=\"row\">";
    for (const std::string& f : plots.files) {
        const std::string stem = fs::path(f).stem().string();
        std::string caption = stem;
        if (stem == "time_vs_rpp")
            caption = "Render time (trace + Snapshot) against the mean primary rays per pixel actually traced, one colour "
                      "per series with its least-squares line and R&sup2; (the paper's Figures 6-7). Lower is cheaper at "
                      "the same sampling.";
        else if (stem == "error_vs_time")
            caption = "% pixels above the FLIP threshold against render time (log axis when times span a decade or "
                      "more); each point is labelled with its rpp. Down and left is better; the dashed line is the Pareto "
                      "front: no render is both faster and more accurate than a point on it.";
        h += figure(outDir, f, stem, caption);
    }
    return h + "</div></section>\n";
}

std::string mapsSection(const Json& results, const fs::path& outDir) {
    const Json config = results.value("config", Json::object());
    const Json snap = config.value("snapshot", Json::object());
    std::string h = "<section id=\"maps\"><h2>Snapshot, aamap and true aliasing</h2>\n<div class=\"row maps\">";
    h += figure(outDir, "snapshot.png", "snapshot",
                fmt::format("The Snapshot: the Vulkan raster the aamap is built from ({} &times; the render's resolution, "
                            "{} point lights per area light).",
                            readableNumber(numberOr(snap, "scale")), readableNumber(numberOr(snap, "area_light_samples"))));
    h += figure(outDir, "laplacian.png", "|Laplacian|",
                "|Laplacian| of the Snapshot (5&times;5): the edges it finds; brighter is a stronger edge.");
    h += figure(outDir, "aamap.png", "aamap",
                "<div class=\"cbar\"><div class=\"bar\" style=\"background:linear-gradient(to right,#000,#fff)\"></div>"
                "<span class=\"tick\" style=\"left:0\">0</span><span class=\"tick\" style=\"left:50%\">0.5</span>"
                "<span class=\"tick\" style=\"left:100%\">1</span><span class=\"unit\">aamap value</span></div>"
                "The aamap: black = smooth, the tracer spends the minimum; brighter = predicted aliasing, more rays. "
                "Also a layer of the viewer.");
    if (results.contains("map_quality")) {
        const Json& q = results["map_quality"];
        const auto swatch = [](const char* colour) { return fmt::format("<span class=\"swatch\" style=\"background:{}\"></span>", colour); };
        h += figure(
            outDir, "aliasing.png", "aliasing",
            fmt::format("Where the aamap is right. True aliasing: FLIP(1-ray, reference) &gt; {}; flagged: aamap &gt; 0."
                        "<br>{}flagged and aliased (a hit)<br>{}aliased, not flagged (a miss)<br>{}a miss whose own "
                        "display value equals the reference's: FLIP rose there only beside a neighbour's error, and no "
                        "sampling of this pixel can change it<br>{}flagged, not aliased (rays spent for nothing)<br>"
                        "dimmed 1-ray render: neither.",
                        readableNumber(numberOr(q, "threshold")), swatch("#fff"), swatch("#f00"), swatch("#ffa000"),
                        swatch("#285aff")));
        if (q.contains("causes")) {
            std::string legend;
            for (int i = 0; i < metrics::kPixelCauses; ++i) {
                const auto cause = static_cast<metrics::PixelCause>(i);
                const glm::u8vec3 c = metrics::colour(cause);
                legend += fmt::format("<br><span class=\"swatch\" style=\"background:rgb({},{},{})\"></span>{}", c.r, c.g,
                                      c.b, metrics::toString(cause));
            }
            h += figure(outDir, "causes.png", "causes",
                        "Why the aamap missed (bright: truly aliased, not flagged) or wasted (dark: flagged, not aliased), "
                        "by what the tracer sees in the pixel (the Causes tables; per render in the viewer's causes "
                        "layer). Black: neither." + legend);
        }
    }
    return h + "</div></section>\n";
}

}  // namespace

std::string htmlReport(const Json& results, const std::vector<Table>& tables, const PlotRun& plots,
                       const fs::path& outDir) {
    std::string h = fmt::format("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                                "<meta name=\"viewport\" content=\"width=device-width\"><title>aamap report {}</title>"
                                "<style>{}</style></head><body>\n<h1>aamap experiment report</h1>\n",
                                escape(results.value("config_hash", std::string())), report_page::kStyle);
    const Json& renders = results["renders"];
    std::string machine, scene, view, size;
    if (!renders.empty()) {
        const Json& r = renders[0];
        machine = fmt::format("{} ({}, {} threads)", r["machine"]["cpu_model"].get<std::string>(),
                              r["machine"]["hostname"].get<std::string>(), r["machine"]["threads"].get<int>());
        scene = r["scene"].get<std::string>();
        view = r["view"].get<std::string>();
        size = fmt::format("{} &times; {} px", r["width"].get<int>(), r["height"].get<int>());
    }
    h += fmt::format("<p class=\"meta\">scene <code>{}</code>, view <code>{}</code>, {}, {} renders; machine {}; git "
                     "<code>{}</code>, config hash <code>{}</code>. Data: <a href=\"results.json\">results.json</a>, "
                     "<a href=\"results.csv\">results.csv</a>, <a href=\"report.md\">report.md</a>.</p>\n",
                     escape(scene), escape(view), size, renders.size(), escape(machine),
                     escape(results.value("git_revision", std::string())), escape(results.value("config_hash", std::string())));
    h += problemsSection(results, plots);

    h += "<section id=\"summary\" class=\"cards\">\n";
    const Table* all = nullptr;
    std::vector<const Table*> causes;  // one row per render: folded away below the maps
    for (const Table& t : tables) {
        if (t.id == "renders") all = &t;  // long: folded away at the bottom
        else if (t.id.starts_with("causes_")) causes.push_back(&t);
        else h += "<div class=\"card\">" + tableHtml(t) + "</div>\n";
        if (t.id == "speedup") h += snapshotCard(results);  // narrow: beside the time tables
    }
    h += "</section>\n";

    h += viewerSection(results, outDir);
    h += plotsSection(plots, outDir);
    h += mapsSection(results, outDir);
    if (!causes.empty()) {
        h += "<details id=\"causes\"><summary>Causes: why error pixels remain and where extra rays bought nothing</summary>\n";
        for (const Table* t : causes) h += tableHtml(*t, "h3");
        h += "</details>\n";
    }

    if (all) h += "<details id=\"all-renders\"><summary>" + escape(all->title) + " (" + std::to_string(all->rows.size()) +
                  ")</summary>\n" + tableHtml(*all, "h3") + "</details>\n";
    h += "<details id=\"config\"><summary>Config</summary>\n<pre>" + escape(results["config"].dump(2)) + "</pre></details>\n";
    h += fmt::format("<script>{}</script>\n</body></html>\n", report_page::kScript);
    return h;
}

// For other pages built from the same tables (aamap compare).
std::string htmlEscape(const std::string& s) { return escape(s); }
std::string htmlTable(const Table& t) { return tableHtml(t); }

}  // namespace aamap
