#include "passes/cpu_geometric.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "glsl/shared/geometric_edges.h"

namespace aamap::cpu {
namespace {

bool covered(const glm::vec4& nd) { return nd.w > 0.0f; }

// Float arithmetic in the GLSL order, so both sides decide alike.
bool depthJump(const glm::vec4& a, const glm::vec4& p, const glm::vec4& b) {
    if (!covered(a) || !covered(b)) return false;
    const float wp = 1.0f / p.w;
    const float second = (1.0f / a.w + 1.0f / b.w) - 2.0f * wp;
    return std::fabs(second) > static_cast<float>(GEOMETRIC_DEPTH_TOLERANCE) * wp;
}

bool differs(const glm::vec4& np, const glm::vec4& ip, const glm::vec4& nq, const glm::vec4& iq) {
    if (covered(np) != covered(nq)) return true;
    if (!covered(np)) return false;
    if (ip != iq) return true;  // object, material, occlusion mask
    const float d = np.x * nq.x + np.y * nq.y + np.z * nq.z;
    return d < static_cast<float>(GEOMETRIC_CREASE_COS);
}

}  // namespace

ImageGrey geometricEdges(const GeometryImages& g) {
    const int W = g.normalDepth.width(), H = g.normalDepth.height();
    if (g.ids.width() != W || g.ids.height() != H) throw std::invalid_argument("geometricEdges: image sizes differ");
    ImageGrey out(W, H, 0.0f);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::vec4& np = g.normalDepth.at(x, y);
            const glm::vec4& ip = g.ids.at(x, y);
            const int xl = std::max(x - 1, 0), xr = std::min(x + 1, W - 1);
            const int yu = std::max(y - 1, 0), yd = std::min(y + 1, H - 1);
            bool edge = false;
            for (auto [qx, qy] : {std::pair{xl, y}, std::pair{xr, y}, std::pair{x, yu}, std::pair{x, yd}})
                edge = edge || differs(np, ip, g.normalDepth.at(qx, qy), g.ids.at(qx, qy));
            if (!edge && covered(np))
                edge = depthJump(g.normalDepth.at(xl, y), np, g.normalDepth.at(xr, y)) ||
                       depthJump(g.normalDepth.at(x, yu), np, g.normalDepth.at(x, yd));
            out.at(x, y) = edge ? static_cast<float>(GEOMETRIC_EDGE_VALUE) : 0.0f;
        }
    return out;
}

ImageGrey maxEdges(const ImageGrey& a, const ImageGrey& b) {
    if (a.width() != b.width() || a.height() != b.height()) throw std::invalid_argument("maxEdges: sizes differ");
    ImageGrey out(a.width(), a.height());
    for (std::size_t i = 0; i < a.size(); ++i) out.data()[i] = std::max(a.data()[i], b.data()[i]);
    return out;
}

}  // namespace aamap::cpu
