// Shadow-map visibility of a receiver, shared by the G-buffer's shading (gbuffer.glsl) and the
// geometric aamap's raster (geometry_buffer.glsl), so both see the same shadows. Include after
// shadow_cube.glsl; needs GL_EXT_samplerless_texture_functions.

// Fraction of the pcf x pcf texels around map position st (texels) of `layer` whose stored depth
// is not above `threshold`: lit. pcf is a specialisation constant at every call, so the other path
// is compiled out.
float litFraction(texture2DArray shadowCubes, vec2 st, int layer, int size, float threshold, int pcf) {
    if (pcf == 1) {
        const ivec2 t = clamp(ivec2(st), ivec2(0), ivec2(size - 1));
        return texelFetch(shadowCubes, ivec3(t, layer), 0).r > threshold ? 0.0 : 1.0;
    }
    const ivec2 lo = ivec2(floor(st - 0.5 * float(pcf - 1)));
    int lit = 0;
    for (int y = 0; y < pcf; ++y) {
        for (int x = 0; x < pcf; ++x) {
            const ivec2 t = clamp(lo + ivec2(x, y), ivec2(0), ivec2(size - 1));
            lit += texelFetch(shadowCubes, ivec3(t, layer), 0).r > threshold ? 0 : 1;
        }
    }
    return float(lit) / float(pcf * pcf);
}

// Fraction of the PCF kernel (pcf x pcf nearest texels of the light's cube face) that sees no
// occluder nearer than the receiver. `r` runs from the light to the surface. shadow: x cube-map
// near plane, y depth bias, z slope bias (texels), w the light's face size (GpuLight::position.w).
float shadowVisibility(texture2DArray shadowCubes, uint light, vec3 r, vec3 n, vec4 shadow, int pcf) {
    uint face;
    const vec3 f = cubeLookup(r, face);
    const float ma = f.z;
    const int size = int(shadow.w);
    // Slope-scaled bias in texels at the receiver: the stored distance runs along the face's
    // axis, so a receiver tilted by theta from that axis changes it across one texel (and across
    // the wider PCF footprint) by about texel * tan(theta).
    const float texel = 2.0 * ma / float(size);
    const float cosAxis = abs(n[face >> 1u]);
    const float tanTheta = min(sqrt(max(1.0 - cosAxis * cosAxis, 0.0)) / max(cosAxis, 1e-4), 10.0);
    const float bias = texel * (shadow.y + shadow.z * tanTheta * 0.5 * float(pcf + 1));
    // Stored near/m_occ > near/(ma - bias) <=> occluder nearer than ma - bias.
    const float threshold = shadow.x / max(ma - bias, shadow.x);
    const vec2 st = (f.xy / ma * 0.5 + 0.5) * float(size);
    const int layer = int(light * 6u + face);
    return litFraction(shadowCubes, st, layer, size, threshold, pcf);
}

// The same for directional light `light` (its orthographic map in layer 6 light) at world point p
// with unit normal n: the bias grows with the slope to the light's direction as above, in units
// of the map's texels (2 radius / size in world units).
float directionalShadowVisibility(texture2DArray shadowCubes, uint light, GpuLight l, vec3 p, vec3 n, vec4 shadow,
                                  int pcf) {
    const vec3 o = directionalMapCoords(p, l.normal.xyz, l.position.xyz, l.cone.x);
    const int size = int(shadow.w);
    const float cosAxis = abs(dot(n, l.normal.xyz));
    const float tanTheta = min(sqrt(max(1.0 - cosAxis * cosAxis, 0.0)) / max(cosAxis, 1e-4), 10.0);
    // One texel is 2R / size wide; depth runs over 2R: a texel of bias is 1 / size in depth.
    const float bias = (shadow.y + shadow.z * tanTheta * 0.5 * float(pcf + 1)) / float(size);
    const float threshold = o.z + bias;
    const vec2 st = (o.xy * 0.5 + 0.5) * float(size);
    const int layer = int(light * 6u);
    return litFraction(shadowCubes, st, layer, size, threshold, pcf);
}

