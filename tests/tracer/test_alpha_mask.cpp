// The tracer cuts out the same texels as the Snapshot: alpha-tested materials install Embree
// filters that reject hits on cut-out texels for closest-hit and shadow rays alike, and scenes
// without masks install none.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "tracer/embree_scene.h"

namespace aamap {
namespace {

// A side x side texture: alpha 0 in the central half, 1 around it (rgb white).
Texture holeTexture(int side) {
    Texture t;
    t.width = t.height = side;
    t.rgba.assign(static_cast<std::size_t>(side) * side * 4, 1.0f);
    for (int y = side / 4; y < 3 * side / 4; ++y)
        for (int x = side / 4; x < 3 * side / 4; ++x) t.rgba[4 * (static_cast<std::size_t>(y) * side + x) + 3] = 0.0f;
    return t;
}

// Square [-1, 1]^2 at z facing +z; uv (0, 0) at its top-left corner (x = -1, y = 1).
void addQuad(Scene& s, float z, std::uint32_t material) {
    const auto base = static_cast<std::uint32_t>(s.mesh.positions.size());
    s.mesh.positions.insert(s.mesh.positions.end(), {{-1, -1, z}, {1, -1, z}, {1, 1, z}, {-1, 1, z}});
    s.mesh.normals.insert(s.mesh.normals.end(), 4, glm::vec3(0, 0, 1));
    s.mesh.uvs.insert(s.mesh.uvs.end(), {{0, 1}, {1, 1}, {1, 0}, {0, 0}});
    s.mesh.triangles.insert(s.mesh.triangles.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    s.mesh.materialIds.insert(s.mesh.materialIds.end(), 2, material);
    s.mesh.objectIds.insert(s.mesh.objectIds.end(), 2, material);
}

// A masked quad at z = 0 in front of an opaque one at z = -1.
Scene maskedScene(AlphaMode mode, float alpha, bool textured) {
    Scene s;
    Material front;
    front.name = "leaf";
    front.alphaMode = mode;
    front.alpha = alpha;
    if (textured) {
        s.textures.push_back(holeTexture(16));
        front.diffuseTexture = front.alphaTexture = 0;
    }
    Material back;
    back.name = "wall";
    s.materials = {front, back};
    addQuad(s, 0.0f, 0);
    addQuad(s, -1.0f, 1);
    return s;
}

float closestHit(const EmbreeScene& g, float x, float y) {
    RTCRayHit rh = makeRayHit({x, y, 3.0f}, {0, 0, -1});
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(g.handle(), &context, &rh);
    return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1.0f : rh.ray.tfar;
}

bool occludedBetweenTheQuads(const EmbreeScene& g, float x, float y) {
    RTCRay ray = makeRayHit({x, y, -0.5f}, {0, 0, 1}).ray;
    ray.tfar = 10.0f;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1(g.handle(), &context, &ray);
    return ray.tfar < 0.0f;
}

TEST(AlphaMask, MaskedTexelsAreCutOutForCameraAndShadowRays) {
    const Scene scene = maskedScene(AlphaMode::Mask, 1.0f, true);
    const EmbreeScene g(scene);
    EXPECT_TRUE(g.features().alphaMask);
    // Hole: texels 4..11 of 16, i.e. |x|, |y| < 0.5 on the quad (bilinear: the 0.5 crossing is
    // on the texel boundary). Sample away from it by a quarter texel (1/32 in quad units).
    for (float y = -0.95f; y < 1.0f; y += 0.1f) {
        for (float x = -0.95f; x < 1.0f; x += 0.1f) {
            const float m = std::max(std::fabs(x), std::fabs(y));
            if (std::fabs(m - 0.5f) < 1.0f / 32.0f) continue;
            const bool hole = m < 0.5f;
            EXPECT_FLOAT_EQ(closestHit(g, x, y), hole ? 4.0f : 3.0f) << x << "," << y;
            EXPECT_EQ(occludedBetweenTheQuads(g, x, y), !hole) << x << "," << y;
        }
    }
    EXPECT_FALSE(g.cutOut(0, 0.0f, 0.0f));   // triangle 0's corner (-1, -1): opaque texel
    EXPECT_TRUE(g.cutOut(0, 0.05f, 0.5f));   // (0.1, 0), inside the hole
    EXPECT_FALSE(g.cutOut(2, 0.05f, 0.5f));  // the wall is opaque
}

TEST(AlphaMask, ConstantCoverageCutsEverythingOrNothing) {
    // BLEND at 0.25 is a mask at 0.5: the whole quad is cut; at 0.75 none of it is, and such a
    // material needs no filter at all.
    const EmbreeScene faint(maskedScene(AlphaMode::Blend, 0.25f, false));
    EXPECT_TRUE(faint.features().alphaMask);
    EXPECT_FLOAT_EQ(closestHit(faint, 0.8f, 0.8f), 4.0f);
    EXPECT_FALSE(occludedBetweenTheQuads(faint, 0.8f, 0.8f));
    const EmbreeScene solid(maskedScene(AlphaMode::Blend, 0.75f, false));
    EXPECT_FALSE(solid.features().alphaMask);
    EXPECT_FLOAT_EQ(closestHit(solid, 0.0f, 0.0f), 3.0f);
}

TEST(AlphaMask, OpaqueScenesInstallNoFilter) {
    const EmbreeScene g(maskedScene(AlphaMode::Opaque, 1.0f, true));
    EXPECT_FALSE(g.features().alphaMask);
    EXPECT_FLOAT_EQ(closestHit(g, 0.0f, 0.0f), 3.0f);  // the texture's alpha is ignored
}

}  // namespace
}  // namespace aamap
