// Lookups inside one atlas entry (passes/gbuffer_textures.h): bilinear with repeat, texel centres
// at (i + 0.5) / size and v = 0 on the entry's top row, the tracer's rule (tracer/embree_scene.cpp),
// so the Snapshot and the tracer agree on colours and on where alpha masks cut. Coverage is the
// level-0 lookup (atlasBilinear); colour is filtered over the pixel's footprint through the entry's
// mip chain (atlasFiltered), the rule of filteredLookup in scene/texture_filter.cpp.
// Needs GL_EXT_samplerless_texture_functions and snapshot_interface.h.

// Bilinear in one rectangle (origin, size) of page `layer`.
vec4 atlasBilinearIn(texture2DArray atlas, vec2 uv, ivec2 origin, ivec2 size, int layer) {
    const vec2 p = uv * vec2(size) - 0.5;
    const vec2 f = floor(p);
    const vec2 a = p - f;
    // Wrap into [0, size) with a floored modulo (GLSL's % is undefined for negative operands).
    const vec2 fsize = vec2(size);
    const ivec2 lo = clamp(ivec2(f - fsize * floor(f / fsize)), ivec2(0), size - 1);
    const ivec2 next = lo + 1;
    const ivec2 hi = mix(next, ivec2(0), equal(next, size));
    const vec4 t00 = texelFetch(atlas, ivec3(origin + ivec2(lo.x, lo.y), layer), 0);
    const vec4 t10 = texelFetch(atlas, ivec3(origin + ivec2(hi.x, lo.y), layer), 0);
    const vec4 t01 = texelFetch(atlas, ivec3(origin + ivec2(lo.x, hi.y), layer), 0);
    const vec4 t11 = texelFetch(atlas, ivec3(origin + ivec2(hi.x, hi.y), layer), 0);
    return mix(mix(t00, t10, a.x), mix(t01, t11, a.x), a.y);
}

// rect: x, y, width, height of the entry (level 0) in the page; layer: its page.
vec4 atlasBilinear(texture2DArray atlas, vec2 uv, uvec4 rect, float layer) {
    return atlasBilinearIn(atlas, uv, ivec2(rect.xy), ivec2(rect.zw), int(layer));
}

// Level `level`'s rectangle: level 1 just below level 0, each next level right of the previous
// (atlasLevel in passes/gbuffer_textures.cpp).
void atlasLevel(uvec4 rect, int level, out ivec2 origin, out ivec2 size) {
    origin = ivec2(rect.xy);
    size = ivec2(rect.zw);
    if (level == 0) return;
    origin.y += size.y;
    size = max(size / 2, ivec2(1));
    for (int l = 1; l < level; ++l) {
        origin.x += size.x;
        size = max(size / 2, ivec2(1));
    }
}

// The colour at uv for a footprint with full-width axes duvA, duvB in uv units (a pixel's:
// dFdx(uv), dFdy(uv)): up to TEXTURE_MAX_ANISOTROPY trilinear probes along the major axis, as
// footprintProbes and filteredLookup (scene/texture_filter.cpp).
vec3 atlasFiltered(texture2DArray atlas, vec2 uv, vec2 duvA, vec2 duvB, uvec4 rect, float layer) {
    const vec2 fsize = vec2(rect.zw);
    const int levels = findMSB(int(max(rect.z, rect.w))) + 1;
    const float maxLevel = float(max(levels - 1, 0));
    const vec2 axisA = duvA * fsize, axisB = duvB * fsize;
    const float la = length(axisA), lb = length(axisB);
    int count = 1;
    vec2 step = vec2(0.0);
    float level = 0.0;
    if (isinf(la) || isnan(la) || isinf(lb) || isnan(lb)) {
        level = maxLevel;  // an unbounded footprint: the average
    } else {
        const vec2 major = la >= lb ? axisA : axisB;
        const float majorLength = max(la, lb), minorLength = min(la, lb);
        count = int(clamp(ceil(majorLength / max(minorLength, 1.0)), 1.0, float(TEXTURE_MAX_ANISOTROPY)));
        step = major / float(count);
        const float width = max(minorLength, majorLength / float(count));
        level = width > 1.0 ? min(log2(width), maxLevel) : 0.0;
    }
    const int l0 = int(level);
    const float f = level - float(l0);
    const bool blendLevels = f > 0.0 && l0 + 1 < levels;
    ivec2 origin0, size0, origin1, size1;
    atlasLevel(rect, l0, origin0, size0);
    atlasLevel(rect, min(l0 + 1, levels - 1), origin1, size1);
    const int page = int(layer);
    vec3 sum = vec3(0.0);
    for (int i = 0; i < count; ++i) {
        const float offset = float(i) - 0.5 * float(count - 1);
        const vec2 at = uv + offset * step / fsize;
        vec3 c = atlasBilinearIn(atlas, at, origin0, size0, page).rgb;
        if (blendLevels) c = (1.0 - f) * c + f * atlasBilinearIn(atlas, at, origin1, size1, page).rgb;
        sum += c;
    }
    return sum / float(count);
}