// --- Soft shadows of area-light samples ------------------------------------------------------
// A sample that stands for a square patch of an area light (GpuLight::cone.w, its half side)
// casts the patch's penumbra, estimated as in percentage-closer soft shadows (Fernando 2005):
// a blocker search around the receiver's texel gives the mean occluder distance d_b, similar
// triangles give the penumbra's half width on the map, patch (d_r - d_b) / (d_r d_b) in units of
// the face's tangent plane, and a percentage-closer filter of that half width gives the lit
// fraction. The taps are a fixed pattern (no noise: every run and every pixel alike): 4 for the
// search, 2 x kSoftFilterCells^2 for the filter.
// Blockers are searched for as near to the light as a quarter of the receiver's distance.
// The filter grid's cells per box side plus one: 2 (a cell per box width, 2 x 2 taps per box)
// flagged fewer pixels on the Cornell box than 3 (3 x 3 taps, finer jaggies) and costs less.
const int kSoftFilterCells = 2;
const float kSoftSearchReach = 3.0;  // = (d_r - d_r / 4) / (d_r / 4)
const float kSoftMaxRadius = 0.125;  // the widest kernel's half width, in face widths

// The stored value (near / distance along the face axis) of the texel under map position st of
// `layer`, and whether it occludes: the occluder is nearer the light than the receiver's plane
// along that texel's ray, by more than `bias`. The plane rather than the receiver's own depth, so
// that a tilted receiver does not shadow itself across a wide kernel: linearised about the
// receiver (st0, distance ma) with slope (distance per texel): exact to first order.
bool tapOccluded(texture2DArray shadowCubes, vec2 st, vec2 st0, int layer, int size, float ma, vec2 slope,
                 float bias, float nearPlane, out float stored) {
    const ivec2 t = clamp(ivec2(floor(st)), ivec2(0), ivec2(size - 1));
    const float planeDepth = ma + dot(slope, vec2(t) + 0.5 - st0);
    stored = texelFetch(shadowCubes, ivec3(t, layer), 0).r;
    // stored > near / (planeDepth - bias), without the division; never where the plane is nearer
    // than the near plane (stored <= 1).
    return stored * (planeDepth - bias) > nearPlane;
}

// The lit fraction under a box of half width `radius` texels about st over the map point-sampled
// on a grid of kSoftFilterCells - 1 cells per box width: the box overlaps kSoftFilterCells^2
// cells, the inner ones wholly, the outer ones in part, each weighted by its overlap. As the
// receiver moves the weights change linearly and a cell enters or leaves at weight 0, so the lit
// fraction is continuous: a ramp, never a staircase.
float boxOfNearest(texture2DArray shadowCubes, vec2 st, int layer, int size, float ma, vec2 slope, float bias,
                   float nearPlane, float radius) {
    const float cellsPerBox = float(kSoftFilterCells - 1);
    const float spacing = 2.0 * radius / cellsPerBox;
    const vec2 from = (st - radius) / spacing;  // the box's low corner, in grid cells
    const vec2 firstCell = floor(from + 0.5);   // the cell (centre k spacing) that holds it
    const vec2 firstWeight = (firstCell + 0.5 - from) / cellsPerBox;
    const float innerWeight = 1.0 / cellsPerBox;
    float lit = 0.0;
    for (int j = 0; j < kSoftFilterCells; ++j) {
        const float wy = j == 0 ? firstWeight.y : (j < kSoftFilterCells - 1 ? innerWeight : innerWeight - firstWeight.y);
        for (int i = 0; i < kSoftFilterCells; ++i) {
            const float wx =
                i == 0 ? firstWeight.x : (i < kSoftFilterCells - 1 ? innerWeight : innerWeight - firstWeight.x);
            float stored;
            const vec2 tap = (firstCell + vec2(i, j)) * spacing;
            lit += tapOccluded(shadowCubes, tap, st, layer, size, ma, slope, bias, nearPlane, stored) ? 0.0 : wx * wy;
        }
    }
    return lit;
}

