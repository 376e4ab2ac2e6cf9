// Cross-check of eval/metrics FLIP against the reference implementation (PyPI flip-evaluator 1.7)
// run from the repo's .venv (tools/python-env.sh). Label "python".
//
// LDR: image pairs are made here as 8-bit sRGB, written as PNG, read by flip_evaluator, and the
// same 8-bit values / 255 go to flipLdrSrgb(); the means must agree within 1e-3.
// HDR: linear float pairs written as EXR (exact), HDR-FLIP with default settings on both sides.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <gtest/gtest.h>
#include <unistd.h>

#include "core/image_io.h"
#include "eval/metrics/flip.h"
#include "patterns.h"

namespace aamap::metrics {
namespace {

namespace fs = std::filesystem;

struct Pair {
    std::string name;
    ImageRGB reference;
    ImageRGB test;
};

ImageRGB8 toSrgb8(const ImageRGB& linear) { return toneMap(linear, 1.0f); }

ImageRGB fromSrgb8(const ImageRGB8& img) {
    ImageRGB out(img.width(), img.height());
    for (std::size_t i = 0; i < img.size(); ++i) out.pixels()[i] = glm::vec3(img.pixels()[i]) / 255.0f;
    return out;
}

ImageRGB boxBlur(const ImageRGB& in, int r) {
    ImageRGB out(in.width(), in.height());
    for (int y = 0; y < in.height(); ++y)
        for (int x = 0; x < in.width(); ++x) {
            glm::vec3 acc(0.0f);
            int n = 0;
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= in.width() || yy >= in.height()) continue;
                    acc += in.at(xx, yy);
                    ++n;
                }
            out.at(x, y) = acc / float(n);
        }
    return out;
}

// A disc edge sampled once per pixel (aliased) or 16 times (antialiased): this project's case.
ImageRGB disc(int w, int h, int samplesPerAxis) {
    ImageRGB img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float inside = 0.0f;
            for (int j = 0; j < samplesPerAxis; ++j)
                for (int i = 0; i < samplesPerAxis; ++i) {
                    const float sx = float(x) + (float(i) + 0.5f) / float(samplesPerAxis);
                    const float sy = float(y) + (float(j) + 0.5f) / float(samplesPerAxis);
                    inside += std::hypot(sx - 0.5f * float(w), sy - 0.45f * float(h)) < 0.33f * float(h) ? 1.0f : 0.0f;
                }
            inside /= float(samplesPerAxis * samplesPerAxis);
            img.at(x, y) = glm::mix(glm::vec3(0.1f, 0.12f, 0.15f), glm::vec3(0.9f, 0.8f, 0.3f), inside);
        }
    return img;
}

std::vector<Pair> ldrPairs() {
    const int w = 96, h = 72;
    const ImageRGB base = test::scene(w, h);
    std::vector<Pair> pairs;
    // Noise: +-0.15 in linear, per channel.
    ImageRGB noisy = base;
    test::Rng rng(42);
    for (auto& p : noisy.pixels()) p = glm::clamp(p + (glm::vec3(rng.next(), rng.next(), rng.next()) - 0.5f) * 0.3f, 0.0f, 1.0f);
    pairs.push_back({"noise", base, noisy});
    pairs.push_back({"shifted_edges", base, test::scene(w, h, 1.0f)});
    // Colour change: the red disc turns green-ish, the background hue rotates.
    ImageRGB recoloured = base;
    for (auto& p : recoloured.pixels()) p = p.r > 0.85f ? glm::vec3(0.2f, 0.8f, 0.1f) : glm::vec3(p.g, p.b, p.r);
    pairs.push_back({"colour_change", base, recoloured});
    pairs.push_back({"blur", base, boxBlur(base, 1)});
    pairs.push_back({"aliased_disc", disc(w, h, 4), disc(w, h, 1)});
    pairs.push_back({"black_white", ImageRGB(w / 2, h / 2, glm::vec3(0.0f)), ImageRGB(w / 2, h / 2, glm::vec3(1.0f))});
    return pairs;
}

