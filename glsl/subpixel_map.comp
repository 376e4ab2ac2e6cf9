#version 460
// The sub-pixel aamap: each render pixel's predicted one-ray display error from its k x k
// samples and the ring of samples just outside it (or, with shared shading, from its shade and its
// neighbours'), as a map value (glsl/shared/subpixel_map.h has the rule; passes/cpu_subpixel.cpp
// is its CPU reference). Step 3's geometry tests come from subpixel_geometry.comp's flags.
#extension GL_GOOGLE_include_directive : require
#include "aamap_filter.h"
#include "subpixel_map.h"
#include "snapshot_interface.h"
#include "display_luma.glsl"

layout(local_size_x = SUBPIXEL_GROUP_X, local_size_y = SUBPIXEL_GROUP_Y) in;
layout(push_constant) uniform Push { SubpixelPush pc; };
// k is fixed per pipeline so that the sample loops unroll to exactly k x k (lavapipe runs a loop
// bounded by a push constant, or masked lanes of a longer one, much slower).
layout(constant_id = SUBPIXEL_SPEC_K) const int K = SUBPIXEL_DEFAULT_K;
// Shared shading: one shade per render pixel (colour W x H), rule 2' of subpixel_map.h.
layout(constant_id = SUBPIXEL_SPEC_SHARED) const uint kShared = 0u;

layout(binding = SUBPIXEL_BINDING_COLOUR, rgba32f) uniform readonly image2D colour;
layout(binding = SUBPIXEL_BINDING_GEOMETRY, r32f) uniform readonly image2D geometryFlags;
layout(binding = SUBPIXEL_BINDING_OUTPUT, r32f) uniform writeonly image2D aamap;

// core displayEncode: exposure, non-finite -> 0, clamp, sRGB.
float display(float linear) {
    precise float v = pc.exposure * linear;
    if (isnan(v) || isinf(v)) return 0.0;
    return srgbEncode(clamp(v, 0.0, 1.0));
}
vec3 display(vec3 rgb) { return vec3(display(rgb.r), display(rgb.g), display(rgb.b)); }
float maxOf(vec3 v) { return max(v.r, max(v.g, v.b)); }

// A pixel's geometry flags (SUBPIXEL_FLAG_*); 0 outside the image.
uint flagsAt(ivec2 q) {
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, pc.outSize))) return 0u;
    return uint(imageLoad(geometryFlags, q).r);
}

// Rule 2' (shared shading): E from the shades of p and its 4-neighbours, and step 3.
float sharedError(ivec2 p) {
    const ivec2 steps[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(-1, 0), ivec2(0, -1));
    const vec3 dp = display(imageLoad(colour, p).rgb);
    const uint fp = flagsAt(p);
    const bool ownP = (fp & SUBPIXEL_FLAG_OWN) != 0u;
    uint fq[4];  // the neighbours' flags, each loaded once
    for (int n = 0; n < 4; ++n) fq[n] = flagsAt(p + steps[n]);
    // border(p, q) for q = right, down, left, up: the right and down flags of p, of left and up.
    const bool border[4] = bool[4]((fp & SUBPIXEL_FLAG_RIGHT) != 0u, (fp & SUBPIXEL_FLAG_DOWN) != 0u,
                                   (fq[2] & SUBPIXEL_FLAG_RIGHT) != 0u, (fq[3] & SUBPIXEL_FLAG_DOWN) != 0u);
    bool geometry = ownP;
    vec3 diff[4];  // d(q) - d(p) where p owns the step, else 0
    for (int n = 0; n < 4; ++n) {
        const ivec2 q = p + steps[n];
        diff[n] = vec3(0.0);
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, pc.outSize))) continue;
        geometry = geometry || border[n];
        if (!ownP && !border[n] && (fq[n] & SUBPIXEL_FLAG_OWN) != 0u) continue;  // q's edge, q's step
        diff[n] = display(imageLoad(colour, q).rgb) - dp;
    }
    float error = 0.0;
    for (int axis = 0; axis < 2; ++axis) {
        const vec3 a = diff[axis], b = -diff[axis + 2];  // d(p+) - d(p), d(p) - d(p-)
        for (int c = 0; c < 3; ++c) {
            precise float e = 0.5 * abs(a[c] - b[c]);
            if (a[c] * b[c] > 0.0) e += 0.25 * min(abs(a[c]), abs(b[c]));
            error = max(error, e);
        }
    }
    if (geometry) error = max(error, float(SUBPIXEL_GEOMETRY_ERROR) * pc.tolerance);
    return error;
}

// Steps 1-3 with a shade per sample.
float sampleError(ivec2 p) {
    const int k = K;
    const ivec2 base = k * p;
    const ivec2 size = k * pc.outSize;
    precise vec3 sum = vec3(0.0);
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) sum += imageLoad(colour, base + ivec2(i, j)).rgb;
    const vec3 mean = display(sum / float(k * k));

    float own = 0.0;  // sum of the samples' deviations, row-major
    float error = 0.0;
    const ivec2 steps[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(-1, 0), ivec2(0, -1));
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
            const ivec2 s = base + ivec2(i, j);
            const vec3 ds = display(imageLoad(colour, s).rgb);
            own += maxOf(abs(ds - mean));
            for (int n = 0; n < 4; ++n) {
                const ivec2 o = ivec2(i, j) + steps[n];
                const bool inside = all(greaterThanEqual(o, ivec2(0))) && all(lessThan(o, ivec2(k)));
                if (inside) continue;
                const ivec2 r = base + o;
                if (any(lessThan(r, ivec2(0))) || any(greaterThanEqual(r, size))) continue;
                error = max(error, 0.5 * maxOf(abs(display(imageLoad(colour, r).rgb) - ds)));
            }
        }
    error = max(error, own / float(k * k));
    // Step 3: an inside pair, or a boundary pair with any of the four neighbours.
    const uint fp = flagsAt(p);
    const bool geometry = fp != 0u || (flagsAt(p - ivec2(1, 0)) & SUBPIXEL_FLAG_RIGHT) != 0u ||
                          (flagsAt(p - ivec2(0, 1)) & SUBPIXEL_FLAG_DOWN) != 0u;
    if (geometry) error = max(error, float(SUBPIXEL_GEOMETRY_ERROR) * pc.tolerance);
    return error;
}

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, pc.outSize))) return;
    const float error = kShared != 0u ? sharedError(p) : sampleError(p);
    const float tau = pc.tolerance;
    precise float a = error > tau ? 1.0 - tau / error : 0.0;
    imageStore(aamap, p, vec4(a));
}