// The lit fraction of the patch (half side patchHalfSide) of area-light sample `light` seen
// from a receiver with unit normal n; r, shadow and pcf as shadowVisibility, whose footprint is
// the kernel's least half width, so that contact shadows stay as sharp as a point light's.
float softShadowVisibility(texture2DArray shadowCubes, uint light, vec3 r, vec3 n, vec4 shadow, float patchHalfSide,
                           int pcf) {
    uint face;
    const vec3 f = cubeLookup(r, face);
    const float ma = f.z;
    const int size = int(shadow.w);
    const float fsize = shadow.w;
    // n in the face's (sc, tc, ma) frame: cubeLookup's signed permutation applied to n.
    const vec3 s = mix(vec3(-1.0), vec3(1.0), greaterThanEqual(r, vec3(0.0)));
    const vec3 nl = face < 2u ? vec3(-s.x * n.z, -n.y, s.x * n.x)
                              : (face < 4u ? vec3(n.x, s.y * n.z, s.y * n.y) : vec3(s.z * n.x, -n.y, s.z * n.z));
    // The receiver's plane nl . x = nl . f meets the ray (u, v, 1) at distance (nl . f) / (nl . (u, v, 1));
    // its derivative at the receiver, per texel (2 / size in u and v), bounded as the bias's slope.
    const float texel = 2.0 * ma / fsize;
    const float facing = dot(nl, f) / ma;  // nl . (u0, v0, 1)
    const float cosAxis = abs(nl.z);
    const float tanTheta = min(sqrt(max(1.0 - cosAxis * cosAxis, 0.0)) / max(cosAxis, 1e-4), 10.0);
    const float maxSlope = 10.0 * texel;
    const vec2 slope = clamp(-nl.xy * texel / (abs(facing) > 1e-6 ? facing : 1e-6), vec2(-maxSlope), vec2(maxSlope));
    // Each tap tests the plane at its texel's centre: the bias covers depth quantisation and
    // curvature within one texel only.
    const float bias = texel * (shadow.y + shadow.z * tanTheta);
    const vec2 st = (f.xy / ma * 0.5 + 0.5) * fsize;
    const int layer = int(light * 6u + face);
    const float texelsPerTangent = 0.5 * fsize;
    const float minRadius = 0.5 * float(pcf);
    const float maxRadius = max(kSoftMaxRadius * fsize, minRadius);
    const float searchRadius = clamp(kSoftSearchReach * patchHalfSide / ma * texelsPerTangent, minRadius, maxRadius);
    // The search: the map point-sampled every searchRadius texels, bilinearly weighted (a tent of
    // that half width), so that the blockers' share and mean distance change continuously across
    // receivers at one distance (where the distance changes, the grid's points move with it).
    const float searchSpacing = searchRadius;
    const vec2 searchCell = floor(st / searchSpacing);
    const vec2 searchFraction = st / searchSpacing - searchCell;
    float blockerWeight = 0.0, blockerSum = 0.0;  // of the stored near / distance, weighted
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            const vec2 w2 = mix(1.0 - searchFraction, searchFraction, vec2(i, j));
            float stored;
            const vec2 tap = (searchCell + vec2(i, j)) * searchSpacing;
            if (tapOccluded(shadowCubes, tap, st, layer, size, ma, slope, bias, shadow.x, stored)) {
                blockerWeight += w2.x * w2.y;
                blockerSum += w2.x * w2.y * stored;
            }
        }
    }
    // The blockers' distance (weighted harmonic mean) sets the kernel; where they thin out, the
    // kernel shrinks continuously to the least one, the point light's lookup.
    const float blockerDepth = blockerSum > 0.0 ? clamp(shadow.x * blockerWeight / blockerSum, shadow.x, ma) : ma;
    const float penumbra = patchHalfSide * (ma - blockerDepth) / (ma * blockerDepth);
    const float filterRadius =
        mix(minRadius, clamp(penumbra * texelsPerTangent, minRadius, searchRadius), min(4.0 * blockerWeight, 1.0));
    // Kernel widths between powers of two blend the two boxes around them: a grid whose spacing
    // followed the width continuously would move its points across texels.
    const float level = floor(log2(filterRadius));
    const float narrow = exp2(level);
    return mix(boxOfNearest(shadowCubes, st, layer, size, ma, slope, bias, shadow.x, narrow),
               boxOfNearest(shadowCubes, st, layer, size, ma, slope, bias, shadow.x, 2.0 * narrow),
               filterRadius / narrow - 1.0);
}
