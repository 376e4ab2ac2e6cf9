#include "eval/report_viewer.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "core/image_io.h"
#include "eval/metrics/magma.h"
#include "eval/metrics/pixel_causes.h"
#include "eval/config.h"
#include "eval/report.h"
#include "tracer/shading_params.h"
#include "tracer/strategy.h"

namespace aamap {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

std::string cssColour(float r, float g, float b) {
    const auto byte = [](float v) { return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return fmt::format("#{:02x}{:02x}{:02x}", byte(r), byte(g), byte(b));
}

// 17 evenly spaced stops: a CSS gradient through them matches the PNGs' maps to the eye.
Json magmaStops() {
    Json stops = Json::array();
    for (int i = 0; i <= 16; ++i) {
        const glm::vec3 c = metrics::magmaSrgb(static_cast<float>(i) / 16.0f);
        stops.push_back(cssColour(c.r, c.g, c.b));
    }
    return stops;
}

Json viridisStops() {
    Json stops = Json::array();
    for (int i = 0; i <= 16; ++i) {
        const glm::u8vec3 c = colourRamp(static_cast<float>(i) / 16.0f);
        stops.push_back(fmt::format("#{:02x}{:02x}{:02x}", c.r, c.g, c.b));
    }
    return stops;
}

Json numberOrNull(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

std::string referenceText(const Json& results) {
    const Json ref = results.value("reference", Json::object());
    const std::string type = ref.value("type", std::string(toString(ReferenceType::None)));
    if (type == toString(ReferenceType::Uniform) && ref.contains("rpp"))
        return fmt::format("uniform sampling, {} primary rays in every pixel ({} shading)", ref["rpp"].get<int>(),
                           ref.value("mode", std::string(toString(ShadingSettings().mode))));
    if (ref.contains("path")) return fmt::format("the image {}", fs::path(ref["path"].get<std::string>()).filename().string());
    return type;
}

}  // namespace

Json viewerData(const Json& results, const fs::path& outDir) {
    const Json& renders = results["renders"];
    const auto present = [&](const std::string& f) { return fs::is_regular_file(outDir / f) ? Json(f) : Json(nullptr); };
    const Json config = results.value("config", Json::object());
    Json d;
    d["width"] = renders.empty() ? 0 : renders[0]["width"].get<int>();
    d["height"] = renders.empty() ? 0 : renders[0]["height"].get<int>();
    d["exposure"] = config.contains("image") ? config["image"].value("exposure", 1.0) : 1.0;
    d["flip_threshold"] = static_cast<float>(
        config.contains("metrics") ? config["metrics"].value("flip_threshold", 0.1) : 0.1);
    d["reference"] = present("reference.png");
    d["reference_text"] = referenceText(results);
    d["aamap"] = present("aamap.png");
    d["colour_maps"] = {{"magma", magmaStops()}, {"viridis", viridisStops()}};
    Json legend = Json::array();  // the causes layer's colours (eval/metrics/pixel_causes.h)
    for (int i = 0; i < metrics::kPixelCauses; ++i) {
        const glm::u8vec3 c = metrics::colour(static_cast<metrics::PixelCause>(i));
        legend.push_back({metrics::toString(static_cast<metrics::PixelCause>(i)), fmt::format("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)});
    }
    d["causes_legend"] = legend;

    std::vector<int> rpps;
    std::vector<std::string> series;
    Json list = Json::array();
    std::size_t worstSelective = 0, worstAny = 0;
    double worstSelectivePct = -1, worstAnyPct = -1;
    for (const Json& r : renders) {
        const std::string name = r["name"].get<std::string>();
        const std::string s = r.value("series", r["strategy"].get<std::string>());
        const int rpp = r["max_rays_per_pixel"].get<int>();
        const Json m = r.value("metrics", Json::object());
        Json regions = Json::array();
        for (const Json& g : m.value("worst_regions", Json::array()))
            regions.push_back({{"x", g["x"]}, {"y", g["y"]}, {"size", g["size"]}, {"flip_mean", g["flip_mean"]}});
        const double pct = numberOr(m, "pct_error_flip");
        // Open on the selective render with most error, where there is most to see (or on the
        // render with most error when no selective one has any).
        if (std::isfinite(pct) && pct > worstAnyPct) worstAnyPct = pct, worstAny = list.size();
        if (r["strategy"] != baselineStrategyName() && std::isfinite(pct) && pct > worstSelectivePct)
            worstSelectivePct = pct, worstSelective = list.size();
        list.push_back({{"name", name},
                        {"series", s},
                        {"strategy", r["strategy"]},
                        {"rpp", rpp},
                        {"uniform", r["strategy"] == baselineStrategyName()},
                        {"mean_rpp", numberOrNull(numberOr(r, "mean_primary_rpp"))},
                        {"pct_flip", numberOrNull(pct)},
                        {"flip_mean", numberOrNull(numberOr(m, "flip_mean"))},
                        {"layers",
                         {{"render", present(name + ".png")},
                          {"flip", present(name + ".flip.png")},
                          {"overlay", present(name + ".overlay.png")},
                          {"rpp", present(name + ".rpp.png")},
                          {"causes", present(name + ".causes.png")}}},
                        {"regions", regions}});
        if (std::find(rpps.begin(), rpps.end(), rpp) == rpps.end()) rpps.push_back(rpp);
        if (std::find(series.begin(), series.end(), s) == series.end()) series.push_back(s);
    }
    std::sort(rpps.begin(), rpps.end());
    d["series"] = series;
    d["rpps"] = rpps;
    d["renders"] = list;
    d["initial"] = worstSelectivePct > 0 ? worstSelective : worstAny;
    return d;
}

std::string viewerSection(const Json& results, const fs::path& outDir) {
    const Json data = viewerData(results, outDir);
    if (data["renders"].empty()) return "";
    std::set<std::string> files;
    for (const char* f : {"reference", "aamap"})
        if (data[f].is_string()) files.insert(data[f].get<std::string>());
    for (const Json& r : data["renders"])
        for (const auto& [layer, f] : r["layers"].items())
            if (f.is_string()) files.insert(f.get<std::string>());
    std::string h = "<section id=\"viewer\">\n<h2>Compare a render with the reference</h2>\n"
                    "<p class=\"note\">Pick a render in the grid (rpp down, series across), then what to show and what to "
                    "compare it with: <b>flip</b> toggles between the two (Space), <b>slider</b> puts one left and one right "
                    "of a line you can drag. Wheel zooms at the cursor down to single pixels, drag pans, double-click toggles "
                    "fit and 4&times;. The crops below are the windows with the largest summed FLIP error.</p>\n"
                    "<div class=\"viewer\"></div>\n"
                    "<noscript><p class=\"problems\">The viewer needs JavaScript. The images it shows are the files beside this "
                    "page: NAME.png (render), NAME.flip.png, NAME.overlay.png, NAME.rpp.png, reference.png, aamap.png.</p>"
                    "</noscript>\n<div id=\"viewer-images\" hidden>";
    for (const std::string& f : files) h += fmt::format("<img src=\"{}\" alt=\"\">", htmlEscape(f));
    std::string json = data.dump();
    // Inside <script>, "</" could end the element early; JSON allows "<\/" for the same text.
    for (std::size_t p = json.find("</"); p != std::string::npos; p = json.find("</", p + 2)) json.replace(p, 2, "<\\/");
    h += "</div>\n<script type=\"application/json\" id=\"aamap-viewer-data\">" + json + "</script>\n</section>\n";
    return h;
}

}  // namespace aamap
