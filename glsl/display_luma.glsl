// Step 1 of aamap_filter.h, shared by the luminance pass (luminance.comp) and the G-buffer's
// fused variant (gbuffer.glsl, GBUFFER_GREY): g = dot(LUMA, srgbEncode(clamp(exposure * rgb, 0, 1))),
// bit for bit the same in both (`precise` keeps the arithmetic unfused). Include after
// aamap_filter.h.

// c^(1/2.4) to about an ulp: GPU pow (exp2(log2)) is a few ulps off, and the Laplacian
// multiplies that by up to 48. One Newton step on y^12 = c^5 (1/2.4 = 5/12) fixes it.
float powFiveTwelfths(float c) {
    const float y = pow(c, 5.0 / 12.0);
    const float y2 = y * y, y4 = y2 * y2, y12 = y4 * y4 * y4;
    const float c2 = c * c, c5 = c2 * c2 * c;
    precise float refined = y - y * (1.0 - c5 / y12) * (1.0 / 12.0);
    return refined;
}

// Same curve and constants as the CPU reference.
float srgbEncode(float c) {
    precise float r = c <= 0.0031308 ? 12.92 * c : 1.055 * powFiveTwelfths(c) - 0.055;
    return r;
}

float displayLuma(vec3 rgb, float exposure) {
    const float r = srgbEncode(clamp(exposure * rgb.r, 0.0, 1.0));
    const float g = srgbEncode(clamp(exposure * rgb.g, 0.0, 1.0));
    const float b = srgbEncode(clamp(exposure * rgb.b, 0.0, 1.0));
    precise float y = float(AAMAP_LUMA_R) * r + float(AAMAP_LUMA_G) * g + float(AAMAP_LUMA_B) * b;
    return y;
}
