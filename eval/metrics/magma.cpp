#include "eval/metrics/magma.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

#include "eval/metrics/flip_color.h"

namespace aamap::metrics {
namespace {

// Entries 0, 5, 10, ..., 255 of matplotlib's magma table (sRGB), evenly spaced in t.
constexpr std::array<glm::vec3, 52> kMagma = {{
    {0.001462f, 0.000466f, 0.013866f}, {0.007588f, 0.006356f, 0.044973f}, {0.018815f, 0.016026f, 0.084584f},
    {0.035520f, 0.028397f, 0.125209f}, {0.056615f, 0.042160f, 0.167446f}, {0.078815f, 0.054184f, 0.211667f},
    {0.102815f, 0.063010f, 0.257854f}, {0.129380f, 0.067935f, 0.305443f}, {0.159018f, 0.068354f, 0.352688f},
    {0.191460f, 0.064818f, 0.396152f}, {0.225302f, 0.060445f, 0.431742f}, {0.258857f, 0.059706f, 0.457710f},
    {0.291366f, 0.064553f, 0.475462f}, {0.322899f, 0.073782f, 0.487408f}, {0.353773f, 0.085373f, 0.495501f},
    {0.384299f, 0.097855f, 0.501002f}, {0.414709f, 0.110431f, 0.504662f}, {0.445163f, 0.122724f, 0.506901f},
    {0.475780f, 0.134577f, 0.507921f}, {0.506629f, 0.145958f, 0.507806f}, {0.537755f, 0.156894f, 0.506551f},
    {0.569172f, 0.167454f, 0.504105f}, {0.600868f, 0.177743f, 0.500394f}, {0.632805f, 0.187893f, 0.495332f},
    {0.664915f, 0.198075f, 0.488836f}, {0.697098f, 0.208501f, 0.480835f}, {0.729216f, 0.219437f, 0.471279f},
    {0.761077f, 0.231214f, 0.460162f}, {0.792427f, 0.244242f, 0.447543f}, {0.822926f, 0.259016f, 0.433573f},
    {0.852126f, 0.276106f, 0.418573f}, {0.879464f, 0.296125f, 0.403118f}, {0.904281f, 0.319610f, 0.388137f},
    {0.925937f, 0.346844f, 0.374959f}, {0.944006f, 0.377643f, 0.365136f}, {0.958464f, 0.411324f, 0.360014f},
    {0.969680f, 0.446936f, 0.360311f}, {0.978210f, 0.483612f, 0.366025f}, {0.984622f, 0.520713f, 0.376698f},
    {0.989363f, 0.557873f, 0.391671f}, {0.992785f, 0.594891f, 0.410283f}, {0.995122f, 0.631696f, 0.431951f},
    {0.996580f, 0.668256f, 0.456192f}, {0.997254f, 0.704611f, 0.482635f}, {0.997285f, 0.740772f, 0.510983f},
    {0.996727f, 0.776795f, 0.541039f}, {0.995680f, 0.812706f, 0.572645f}, {0.994222f, 0.848540f, 0.605696f},
    {0.992440f, 0.884330f, 0.640099f}, {0.990570f, 0.920049f, 0.675675f}, {0.988717f, 0.955742f, 0.712242f},
    {0.987053f, 0.991438f, 0.749504f},
}};

}  // namespace

glm::vec3 magmaSrgb(float t) {
    if (!(t > 0.0f)) return kMagma.front();  // also NaN
    if (t >= 1.0f) return kMagma.back();
    const float p = t * float(kMagma.size() - 1);
    const int i = std::min(int(p), int(kMagma.size()) - 2);
    const float f = p - float(i);
    return kMagma[i] * (1.0f - f) + kMagma[i + 1] * f;
}

ImageRGB magmaImage(const ImageGrey& values) {
    ImageRGB out(values.width(), values.height());
    tbb::parallel_for(0, values.height(), [&](int y) {
        for (int x = 0; x < values.width(); ++x) {
            const glm::vec3 c = magmaSrgb(values.at(x, y));
            out.at(x, y) = {flip::srgbToLinear(c.x), flip::srgbToLinear(c.y), flip::srgbToLinear(c.z)};
        }
    });
    return out;
}

}  // namespace aamap::metrics
