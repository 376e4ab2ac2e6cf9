// Bilinear lookup with repeat inside one atlas entry (passes/gbuffer_textures.h): texel centres at
// (i + 0.5) / size and v = 0 on the entry's top row, the tracer's rule (tracer/embree_scene.cpp),
// so the Snapshot and the tracer agree on colours and on where alpha masks cut.
// Needs GL_EXT_samplerless_texture_functions.

// rect: x, y, width, height of the entry in the page; layer: its page.
vec4 atlasBilinear(texture2DArray atlas, vec2 uv, uvec4 rect, float layer) {
    const ivec2 size = ivec2(rect.zw);
    const vec2 p = uv * vec2(size) - 0.5;
    const vec2 f = floor(p);
    const vec2 a = p - f;
    // Wrap into [0, size) with a floored modulo (GLSL's % is undefined for negative operands).
    const vec2 fsize = vec2(size);
    const ivec2 lo = clamp(ivec2(f - fsize * floor(f / fsize)), ivec2(0), size - 1);
    const ivec2 next = lo + 1;
    const ivec2 hi = mix(next, ivec2(0), equal(next, size));
    const ivec2 origin = ivec2(rect.xy);
    const int l = int(layer);
    const vec4 t00 = texelFetch(atlas, ivec3(origin + ivec2(lo.x, lo.y), l), 0);
    const vec4 t10 = texelFetch(atlas, ivec3(origin + ivec2(hi.x, lo.y), l), 0);
    const vec4 t01 = texelFetch(atlas, ivec3(origin + ivec2(lo.x, hi.y), l), 0);
    const vec4 t11 = texelFetch(atlas, ivec3(origin + ivec2(hi.x, hi.y), l), 0);
    return mix(mix(t00, t10, a.x), mix(t01, t11, a.x), a.y);
}
