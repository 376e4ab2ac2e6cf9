#include "scene/mitsuba_transform.h"

#include <cmath>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

namespace aamap::mitsuba {
namespace {

// x/y/z attributes (each defaulting to `fallback`) or value="x, y, z" (one number: all three).
glm::dvec3 vectorOf(const Element& e, double fallback) {
    if (e.has("value")) {
        const std::vector<double> v = parseNumbers(e, e.attribute("value"));
        if (v.size() == 1) return glm::dvec3(v[0]);
        if (v.size() != 3) fail(e, fmt::format("<{}> value '{}' should be one or three numbers", e.tag, e.attribute("value")));
        return {v[0], v[1], v[2]};
    }
    glm::dvec3 out(fallback);
    const char* axes[] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        if (!e.has(axes[i])) continue;
        const std::vector<double> v = parseNumbers(e, e.attribute(axes[i]));
        if (v.size() != 1) fail(e, fmt::format("<{}> {}='{}' should be one number", e.tag, axes[i], e.attribute(axes[i])));
        out[i] = v[0];
    }
    return out;
}

glm::dvec3 pointAttribute(const Element& e, const char* key, bool required, glm::dvec3 fallback) {
    if (!e.has(key)) {
        if (required) fail(e, fmt::format("<{}> needs a '{}' attribute", e.tag, key));
        return fallback;
    }
    const std::vector<double> v = parseNumbers(e, e.attribute(key));
    if (v.size() != 3) fail(e, fmt::format("<{}> {}='{}' should be three numbers", e.tag, key, e.attribute(key)));
    return {v[0], v[1], v[2]};
}

glm::dmat4 lookAt(const Element& e) {
    const glm::dvec3 origin = pointAttribute(e, "origin", true, {});
    const glm::dvec3 target = pointAttribute(e, "target", true, {});
    const glm::dvec3 up = pointAttribute(e, "up", false, {0, 1, 0});
    const glm::dvec3 dir = target - origin;
    if (!(glm::length(dir) > 0.0)) fail(e, "<lookat> origin and target are the same point");
    const glm::dvec3 d = glm::normalize(dir);
    const glm::dvec3 left = glm::cross(up, d);
    if (!(glm::length(left) > 1e-9 * glm::length(up))) fail(e, "<lookat> up is parallel to the view direction");
    const glm::dvec3 l = glm::normalize(left);
    const glm::dvec3 u = glm::cross(d, l);
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(l, 0.0);
    m[1] = glm::dvec4(u, 0.0);
    m[2] = glm::dvec4(d, 0.0);
    m[3] = glm::dvec4(origin, 1.0);
    return m;
}

glm::dmat4 step(const Element& e) {
    if (e.tag == "translate") return glm::translate(glm::dmat4(1.0), vectorOf(e, 0.0));
    if (e.tag == "scale") return glm::scale(glm::dmat4(1.0), vectorOf(e, 1.0));
    if (e.tag == "rotate") {
        const glm::dvec3 axis = vectorOf(e, 0.0);
        const std::vector<double> angle = parseNumbers(e, e.attribute("angle"));
        if (angle.size() != 1) fail(e, "<rotate> needs one angle (degrees)");
        if (!(glm::length(axis) > 0.0)) fail(e, "<rotate> has a zero axis");
        return glm::rotate(glm::dmat4(1.0), glm::radians(angle[0]), glm::normalize(axis));
    }
    if (e.tag == "matrix") {
        const std::vector<double> v = parseNumbers(e, e.attribute("value"));
        glm::dmat4 m(1.0);
        const int n = v.size() == 16 ? 4 : v.size() == 9 ? 3 : 0;
        if (n == 0) fail(e, fmt::format("<matrix> has {} numbers (expected 16, or 9)", v.size()));
        for (int row = 0; row < n; ++row)
            for (int col = 0; col < n; ++col) m[col][row] = v[row * n + col];  // written row by row
        return m;
    }
    if (e.tag == "lookat") return lookAt(e);
    fail(e, fmt::format("<{}> is not a transform step (translate, rotate, scale, matrix, lookat)", e.tag));
}

}  // namespace

glm::mat4 readTransform(const Element& transform) {
    glm::dmat4 m(1.0);
    for (const Element& c : transform.children) m = step(c) * m;
    const double det = glm::determinant(glm::dmat3(m));
    if (!std::isfinite(det) || std::abs(det) < 1e-30) fail(transform, "the transform is singular");
    return glm::mat4(m);
}

glm::mat4 transformProperty(const Element& parent, const char* name) {
    const Element* t = parent.property(name);
    if (t == nullptr) return glm::mat4(1.0f);
    if (t->tag != "transform") fail(*t, fmt::format("property '{}' should be a <transform>", name));
    return readTransform(*t);
}

}  // namespace aamap::mitsuba
