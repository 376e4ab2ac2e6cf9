// Cube-face geometry shared by the shadow raster (shadow_cube.vert) and its receiver
// (gbuffer.glsl): the face order and (sc, tc, ma) of the Vulkan spec's cube-map table, so a
// samplerCube would read these layers the same way.

// (sc, tc, ma) of direction r on face f (0..5 = +X -X +Y -Y +Z -Z); ma > 0 in front of the face.
vec3 cubeFaceCoords(vec3 r, uint f) {
    switch (f) {
        case 0u: return vec3(-r.z, -r.y, r.x);
        case 1u: return vec3(r.z, -r.y, -r.x);
        case 2u: return vec3(r.x, r.z, r.y);
        case 3u: return vec3(r.x, -r.z, -r.y);
        case 4u: return vec3(r.x, -r.y, r.z);
        default: return vec3(-r.x, -r.y, -r.z);
    }
}

// The face whose axis is r's major axis.
uint cubeFace(vec3 r) {
    const vec3 a = abs(r);
    if (a.x >= a.y && a.x >= a.z) return r.x >= 0.0 ? 0u : 1u;
    if (a.y >= a.z) return r.y >= 0.0 ? 2u : 3u;
    return r.z >= 0.0 ? 4u : 5u;
}

// cubeFace and cubeFaceCoords together, with selects instead of branches: the receiver's faces
// vary per pixel, and a divergent switch runs every case on SIMD CPUs (lavapipe).
vec3 cubeLookup(vec3 r, out uint face) {
    const vec3 a = abs(r);
    const vec3 s = mix(vec3(-1.0), vec3(1.0), greaterThanEqual(r, vec3(0.0)));
    const bool xMajor = a.x >= a.y && a.x >= a.z;
    const bool yMajor = !xMajor && a.y >= a.z;
    face = xMajor ? (s.x > 0.0 ? 0u : 1u) : (yMajor ? (s.y > 0.0 ? 2u : 3u) : (s.z > 0.0 ? 4u : 5u));
    const vec3 fx = vec3(-s.x * r.z, -r.y, a.x);
    const vec3 fy = vec3(r.x, s.y * r.z, a.y);
    const vec3 fz = vec3(s.z * r.x, -r.y, a.z);
    return xMajor ? fx : (yMajor ? fy : fz);
}

// The orthographic shadow map of a directional light (GpuLight: toLight in normal, the covered
// sphere's centre in position and radius in cone.x): x, y in [-1, 1] across the map and z the
// reversed depth 1 - (R - dot(p - c, toLight)) / (2R), larger nearer the light as near/ma is for
// the cube faces. The basis is Duff et al. 2017's, a pure function of the direction, so the
// raster and every receiver agree.
vec3 directionalMapCoords(vec3 p, vec3 toLight, vec3 centre, float radius) {
    const float s = toLight.z >= 0.0 ? 1.0 : -1.0;
    const float a = -1.0 / (s + toLight.z);
    const float c = toLight.x * toLight.y * a;
    const vec3 t = vec3(1.0 + s * toLight.x * toLight.x * a, s * c, -s * toLight.x);
    const vec3 b = vec3(c, s + toLight.y * toLight.y * a, -toLight.y);
    const vec3 q = p - centre;
    return vec3(dot(q, t) / radius, dot(q, b) / radius, 1.0 - (radius - dot(q, toLight)) / (2.0 * radius));
}
