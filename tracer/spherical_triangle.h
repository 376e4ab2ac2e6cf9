#pragma once
// A triangle as seen from a point: the spherical triangle its vertices project to on the unit
// sphere around the receiver. Sampling directions uniformly within it gives an area light's
// samples pdf 1 / solid angle, so the estimator loses the 1/d^2 and cos' factors that make area
// sampling noisy close to a large light (docs/tracer.md, "Light sampling"). Inline: it runs once
// per light sample.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace aamap {

// Solid angle (sr) of the triangle with vertices a, b, c relative to the receiver (not unit):
// Van Oosterom and Strackee's tan(omega / 2) = |a.(b x c)| / (|a||b||c| + (a.b)|c| + (a.c)|b| +
// (b.c)|a|). Accurate for small triangles, where the angle-sum form below cancels.
inline float triangleSolidAngle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const float la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const float numerator = std::abs(glm::dot(a, glm::cross(b, c)));
    const float denominator = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    const float omega = 2.0f * std::atan2(numerator, denominator);
    return std::isfinite(omega) ? omega : 0.0f;
}

// A spherical triangle set up for sampling: what depends on the receiver and the triangle alone,
// computed once (square roots and no trigonometry) so that each sample costs one sincos, two
// square roots and a normalisation. Directions are uniform over the triangle (Arvo 1995,
// "Stratified sampling of spherical triangles"); the map is continuous in u, so a stratified
// pattern stays stratified.
class SphericalTriangle {
public:
    static constexpr float kMinArea = 1e-6f;  // sr
    // From the triangle's vertices relative to the receiver (not unit) and its solid angle
    // (triangleSolidAngle of the same vertices: the sampler and the pdf then share one area).
    // False for a degenerate one: below kMinArea, or vertices in one plane with the receiver.
    bool setup(const glm::vec3& va, const glm::vec3& vb, const glm::vec3& vc, float solidAngle) {
        area_ = solidAngle;
        if (!(area_ > kMinArea) || !std::isfinite(area_)) return false;
        a_ = glm::normalize(va);
        b_ = glm::normalize(vb);
        const glm::vec3 c = glm::normalize(vc);
        // The angle alpha at a, between the great circles a-b and a-c, from their planes'
        // normals: its cosine is their dot product, its sine the length of their cross product.
        glm::vec3 nAB = glm::cross(a_, b_), nAC = glm::cross(a_, c);
        const float lAB = glm::length(nAB), lAC = glm::length(nAC);
        if (!(lAB > 0.0f) || !(lAC > 0.0f)) return false;
        nAB *= 1.0f / lAB;
        nAC *= 1.0f / lAC;
        cosAlpha_ = std::clamp(glm::dot(nAB, nAC), -1.0f, 1.0f);
        sinAlpha_ = std::min(glm::length(glm::cross(nAB, nAC)), 1.0f);
        cosAB_ = glm::dot(a_, b_);
        // The unit tangent at a towards c: the arc a..c is cos(s) a + sin(s) towardC_.
        const glm::vec3 t = c - glm::dot(c, a_) * a_;
        const float lt = glm::length(t);
        if (!(lt > 0.0f) || !(sinAlpha_ > 0.0f)) return false;
        towardC_ = t * (1.0f / lt);
        return true;
    }
    bool setup(const glm::vec3& va, const glm::vec3& vb, const glm::vec3& vc) {
        return setup(va, vb, vc, triangleSolidAngle(va, vb, vc));
    }
    float area() const { return area_; }

    // A direction uniform over the triangle, unit up to rounding (callers that need it exactly
    // unit normalise it); u in [0,1)^2.
    glm::vec3 sample(glm::vec2 u) const {
        // The point c' on arc ac that cuts off the sub-triangle a b c' of area u.x * area.
        // s, t = sin, cos of (subArea - alpha), by the angle-difference identities.
        const float subArea = u.x * area_;
        const float sinSub = std::sin(subArea), cosSub = std::cos(subArea);
        const float s = sinSub * cosAlpha_ - cosSub * sinAlpha_, t = cosSub * cosAlpha_ + sinSub * sinAlpha_;
        const float p = t - cosAlpha_;
        const float q = s + sinAlpha_ * cosAB_;
        const float den = (q * s + p * t) * sinAlpha_;
        const float cosArc = std::clamp(den != 0.0f ? ((q * t - p * s) * cosAlpha_ - q) / den : 1.0f, -1.0f, 1.0f);
        const glm::vec3 cPrime = cosArc * a_ + std::sqrt(std::max(0.0f, 1.0f - cosArc * cosArc)) * towardC_;
        // Along the arc from b to c': the cosine of the distance from b, linear in u.y, gives
        // uniform area.
        const float cosB = glm::dot(cPrime, b_);
        const float z = std::clamp(1.0f - u.y * (1.0f - cosB), -1.0f, 1.0f);
        // b and the unit tangent t2 / |t2| are orthonormal: the result is unit without a
        // normalisation, and one square root scales the tangent.
        const glm::vec3 t2 = cPrime - cosB * b_;
        const float t2Squared = glm::dot(t2, t2);
        if (!(t2Squared > 0.0f)) return b_;  // c' at b: the sub-triangle has no width
        return z * b_ + std::sqrt(std::max(0.0f, 1.0f - z * z) / t2Squared) * t2;
    }

private:
    // Left uninitialised until setup(): a LightView holds several, most never used.
    glm::vec3 a_, b_, towardC_;
    float cosAlpha_, sinAlpha_, cosAB_, area_;
};

}  // namespace aamap
