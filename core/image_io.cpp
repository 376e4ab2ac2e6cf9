#include "core/image_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <fmt/format.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include "core/atomic_file.h"
#include "core/error.h"

// stb_easy_font is all static functions (no implementation define, nothing in libstb).
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace aamap {
namespace {

template <class Pixel>
void checkWritable(const std::filesystem::path& path, const Image<Pixel>& image) {
    if (image.empty()) throw EnvironmentError(fmt::format("{}: refusing to write an empty image", path.string()));
}

// OpenEXR's own file stream drops errors in OutputFile's destructor (the line-offset table is
// written there); this one checks every write, and CheckedFile::close() reports a failure that
// OpenEXR swallowed.
class CheckedExrStream : public Imf::OStream {
public:
    CheckedExrStream(CheckedFile& file, const std::filesystem::path& tmp) : Imf::OStream(tmp.c_str()), file_(file) {}
    void write(const char c[], int n) override { file_.write(c, static_cast<std::size_t>(n)); }
    std::uint64_t tellp() override { return file_.position(); }
    void seekp(std::uint64_t pos) override { file_.seek(pos); }

private:
    CheckedFile& file_;
};

void writeExrChannels(const std::filesystem::path& path, int width, int height, const float* data,
                      const std::vector<const char*>& channels) {
    writeCheckedAtomically(path, [&](CheckedFile& out) {
        try {
            Imf::Header header(width, height);
            Imf::FrameBuffer frame;
            const std::size_t stride = channels.size() * sizeof(float);
            for (std::size_t c = 0; c < channels.size(); ++c) {
                header.channels().insert(channels[c], Imf::Channel(Imf::FLOAT));
                // OpenEXR takes a non-const base pointer even for writing.
                char* base = reinterpret_cast<char*>(const_cast<float*>(data + c));
                frame.insert(channels[c], Imf::Slice(Imf::FLOAT, base, stride, stride * width));
            }
            CheckedExrStream stream(out, path);
            Imf::OutputFile file(stream, header);
            file.setFrameBuffer(frame);
            file.writePixels(height);
        } catch (const EnvironmentError&) {
            throw;
        } catch (const std::exception& e) {
            // A write error from our stream, wrapped by OpenEXR: report it as the stream saw it.
            if (out.failed()) out.close();
            throw EnvironmentError(fmt::format("{}: cannot write EXR: {}", path.string(), e.what()));
        }
    });
}

bool exrIsGrey(const Imf::Header& header) {
    return header.channels().findChannel("R") == nullptr && header.channels().findChannel("Y") != nullptr;
}

// Reads the named channels (all must exist) into an interleaved float buffer. names == {} reads
// R, G, B from a colour file and Y from a greyscale one.
std::vector<float> readExrChannels(const std::filesystem::path& path, std::vector<const char*> names, int& width,
                                   int& height, bool& isGrey) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        width = dw.max.x - dw.min.x + 1;
        height = dw.max.y - dw.min.y + 1;
        isGrey = exrIsGrey(file.header());
        if (names.empty()) names = isGrey ? std::vector<const char*>{"Y"} : std::vector<const char*>{"R", "G", "B"};
        std::vector<float> data(static_cast<std::size_t>(width) * height * names.size());
        Imf::FrameBuffer frame;
        const std::size_t stride = names.size() * sizeof(float);
        for (std::size_t c = 0; c < names.size(); ++c) {
            if (file.header().channels().findChannel(names[c]) == nullptr)
                throw InputError(path, fmt::format("EXR has no channel '{}'", names[c]));
            // The slice base is offset so that data window origin (min.x, min.y) lands on element 0.
            char* base = reinterpret_cast<char*>(data.data() + c) -
                         (static_cast<std::ptrdiff_t>(dw.min.x) + static_cast<std::ptrdiff_t>(dw.min.y) * width) *
                             static_cast<std::ptrdiff_t>(stride);
            frame.insert(names[c], Imf::Slice(Imf::FLOAT, base, stride, stride * width));
        }
        file.setFrameBuffer(frame);
        file.readPixels(dw.min.y, dw.max.y);
        return data;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(path, fmt::format("cannot read EXR: {}", e.what()));
    }
}

void writePngBytes(const std::filesystem::path& path, int width, int height, int components, const void* data) {
    // Encoded in memory first: stbi_write_png ignores fwrite errors, and a C callback must not throw.
    std::vector<unsigned char> png;
    const auto append = [](void* context, void* bytes, int size) {
        auto* out = static_cast<std::vector<unsigned char>*>(context);
        out->insert(out->end(), static_cast<unsigned char*>(bytes), static_cast<unsigned char*>(bytes) + size);
    };
    if (stbi_write_png_to_func(append, &png, width, height, components, data, width * components) == 0)
        throw EnvironmentError(fmt::format("{}: cannot encode PNG", path.string()));
    writeCheckedAtomically(path, [&](CheckedFile& file) { file.write(png.data(), png.size()); });
}

