// The geometric aamap's edge image, included by geometric_edges.comp and its .combined variant:
// the rule of geometric_edges.h on the geometry raster's two images. GEOMETRIC_COMBINED: max
// with the luminance |L|.
#extension GL_GOOGLE_include_directive : require
#include "aamap_filter.h"
#include "geometric_edges.h"
#include "snapshot_interface.h"

layout(local_size_x = AAMAP_FILTER_GROUP_X, local_size_y = AAMAP_FILTER_GROUP_Y) in;
layout(push_constant) uniform Push { FilterPush pc; };

layout(binding = GEOMETRIC_BINDING_NORMAL_DEPTH, rgba32f) uniform readonly image2D normalDepth;
layout(binding = GEOMETRIC_BINDING_IDS, rgba32f) uniform readonly image2D ids;
layout(binding = GEOMETRIC_BINDING_OUTPUT, r32f) uniform writeonly image2D edges;
#ifdef GEOMETRIC_COMBINED
layout(binding = GEOMETRIC_BINDING_LAPLACIAN, r32f) uniform readonly image2D laplacian;
#endif

bool covered(vec4 nd) { return nd.w > 0.0; }

bool depthJump(vec4 a, vec4 p, vec4 b) {
    if (!covered(a) || !covered(b)) return false;
    precise float wp = 1.0 / p.w;
    precise float second = (1.0 / a.w + 1.0 / b.w) - 2.0 * wp;
    return abs(second) > float(GEOMETRIC_DEPTH_TOLERANCE) * wp;
}

bool differs(vec4 np, vec4 ip, ivec2 q) {
    const vec4 nq = imageLoad(normalDepth, q);
    if (covered(np) != covered(nq)) return true;
    if (!covered(np)) return false;
    const vec4 iq = imageLoad(ids, q);
    if (any(notEqual(ip, iq))) return true;  // object, material, occlusion mask
    precise float d = np.x * nq.x + np.y * nq.y + np.z * nq.z;
    return d < float(GEOMETRIC_CREASE_COS);
}

void main() {
    const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    const ivec2 size = pc.inSize;
    if (any(greaterThanEqual(p, size))) return;
    const vec4 np = imageLoad(normalDepth, p);
    const vec4 ip = imageLoad(ids, p);
    const ivec2 l = ivec2(max(p.x - 1, 0), p.y), r = ivec2(min(p.x + 1, size.x - 1), p.y);
    const ivec2 u = ivec2(p.x, max(p.y - 1, 0)), d = ivec2(p.x, min(p.y + 1, size.y - 1));
    bool edge = differs(np, ip, l) || differs(np, ip, r) || differs(np, ip, u) || differs(np, ip, d);
    if (!edge && covered(np))
        edge = depthJump(imageLoad(normalDepth, l), np, imageLoad(normalDepth, r)) ||
               depthJump(imageLoad(normalDepth, u), np, imageLoad(normalDepth, d));
    float e = edge ? float(GEOMETRIC_EDGE_VALUE) : 0.0;
#ifdef GEOMETRIC_COMBINED
    e = max(e, imageLoad(laplacian, p).r);
#endif
    imageStore(edges, p, vec4(e));
}
