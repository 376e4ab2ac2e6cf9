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
// near plane, y depth bias, z slope bias (texels), w face size (GBufferPush::shadow).
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