std::uint8_t toByte(float v) {
    if (!std::isfinite(v)) return 0;
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

void writeExr(const std::filesystem::path& path, const ImageRGB& image) {
    checkWritable(path, image);
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
    writeExrChannels(path, image.width(), image.height(), &image.data()->x, {"R", "G", "B"});
}

void writeExr(const std::filesystem::path& path, const ImageGrey& image) {
    checkWritable(path, image);
    writeExrChannels(path, image.width(), image.height(), image.data(), {"Y"});
}

ImageRGB readExr(const std::filesystem::path& path) {
    int w = 0, h = 0;
    bool grey = false;
    std::vector<float> data = readExrChannels(path, {}, w, h, grey);
    ImageRGB image(w, h);
    for (std::size_t i = 0; i < image.size(); ++i)
        image.pixels()[i] = grey ? glm::vec3(data[i]) : glm::vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
    return image;
}

ImageGrey readExrGrey(const std::filesystem::path& path) {
    int w = 0, h = 0;
    bool grey = false;
    std::vector<float> data = readExrChannels(path, {}, w, h, grey);
    if (!grey) throw InputError(path, "expected a single-channel (Y) EXR map, found colour channels");
    ImageGrey image(w, h);
    image.pixels() = std::move(data);
    return image;
}

void writePng(const std::filesystem::path& path, const ImageRGB8& image) {
    checkWritable(path, image);
    static_assert(sizeof(glm::u8vec3) == 3);
    writePngBytes(path, image.width(), image.height(), 3, image.data());
}

void writePng(const std::filesystem::path& path, const ImageGrey8& image) {
    checkWritable(path, image);
    writePngBytes(path, image.width(), image.height(), 1, image.data());
}

ImageRGB8 readPng(const std::filesystem::path& path) {
    int w = 0, h = 0, comp = 0;
    unsigned char* bytes = stbi_load(path.c_str(), &w, &h, &comp, 3);
    if (bytes == nullptr) throw InputError(path, fmt::format("cannot read PNG: {}", stbi_failure_reason()));
    ImageRGB8 image(w, h);
    std::copy_n(bytes, image.size() * 3, reinterpret_cast<unsigned char*>(image.data()));
    stbi_image_free(bytes);
    return image;
}

float displayEncode(float linear, float exposure) {
    const float v = linear * exposure;
    if (!std::isfinite(v)) return 0.0f;  // as toneMap(): a clamp would turn +inf white
    return srgbEncode(v);                // clamps to [0,1] first
}

float srgbEncode(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

ImageRGB8 toneMap(const ImageRGB& image, float exposure) {
    ImageRGB8 out(image.width(), image.height());
    for (std::size_t i = 0; i < image.size(); ++i) {
        const glm::vec3 c = image.pixels()[i] * exposure;
        out.pixels()[i] = {toByte(srgbEncode(c.r)), toByte(srgbEncode(c.g)), toByte(srgbEncode(c.b))};
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(c[k])) out.pixels()[i][k] = 0;  // clamp would map +Inf to white
    }
    return out;
}

ImageGrey8 quantise(const ImageGrey& image, float scale) {
    ImageGrey8 out(image.width(), image.height());
    for (std::size_t i = 0; i < image.size(); ++i) out.pixels()[i] = toByte(image.pixels()[i] * scale);
    return out;
}

glm::u8vec3 colourRamp(float t) {
    // viridis, sampled at 9 evenly spaced stops (matplotlib's table)
    static constexpr std::array<std::array<float, 3>, 9> stops{{{68, 1, 84},
                                                                {71, 44, 122},
                                                                {59, 81, 139},
                                                                {44, 113, 142},
                                                                {33, 144, 141},
                                                                {39, 173, 129},
                                                                {92, 200, 99},
                                                                {170, 220, 50},
                                                                {253, 231, 37}}};
    if (!std::isfinite(t)) t = 0.0f;
    const float x = std::clamp(t, 0.0f, 1.0f) * (stops.size() - 1);
    const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(x), stops.size() - 2);
    const float f = x - static_cast<float>(i);
    glm::u8vec3 c;
    for (int k = 0; k < 3; ++k)
        c[k] = static_cast<std::uint8_t>(std::lround(stops[i][k] + f * (stops[i + 1][k] - stops[i][k])));
    return c;
}

// ---- false colour with legend -------------------------------------------------------------------

