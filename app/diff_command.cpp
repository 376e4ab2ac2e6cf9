#include "app/diff_command.h"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image_io.h"
#include "eval/metrics/flip_color.h"
#include "eval/metrics/image_comparison.h"

namespace aamap::app {
namespace fs = std::filesystem;

namespace {

ImageRGB readLinear(const fs::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".exr") return readExr(path);
    if (ext == ".png") {  // what a display shows: decoded, as the metrics see it at exposure 1
        const ImageRGB8 png = readPng(path);
        ImageRGB img(png.width(), png.height());
        for (int y = 0; y < png.height(); ++y)
            for (int x = 0; x < png.width(); ++x) {
                const glm::u8vec3 c = png.at(x, y);
                img.at(x, y) = {metrics::flip::srgbToLinear(c.r / 255.0f), metrics::flip::srgbToLinear(c.g / 255.0f), metrics::flip::srgbToLinear(c.b / 255.0f)};
            }
        return img;
    }
    throw InputError(path, fmt::format("unsupported image format '{}' (expected .exr or .png)", ext));
}

// A float setting as the user wrote it (0.1, not 0.10000000149011612).
double asWritten(float v) { return std::stod(fmt::format("{}", v)); }

nlohmann::ordered_json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

}  // namespace

CLI::App* addDiffCommand(CLI::App& app, DiffOptions& o) {
    CLI::App* cmd = app.add_subcommand("diff", "Compare two images: LDR- and HDR-FLIP, MSE/PSNR, % pixels in error");
    cmd->add_option("REFERENCE", o.reference, "Reference image (.exr linear, or .png sRGB)")->required();
    cmd->add_option("TEST", o.test, "Image to measure against it, of the same size")->required();
    cmd->add_option("--heatmap", o.heatmap, "Write the LDR-FLIP error map (magma) to this PNG")->type_name("OUT.png");
    cmd->add_option("--exposure", o.exposure, "Display exposure of both images (as image.exposure)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--threshold", o.threshold, "FLIP above this counts as a pixel in error (as metrics.flip_threshold)")
        ->check(CLI::Range(0.0f, 1.0f));
    cmd->add_option("--ppd", o.ppd, "FLIP pixels per degree (default 67.02, as metrics.ppd)")
        ->check(CLI::Range(0.0f, 1000.0f));
    cmd->add_option("--mse-threshold", o.mseThreshold,
                    "Display-space squared error of a pixel in error (default (2/255)^2, as metrics.mse_threshold)")
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_flag("--json", o.json, "Print one JSON object instead of the table");
    cmd->footer("Exit codes: 0 compared, 2 an image is unreadable or the sizes differ.");
    return cmd;
}

void runDiffCommand(const DiffOptions& o) {
    const ImageRGB reference = readLinear(o.reference);
    const ImageRGB test = readLinear(o.test);
    if (reference.width() != test.width() || reference.height() != test.height())
        throw InputError(o.test, fmt::format("is {}x{}, the reference {} is {}x{}", test.width(), test.height(),
                                             o.reference, reference.width(), reference.height()));
    if (reference.empty()) throw InputError(o.reference, "the image is empty");
    metrics::ComparisonOptions co;
    co.exposure = o.exposure;
    co.flipThreshold = o.threshold;
    if (o.ppd > 0.0f) co.ppd = o.ppd;
    if (o.mseThreshold > 0.0) co.mseThreshold = o.mseThreshold;
    co.flip = co.flipHdr = true;
    const metrics::Comparison c = metrics::compareImages(reference, test, co);
    if (!o.heatmap.empty()) writePng(o.heatmap, toneMap(metrics::flipMagma(*c.flip), 1.0f));

    if (o.json) {
        const nlohmann::ordered_json j = {
            {"reference", o.reference}, {"test", o.test}, {"width", reference.width()}, {"height", reference.height()},
            {"exposure", asWritten(co.exposure)}, {"ppd", asWritten(co.ppd)},
            {"flip_threshold", asWritten(co.flipThreshold)},
            {"mse_threshold", co.mseThreshold},
            {"flip_mean", c.flip->mean}, {"pct_error_flip", 100.0 * c.flip->fractionAbove},
            {"flip_hdr_mean", c.flipHdr->mean}, {"pct_error_flip_hdr", 100.0 * c.flipHdr->fractionAbove},
            {"mse", c.display.mse}, {"rmse", c.display.rmse}, {"psnr", finiteOrNull(c.display.psnr)},
            {"pct_error_mse", 100.0 * c.display.fractionInError}};
        fmt::print("{}\n", j.dump(2));
        return;
    }
    fmt::print("reference  {} ({}x{})\ntest       {}\n", o.reference, reference.width(), reference.height(), o.test);
    fmt::print("LDR-FLIP   mean {:.6f}, {:.3f} % of pixels above {:g}\n", c.flip->mean, 100.0 * c.flip->fractionAbove,
               co.flipThreshold);
    fmt::print("HDR-FLIP   mean {:.6f}, {:.3f} % of pixels above {:g}\n", c.flipHdr->mean,
               100.0 * c.flipHdr->fractionAbove, co.flipThreshold);
    fmt::print("MSE        {:.6g} (RMSE {:.6g}, PSNR {}), {:.3f} % of pixels in error\n", c.display.mse, c.display.rmse,
               std::isfinite(c.display.psnr) ? fmt::format("{:.2f} dB", c.display.psnr) : std::string("inf: identical"),
               100.0 * c.display.fractionInError);
    if (!o.heatmap.empty()) fmt::print("heatmap    {}\n", o.heatmap);
}

}  // namespace aamap::app
