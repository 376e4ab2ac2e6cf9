#pragma once
// The comparison viewer of report.html: its markup, the images it shows and the data its script
// (eval/report_page/viewer.js) reads. The images sit on the page as plain hidden <img src>
// elements, relative to OUTDIR, so the browser loads them from disk and the links stay visible to
// any tool that reads the HTML; the data is a JSON block, since a page opened from file:// cannot
// fetch results.json.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace aamap {

// The data: image size, exposure, FLIP threshold, the reference and aamap images, the colour
// maps of the false-colour layers (as CSS colours, from the same tables the PNGs were made with),
// and per render its name, series, rpp, mean primary rpp, % FLIP, layer images and worst regions
// (metrics.worst_regions). Only files that exist in outDir are named.
nlohmann::ordered_json viewerData(const nlohmann::ordered_json& results, const std::filesystem::path& outDir);

// The viewer's section (heading, mount point, hidden images, data, a note without JavaScript);
// "" when there are no renders.
std::string viewerSection(const nlohmann::ordered_json& results, const std::filesystem::path& outDir);

}  // namespace aamap