namespace {

constexpr int kMinCanvasWidth = 160;  // enough for the legend title at font scale 1
const glm::u8vec3 kBackground{32, 32, 32};
const glm::u8vec3 kText{255, 255, 255};

int fontScale(int width) { return std::max(1, width / 256); }

void fillRect(ImageRGB8& img, int x0, int y0, int x1, int y1, glm::u8vec3 c) {
    for (int y = std::max(0, y0); y < std::min(img.height(), y1); ++y)
        for (int x = std::max(0, x0); x < std::min(img.width(), x1); ++x) img.at(x, y) = c;
}

int textWidth(const std::string& s, int scale) {
    return stb_easy_font_width(const_cast<char*>(s.c_str())) * scale;
}

void drawText(ImageRGB8& img, int x, int y, const std::string& s, int scale) {
    // stb_easy_font emits axis-aligned quads (4 vertices of x, y, z, rgba) in unit pixels.
    struct Vertex {
        float x, y, z;
        unsigned char rgba[4];
    };
    std::vector<Vertex> quads(s.size() * 80 + 64);
    const int n = stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, quads.data(),
                                      static_cast<int>(quads.size() * sizeof(Vertex)));
    for (int q = 0; q < n; ++q) {
        const Vertex& a = quads[4 * q];
        const Vertex& b = quads[4 * q + 2];
        fillRect(img, x + static_cast<int>(a.x) * scale, y + static_cast<int>(a.y) * scale,
                 x + static_cast<int>(b.x) * scale, y + static_cast<int>(b.y) * scale, kText);
    }
}

}  // namespace

int falseColourLegendHeight(int width) { return 40 * fontScale(std::max(width, kMinCanvasWidth)); }

ImageRGB8 falseColour(const Image<std::uint16_t>& rpp, int maxRpp) {
    maxRpp = std::max(1, maxRpp);
    const int canvasW = std::max(rpp.width(), kMinCanvasWidth);
    const int s = fontScale(canvasW);
    const int legendH = falseColourLegendHeight(rpp.width());
    ImageRGB8 img(canvasW, rpp.height() + legendH, kBackground);

    auto colourOf = [&](int r) -> glm::u8vec3 {
        if (r <= 0) return {0, 0, 0};
        return colourRamp(maxRpp == 1 ? 1.0f : static_cast<float>(r - 1) / static_cast<float>(maxRpp - 1));
    };
    bool anyZero = false;
    for (int y = 0; y < rpp.height(); ++y)
        for (int x = 0; x < rpp.width(); ++x) {
            img.at(x, y) = colourOf(rpp.at(x, y));
            anyZero = anyZero || rpp.at(x, y) == 0;
        }

    // Legend: title, colour bar from 1 to maxRpp, tick marks and labels under it.
    const int top = rpp.height();
    const std::string title = anyZero ? fmt::format("rays/pixel (1 .. {}; black = 0)", maxRpp)
                                      : fmt::format("rays/pixel (1 .. {})", maxRpp);
    const int margin = 6 * s;
    drawText(img, margin, top + 3 * s, title, s);
    const int barX0 = margin, barX1 = canvasW - margin, barY0 = top + 13 * s, barY1 = top + 23 * s;
    for (int x = barX0; x < barX1; ++x) {
        const float t = static_cast<float>(x - barX0) / static_cast<float>(std::max(1, barX1 - barX0 - 1));
        fillRect(img, x, barY0, x + 1, barY1, colourRamp(t));
    }
    auto tickX = [&](int r) {
        const float t = maxRpp == 1 ? 1.0f : static_cast<float>(r - 1) / static_cast<float>(maxRpp - 1);
        return barX0 + static_cast<int>(std::lround(t * (barX1 - barX0 - 1)));
    };
    // Ticks: the ends first, then the square counts (k x k strata) wherever their labels fit.
    std::vector<int> candidates{maxRpp};
    if (maxRpp > 1) candidates.push_back(1);
    for (int k = 2; k * k < maxRpp; ++k) candidates.push_back(k * k);
    std::vector<std::pair<int, int>> used;  // label extents
    for (int r : candidates) {
        const std::string label = std::to_string(r);
        const int w = textWidth(label, s);
        const int x = std::clamp(tickX(r) - w / 2, 0, canvasW - w);
        const bool overlaps = std::any_of(used.begin(), used.end(), [&](const std::pair<int, int>& u) {
            return x < u.second + 3 * s && x + w + 3 * s > u.first;
        });
        if (overlaps) continue;
        used.emplace_back(x, x + w);
        fillRect(img, tickX(r), barY1, tickX(r) + s, barY1 + 3 * s, kText);
        drawText(img, x, barY1 + 5 * s, label, s);
    }
    return img;
}

}  // namespace aamap
