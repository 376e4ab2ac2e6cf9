// The tracer's microfacet lobes (tracer/microfacet.h, tracer/bsdf.h evalLobes) for the Snapshot's
// light samples: Beckmann or GGX D (anisotropic), Smith's separable G, the exact Fresnel term of a
// conductor's complex index or of a plastic's dielectric coating. In the local frame of the
// shading normal, built as the tracer builds it (Duff et al. 2017), so alpha_u follows the same
// tangent. Beckmann's G1 is Mitsuba's rational fit (within 0.35 % of the tracer's exact erf form).

struct MicrofacetFrame {
    vec3 t, b, n;
};

MicrofacetFrame microfacetFrame(vec3 n) {
    const float s = n.z >= 0.0 ? 1.0 : -1.0;
    const float a = -1.0 / (s + n.z);
    const float c = n.x * n.y * a;
    MicrofacetFrame f;
    f.t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    f.b = vec3(c, s + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

vec3 toLocal(MicrofacetFrame f, vec3 v) { return vec3(dot(v, f.t), dot(v, f.b), dot(v, f.n)); }

// D(m), normalised over projected area; lobe.y, lobe.z: alpha_u, alpha_v; lobe.w: 1 for GGX.
float microfacetD(vec3 m, vec4 lobe) {
    if (m.z <= 0.0) return 0.0;
    const float cos2 = m.z * m.z;
    const float x = m.x / lobe.y, y = m.y / lobe.z;
    float d;
    if (lobe.w > 0.5) {
        const float s = x * x + y * y + cos2;
        d = 1.0 / (3.14159265 * lobe.y * lobe.z * s * s);
    } else {
        d = exp(-(x * x + y * y) / cos2) / (3.14159265 * lobe.y * lobe.z * cos2 * cos2);
    }
    return d * m.z > 1e-20 ? d : 0.0;
}

// Smith's masking of direction v by normals m.
float microfacetG1(vec3 v, vec3 m, vec4 lobe) {
    if (dot(v, m) * v.z <= 0.0) return 0.0;
    const float xy2 = lobe.y * lobe.y * v.x * v.x + lobe.z * lobe.z * v.y * v.y;
    if (xy2 <= 0.0) return 1.0;
    const float tan2 = xy2 / (v.z * v.z);
    if (lobe.w > 0.5) return 2.0 / (1.0 + sqrt(1.0 + tan2));
    const float a = inversesqrt(tan2);
    if (a >= 1.6) return 1.0;
    return (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}

// Unpolarised Fresnel reflectance of the complex index eta + i k at cosine c (exact; the closed
// form of the complex expression the tracer evaluates).
float fresnelConductor(float c, float eta, float k) {
    c = clamp(c, 0.0, 1.0);
    const float c2 = c * c, s2 = 1.0 - c2;
    const float t0 = eta * eta - k * k - s2;
    const float a2b2 = sqrt(max(t0 * t0 + 4.0 * eta * eta * k * k, 0.0));
    const float a = sqrt(max(0.5 * (a2b2 + t0), 0.0));
    const float t1 = a2b2 + c2, t2 = 2.0 * c * a;
    const float rs = (t1 - t2) / max(t1 + t2, 1e-20);
    const float t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
    const float rp = rs * (t3 - t4) / max(t3 + t4, 1e-20);
    return 0.5 * (rs + rp);
}

// Dielectric Fresnel reflectance from outside (relative index eta) at cosine c > 0.
float fresnelDielectric(float c, float eta) {
    c = clamp(c, 0.0, 1.0);
    const float sin2T = (1.0 - c * c) / (eta * eta);
    if (sin2T >= 1.0) return 1.0;
    const float ct = sqrt(1.0 - sin2T);
    const float rs = (c - eta * ct) / (c + eta * ct);
    const float rp = (eta * c - ct) / (eta * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

// The BRDF of the lobe for view lo and light li (local, both z > 0): tint F D G / (4 cos_o cos_i),
// plus a plastic's base: baseKd / pi times the coating's transmittance 1 - F at both ends (baseKd
// already holds 1 / (1 - R_int) / ior^2).
vec3 microfacetLobe(vec3 lo, vec3 li, vec4 lobe, vec4 eta, vec4 k, vec3 tint, vec3 baseKd) {
    const vec3 h = normalize(lo + li);
    const float D = microfacetD(h, lobe);
    const float G = microfacetG1(lo, h, lobe) * microfacetG1(li, h, lobe);
    const float cosH = dot(lo, h);
    const bool plastic = lobe.x == float(GBUFFER_LOBE_PLASTIC);
    const vec3 F = plastic ? vec3(fresnelDielectric(cosH, eta.w))
                           : vec3(fresnelConductor(cosH, eta.x, k.x), fresnelConductor(cosH, eta.y, k.y),
                                  fresnelConductor(cosH, eta.z, k.z));
    vec3 f = tint * F * (D * G / (4.0 * lo.z * li.z));
    if (plastic)
        f += baseKd * (0.31830988618 * (1.0 - fresnelDielectric(lo.z, eta.w)) * (1.0 - fresnelDielectric(li.z, eta.w)));
    return f;
}