class FlipCrossCheck : public ::testing::Test {
protected:
    void SetUp() override {
        python_ = fs::path(AAMAP_SOURCE_DIR) / ".venv" / "bin" / "python";
        ASSERT_TRUE(fs::exists(python_)) << "no Python environment at " << python_
                                         << "; create it with tools/python-env.sh (needs access to PyPI)";
        dir_ = fs::temp_directory_path() / ("aamap_flip_crosscheck_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    struct Means {
        double pooled;  // flip_evaluator's own mean (float32 accumulation)
        double map;     // mean of its error map in float64
    };

    // Runs tools/flip_crosscheck.py on the files (ref, test, ref, test, ...); one line per pair.
    std::vector<Means> referenceMeans(const std::vector<fs::path>& files, bool hdr) {
        // Appends rather than operator+ chains: GCC 12 warns falsely (-Wrestrict) on those.
        std::string cmd;
        auto arg = [&cmd](const std::string& a) {
            cmd.append(cmd.empty() ? "'" : " '").append(a).append("'");
        };
        arg(python_.string());
        arg((fs::path(AAMAP_SOURCE_DIR) / "tools" / "flip_crosscheck.py").string());
        if (hdr) arg("--hdr");
        for (const auto& f : files) arg(f.string());
        std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd.c_str(), "r"), ::pclose);
        std::string out;
        std::array<char, 256> buf{};
        while (pipe && std::fgets(buf.data(), int(buf.size()), pipe.get())) out += buf.data();
        const int status = pipe ? ::pclose(pipe.release()) : -1;
        EXPECT_EQ(status, 0) << "command failed: " << cmd << "\n" << out;
        std::vector<Means> means;
        std::istringstream in(out);
        for (Means m; in >> m.pooled >> m.map;) means.push_back(m);
        return means;
    }

    static void report(const char* kind, const std::string& name, double ours, Means theirs) {
        std::printf("%s %-16s C++ %.7f  flip_evaluator %.7f (map mean %.7f)  diff %+.1e\n", kind, name.c_str(), ours,
                    theirs.pooled, theirs.map, ours - theirs.map);
        EXPECT_NEAR(ours, theirs.pooled, 1e-3) << name;
        EXPECT_NEAR(ours, theirs.map, 1e-3) << name;
    }

    fs::path python_;
    fs::path dir_;
};

TEST_F(FlipCrossCheck, LdrMeansMatchFlipEvaluator) {
    const std::vector<Pair> pairs = ldrPairs();
    std::vector<fs::path> files;
    std::vector<double> ours;
    for (const Pair& p : pairs) {
        const ImageRGB8 r8 = toSrgb8(p.reference), t8 = toSrgb8(p.test);
        files.push_back(dir_ / (p.name + "_ref.png"));
        files.push_back(dir_ / (p.name + "_test.png"));
        writePng(files[files.size() - 2], r8);
        writePng(files.back(), t8);
        ours.push_back(flipLdrSrgb(fromSrgb8(r8), fromSrgb8(t8)).mean);
    }
    const std::vector<Means> theirs = referenceMeans(files, false);
    ASSERT_EQ(theirs.size(), pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        report("LDR", pairs[i].name, ours[i], theirs[i]);
    }
}

TEST_F(FlipCrossCheck, HdrMeansMatchFlipEvaluator) {
    const int w = 80, h = 60;
    ImageRGB bright = test::scene(w, h);
    for (int y = 0; y < h / 3; ++y)
        for (int x = 0; x < w; ++x) bright.at(x, y) *= 1.0f + 8.0f * float(x) / float(w);  // up to ~9x
    ImageRGB noisy = bright;
    test::Rng rng(7);
    for (auto& p : noisy.pixels()) p *= 0.7f + 0.6f * rng.next();
    const std::vector<Pair> pairs = {{"hdr_noise", bright, noisy},
                                     {"hdr_aliased_disc", disc(w, h, 4), disc(w, h, 1)}};
    std::vector<fs::path> files;
    std::vector<double> ours;
    for (const Pair& p : pairs) {
        files.push_back(dir_ / (p.name + "_ref.exr"));
        files.push_back(dir_ / (p.name + "_test.exr"));
        writeExr(files[files.size() - 2], p.reference);
        writeExr(files.back(), p.test);
        // Read back, in case the file stores fewer bits than float.
        ours.push_back(flipHdr(readExr(files[files.size() - 2]), readExr(files.back())).mean);
    }
    const std::vector<Means> theirs = referenceMeans(files, true);
    ASSERT_EQ(theirs.size(), pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        report("HDR", pairs[i].name, ours[i], theirs[i]);
    }
}

}  // namespace
}  // namespace aamap::metrics
