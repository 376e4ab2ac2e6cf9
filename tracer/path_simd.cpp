// Path mode's common vertex across a packet's lanes (tracer/path_simd.h). Compiled once per
// Highway target (foreach_target re-includes this file); shade() dispatches to the best one the
// CPU has. Plain multiplies and adds only (no MulAdd, and -ffp-contract=off in CMake): a lane's
// arithmetic then rounds as the scalar code's does.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tracer/path_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include "tracer/bsdf.h"
#include "tracer/path_simd.h"
#include "tracer/sampler.h"

#include <cstddef>
#include <numbers>

#ifndef AAMAP_PATH_SIMD_ONCE
#define AAMAP_PATH_SIMD_ONCE
namespace aamap::pathsimd {
// The salts of one step's draws: Sampler::dimSalt of each slot's dimension(s).
struct Salts {
    std::uint64_t lobe, light0, light1, bsdf0, bsdf1, roulette, env0, env1;
};
constexpr float kOneMinusUlp = 0x1.fffffep-1f;  // Sampler::kOneMinusUlp
}  // namespace aamap::pathsimd
#endif

HWY_BEFORE_NAMESPACE();
namespace aamap::pathsimd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The low 64 bits of a * b per lane, from three 32 x 32 -> 64 multiplies: Highway 1.0 has no
// 64-bit lane multiply (nor has AVX2).
template <class DU64, class V = hn::Vec<DU64>>
HWY_INLINE V Mul64(DU64 du64, V a, std::uint64_t b) {
    const hn::Repartition<std::uint32_t, DU64> du32;
    const auto bLow = hn::BitCast(du32, hn::Set(du64, b));  // even lanes: b's low half
    const auto bHigh = hn::BitCast(du32, hn::Set(du64, b >> 32));
    const auto a32 = hn::BitCast(du32, a);
    const V low = hn::MulEven(a32, bLow);
    const V cross = hn::Add(hn::MulEven(hn::BitCast(du32, hn::ShiftRight<32>(a)), bLow), hn::MulEven(a32, bHigh));
    return hn::Add(low, hn::ShiftLeft<32>(cross));
}

// mix64 (tracer/sampler.h), lane-wise.
template <class DU64, class V = hn::Vec<DU64>>
HWY_INLINE V Mix64(DU64 du64, V x) {
    x = hn::Xor(x, hn::ShiftRight<30>(x));
    x = Mul64(du64, x, 0xbf58476d1ce4e5b9ULL);
    x = hn::Xor(x, hn::ShiftRight<27>(x));
    x = Mul64(du64, x, 0x94d049bb133111ebULL);
    return hn::Xor(x, hn::ShiftRight<31>(x));
}

// Sampler::get1D for the lanes of one float vector: keys[0, Lanes(df)) hashed with `salt`.
template <class DF>
HWY_INLINE hn::Vec<DF> Draw(DF df, const std::uint64_t* keys, std::uint64_t salt) {
#if HWY_TARGET == HWY_SCALAR
    // One lane: no 32-bit halves to pair up.
    return hn::Set(df, static_cast<float>(mix64(keys[0] ^ salt) >> 40) * 0x1p-24f);
#else
    const hn::RebindToUnsigned<DF> du32;
    const hn::RebindToSigned<DF> di32;
    const hn::Repartition<std::uint64_t, decltype(du32)> du64;
    const std::size_t half = hn::Lanes(du64);
    const auto s = hn::Set(du64, salt);
    const auto low = hn::ShiftRight<40>(Mix64(du64, hn::Xor(hn::LoadU(du64, keys), s)));
    const auto high = hn::ShiftRight<40>(Mix64(du64, hn::Xor(hn::LoadU(du64, keys + half), s)));
    // 24-bit values: their low 32-bit halves, in lane order, convert exactly.
    const auto bits = hn::ConcatEven(du32, hn::BitCast(du32, high), hn::BitCast(du32, low));
    return hn::Mul(hn::ConvertTo(df, hn::BitCast(di32, bits)), hn::Set(df, 0x1p-24f));
#endif
}

// std::upper_bound over cdf[start, start + n) per lane (n >= 1), step for step: the number of
// entries <= u.
template <class DF, class VI = hn::Vec<hn::RebindToSigned<DF>>, class VF = hn::Vec<DF>>
HWY_INLINE VI UpperBound(DF df, const float* cdf, VI start, VI n, VF u) {
    const hn::RebindToSigned<DF> di;
    const VI one = hn::Set(di, 1);
    VI first = start, len = n;
    for (;;) {
        const auto active = len > hn::Zero(di);
        if (hn::AllFalse(di, active)) break;
        const VI half = hn::ShiftRight<1>(len);
        const VI middle = hn::IfThenElse(active, hn::Add(first, half), start);
        const VF probe = hn::GatherIndex(df, cdf, middle);
        const auto right = hn::And(active, hn::RebindMask(di, probe <= u));
        first = hn::IfThenElse(right, hn::Add(first, hn::Add(half, one)), first);
        len = hn::IfThenElse(right, hn::Sub(hn::Sub(len, half), one), half);
    }
    return hn::Sub(first, start);
}

// std::min / std::max as the scalar code has them (the first argument on ties and NaN).
template <class V>
HWY_INLINE V StdMin(V a, V b) {
    return hn::IfThenElse(b < a, b, a);
}
template <class V>
HWY_INLINE V StdMax(V a, V b) {
    return hn::IfThenElse(a < b, b, a);
}

// (a0 * b0 + a1 * b1) + a2 * b2: glm::dot's order.
template <class V>
HWY_INLINE V Dot(V a0, V a1, V a2, V b0, V b1, V b2) {
    return hn::Add(hn::Add(hn::Mul(a0, b0), hn::Mul(a1, b1)), hn::Mul(a2, b2));
}

// Distribution2D's guided inversion (tracer/distribution_2d.cpp, invert) per lane: the CDF of n
// intervals at cdf + cdfBase, its guide at guide + guideBase; u is rescaled within the interval.
template <class DF, class VF = hn::Vec<DF>, class VI = hn::Vec<hn::RebindToSigned<DF>>>
HWY_INLINE VI Invert(DF df, const float* cdf, const std::int32_t* guide, VI cdfBase, VI guideBase, int n, VF& u) {
    const hn::RebindToSigned<DF> di;
    const VF zero = hn::Zero(df), nf = hn::Set(df, static_cast<float>(n));
    const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1), nI = hn::Set(di, n);
    const VF x = hn::Mul(u, nf);
    // x > 0 ? (x < n ? int(x) : n - 1) : 0, a NaN at 0.
    const VI k = hn::IfThenElse(hn::RebindMask(di, x > zero),
                                hn::IfThenElse(hn::RebindMask(di, x < nf), hn::ConvertTo(di, x), hn::Sub(nI, oneI)), zeroI);
    VI i = hn::GatherIndex(di, guide, hn::Add(guideBase, k));
    const auto at = [&](VI j) { return hn::GatherIndex(df, cdf, hn::Add(cdfBase, j)); };
    for (;;) {  // while (i > 0 && cdf[i] > u) --i
        const auto back = hn::And(hn::RebindMask(df, i > zeroI), at(i) > u);
        if (hn::AllFalse(df, back)) break;
        i = hn::Sub(i, hn::IfThenElseZero(hn::RebindMask(di, back), oneI));
    }
    for (;;) {  // while (i + 1 < n && cdf[i + 1] <= u) ++i
        const VI next = hn::Add(i, oneI);
        const auto on = hn::And(hn::RebindMask(df, next < nI), at(next) <= u);  // next <= n: in the CDF
        if (hn::AllFalse(df, on)) break;
        i = hn::Add(i, hn::IfThenElseZero(hn::RebindMask(di, on), oneI));
    }
    for (;;) {  // while (i > 0 && !(cdf[i + 1] > cdf[i])) --i
        const auto empty = hn::And(hn::RebindMask(df, i > zeroI), hn::Not(at(hn::Add(i, oneI)) > at(i)));
        if (hn::AllFalse(df, empty)) break;
        i = hn::Sub(i, hn::IfThenElseZero(hn::RebindMask(di, empty), oneI));
    }
    const VF lo = at(i), width = hn::Sub(at(hn::Add(i, oneI)), lo);
    const VF rescaled = hn::Min(hn::Max(hn::Div(hn::Sub(u, lo), width), zero), hn::Set(df, kOneMinusUlp));
    u = hn::IfThenElse(width > zero, rescaled, zero);
    return i;
}

void ShadeLanes(const LightTable& t, Lanes& L, int count, const Salts& salts, bool roulette) {
    const hn::CappedTag<float, kLanes> df;
    const hn::RebindToSigned<decltype(df)> di;
    using VF = hn::Vec<decltype(df)>;
    using VI = hn::Vec<decltype(di)>;
    const int step = static_cast<int>(hn::Lanes(df));
    const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), invPi = hn::Set(df, std::numbers::inv_pi_v<float>);
    const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1);
    const VI lights = hn::Set(di, static_cast<std::int32_t>(t.selectCdf.size()));
    const auto storeMask = [&](auto m, std::int32_t* out) {
        hn::StoreU(hn::VecFromMask(di, hn::RebindMask(di, m)), di, out);
    };
    for (int i = 0; i < count; i += step) {
        const auto load = [&](const float* a) { return hn::LoadU(df, a + i); };
        const auto store = [&](VF v, float* a) { hn::StoreU(v, df, a + i); };
        // The step's random numbers.
        const std::uint64_t* keys = L.key + i;
        store(Draw(df, keys, salts.lobe), L.uLobe);
        const VF u1 = Draw(df, keys, salts.light1);
        VF u0 = Draw(df, keys, salts.light0);
        store(u0, L.uLight[0]);
        store(u1, L.uLight[1]);
        const VF b0 = Draw(df, keys, salts.bsdf0), b1 = Draw(df, keys, salts.bsdf1);
        store(b0, L.uBsdf[0]);
        store(b1, L.uBsdf[1]);
        const VF ur = Draw(df, keys, salts.roulette);
        store(ur, L.uRoulette);

        // The sample's inputs, and what the lanes below read of it. Without finite lights (a scene
        // lit by lights at infinity alone) no lane has a light sample, as prepareNextEventFinite.
        VF p[3], g[3], n[3], wi[3], radiance[3], origin[3];
        for (int c = 0; c < 3; ++c) {
            p[c] = load(L.p[c]);
            g[c] = load(L.g[c]);
            n[c] = load(L.n[c]);
            wi[c] = n[c];
            radiance[c] = zero;
        }
        const VF offset = load(L.offset);
        for (int c = 0; c < 3; ++c) origin[c] = hn::Add(p[c], hn::Mul(offset, g[c]));
        VF cs = zero, inv = zero, pick = one, tfar = zero;
        VF segment[3] = {zero, zero, zero};
        auto ok = zero > zero;
        if (!t.selectCdf.empty()) {
            // LightSet::select: the light on the power CDF, u0 rescaled within its interval.
            const float* cdf = t.selectCdf.data();
            const VI l = hn::Min(UpperBound(df, cdf, zeroI, lights, u0), hn::Sub(lights, oneI));
            const VF lowCdf = hn::IfThenElse(hn::RebindMask(df, l == zeroI), zero,
                                             hn::GatherIndex(df, cdf, hn::Max(hn::Sub(l, oneI), zeroI)));
            const VF width = hn::Sub(hn::GatherIndex(df, cdf, l), lowCdf);
            const VF rescaled = hn::Min(hn::Max(hn::Div(hn::Sub(u0, lowCdf), width), zero), hn::Set(df, kOneMinusUlp));
            u0 = hn::IfThenElse(width > zero, rescaled, zero);
            pick = hn::GatherIndex(df, t.selectPdf.data(), l);

            // AreaLightSampler::sample(u): the triangle, then a point uniform on it.
            const VI start = hn::GatherIndex(di, t.triStart.data(), l);
            const VI tris = hn::GatherIndex(di, t.triCount.data(), l);
            const VI tri = hn::Add(start, hn::Min(UpperBound(df, t.cdf.data(), start, tris, u0), hn::Sub(tris, oneI)));
            const VF ux = hn::Min(hn::Max(hn::Mul(hn::Sub(u0, hn::GatherIndex(df, t.cdfLow.data(), tri)),
                                                  hn::GatherIndex(df, t.invCdfWidth.data(), tri)),
                                          zero),
                                  hn::Set(df, kOneMinusUlp));
            const VF su = hn::Sqrt(ux);
            const VF s1 = hn::Mul(su, hn::Sub(one, u1)), s2 = hn::Mul(su, u1);
            VF q[3], ln[3], w[3];
            for (int c = 0; c < 3; ++c) {
                const VF v0 = hn::GatherIndex(df, t.v0[c].data(), tri);
                const VF e1 = hn::GatherIndex(df, t.e1[c].data(), tri), e2 = hn::GatherIndex(df, t.e2[c].data(), tri);
                q[c] = hn::Add(hn::Add(v0, hn::Mul(s1, e1)), hn::Mul(s2, e2));
                ln[c] = hn::GatherIndex(df, t.normal[c].data(), tri);
                w[c] = hn::Sub(q[c], p[c]);
            }

            // PathIntegrator::prepareNextEventFinite's geometry.
            const VF d2 = Dot(w[0], w[1], w[2], w[0], w[1], w[2]);
            ok = d2 > zero;
            const VF invD = hn::Div(one, hn::Sqrt(d2));
            for (int c = 0; c < 3; ++c) wi[c] = hn::Mul(w[c], invD);
            const VF cosLight = hn::Neg(Dot(ln[0], ln[1], ln[2], wi[0], wi[1], wi[2]));
            const VF cg = Dot(g[0], g[1], g[2], wi[0], wi[1], wi[2]);
            cs = Dot(n[0], n[1], n[2], wi[0], wi[1], wi[2]);
            ok = hn::And(ok, hn::And(cosLight > zero, hn::And(cg > zero, cs > zero)));
            // rayOffset(q, vertexScale) (tracer/ray_offset.h).
            const VF scale = StdMax(StdMax(hn::Abs(q[0]), hn::Abs(q[1])), StdMax(hn::Abs(q[2]), hn::Set(df, 1e-30f)));
            const VF vertexScale = hn::GatherIndex(df, t.vertexScale.data(), l);
            const VF rayOffset = hn::Mul(hn::Set(df, 1e-4f), StdMax(scale, hn::Mul(hn::Set(df, 1e-2f), vertexScale)));
            tfar = hn::Sub(one, hn::Mul(rayOffset, invD));
            ok = hn::And(ok, tfar > zero);
            inv = hn::Div(hn::Mul(hn::GatherIndex(df, t.area.data(), l), cosLight), d2);
            for (int c = 0; c < 3; ++c) radiance[c] = hn::GatherIndex(df, t.radiance[c].data(), l);
            for (int c = 0; c < 3; ++c) segment[c] = hn::Sub(q[c], origin[c]);
        }
        for (int c = 0; c < 3; ++c) {
            store(origin[c], L.origin[c]);
            store(segment[c], L.segment[c]);
            store(wi[c], L.wi[c]);
            store(radiance[c], L.radiance[c]);
        }
        store(tfar, L.tfar);
        store(cs, L.cosSurface);
        store(inv, L.inv);
        store(pick, L.pick);
        storeMask(ok, L.lightOk + i);

        // bsdf::basis around the shading normal: the frame of the cosine bounce and of the
        // microfacet lobes.
        const VF sign = hn::CopySign(one, n[2]);
        const VF a = hn::Div(hn::Set(df, -1.0f), hn::Add(sign, n[2]));
        const VF cc = hn::Mul(hn::Mul(n[0], n[1]), a);
        const VF tx = hn::Add(one, hn::Mul(hn::Mul(hn::Mul(sign, n[0]), n[0]), a));
        const VF ty = hn::Mul(sign, cc);
        const VF tz = hn::Mul(hn::Neg(sign), n[0]);
        const VF bx = cc;
        const VF by = hn::Add(sign, hn::Mul(hn::Mul(n[1], n[1]), a));
        const VF bz = hn::Neg(n[1]);
        const VI model = hn::LoadU(di, L.model + i);
        const auto lambert = hn::RebindMask(df, model == hn::Set(di, kLambert));
        const auto plastic = hn::RebindMask(df, model == hn::Set(di, kRoughPlastic));
        const auto shaded = hn::Or(lambert, plastic);
        const bool anyPlastic = !hn::AllFalse(df, plastic);

        // Rough plastic (bsdf::evalModel with GGX): the coating's microfacet lobe and the base
        // under it, their pdf mixed by the coating's pick. Zero where wo or wi is below.
        VF wo[3], lo[3], alphaU = zero, alphaV = zero, ior = one, pickSpecular = zero;
        for (int c = 0; c < 3; ++c) wo[c] = load(L.wo[c]);
        lo[0] = Dot(wo[0], wo[1], wo[2], tx, ty, tz);
        lo[1] = Dot(wo[0], wo[1], wo[2], bx, by, bz);
        lo[2] = Dot(wo[0], wo[1], wo[2], n[0], n[1], n[2]);
        if (anyPlastic) {
            alphaU = load(L.alpha[0]);
            alphaV = load(L.alpha[1]);
            ior = load(L.ior);
            pickSpecular = load(L.pickSpecular);
        }
        const auto lambdaGgx = [&](const VF (&v)[3]) {
            const VF xu = hn::Mul(alphaU, v[0]), yv = hn::Mul(alphaV, v[1]);
            const VF xy2 = hn::Add(hn::Mul(xu, xu), hn::Mul(yv, yv));
            const VF tan2 = hn::Div(xy2, hn::Mul(v[2], v[2]));
            const VF lambda = hn::Mul(hn::Set(df, 0.5f), hn::Sub(hn::Sqrt(hn::Add(one, tan2)), one));
            return hn::IfThenElse(xy2 <= zero, zero, lambda);
        };
        const auto g1 = [&](const VF (&v)[3], const VF (&h)[3]) {
            const VF g = hn::Div(one, hn::Add(one, lambdaGgx(v)));
            return hn::IfThenElseZero(hn::Mul(Dot(v[0], v[1], v[2], h[0], h[1], h[2]), v[2]) > zero, g);
        };
        const auto evalPlastic = [&](const VF (&w)[3], VF (&f)[3], VF& pdf) __attribute__((always_inline)) {
            VF li[3], h[3];
            li[0] = Dot(w[0], w[1], w[2], tx, ty, tz);
            li[1] = Dot(w[0], w[1], w[2], bx, by, bz);
            li[2] = Dot(w[0], w[1], w[2], n[0], n[1], n[2]);
            const auto valid = hn::And(lo[2] > zero, li[2] > zero);
            for (int c = 0; c < 3; ++c) h[c] = hn::Add(lo[c], li[c]);
            const VF hScale = hn::Div(one, hn::Sqrt(Dot(h[0], h[1], h[2], h[0], h[1], h[2])));
            for (int c = 0; c < 3; ++c) h[c] = hn::Mul(h[c], hScale);
            // microfacet::Distribution::D, GGX.
            const VF x = hn::Div(h[0], alphaU), y = hn::Div(h[1], alphaV);
            const VF s = hn::Add(hn::Add(hn::Mul(x, x), hn::Mul(y, y)), hn::Mul(h[2], h[2]));
            const VF piAlpha = hn::Mul(hn::Mul(hn::Set(df, std::numbers::pi_v<float>), alphaU), alphaV);
            VF D = hn::Div(one, hn::Mul(hn::Mul(piAlpha, s), s));
            D = hn::IfThenElseZero(hn::And(h[2] > zero, hn::Mul(D, h[2]) > hn::Set(df, 1e-20f)), D);
            const VF g1o = g1(lo, h);
            const VF G = hn::Mul(g1o, g1(li, h));
            // microfacet::fresnelDielectricSigned(dot(lo, h), ior).
            const VF cosH = Dot(lo[0], lo[1], lo[2], h[0], h[1], h[2]);
            const VF e = hn::IfThenElse(cosH >= zero, ior, hn::Div(one, ior));
            const VF ci = hn::Min(hn::Abs(cosH), one);
            const VF sin2T = hn::Div(hn::Sub(one, hn::Mul(ci, ci)), hn::Mul(e, e));
            const VF ct = hn::Sqrt(hn::Max(hn::Sub(one, sin2T), zero));
            const VF rs = hn::Div(hn::Sub(ci, hn::Mul(e, ct)), hn::Add(ci, hn::Mul(e, ct)));
            const VF rp = hn::Div(hn::Sub(hn::Mul(e, ci), ct), hn::Add(hn::Mul(e, ci), ct));
            const VF fresnel = hn::Mul(hn::Set(df, 0.5f), hn::Add(hn::Mul(rs, rs), hn::Mul(rp, rp)));
            const VF F = hn::IfThenElse(sin2T >= one, one, fresnel);
            const VF glossy = hn::Div(hn::Mul(D, G), hn::Mul(hn::Mul(hn::Set(df, 4.0f), lo[2]), li[2]));
            const VF glossyPdf = hn::Div(hn::Mul(D, g1o), hn::Mul(hn::Set(df, 4.0f), lo[2]));
            // The base through the coating: its transmittance towards wi, from the material's table.
            alignas(64) float cosines[kLanes], tI[kLanes] = {};
            hn::Store(li[2], df, cosines);
            for (int j = 0; j < step; ++j)
                if (L.model[i + j] == kRoughPlastic) tI[j] = bsdf::coatingTransmittance(*L.material[i + j], cosines[j]);
            const VF diffuse = hn::Div(hn::Mul(hn::Mul(invPi, load(L.tO)), hn::Load(df, tI)), hn::Mul(ior, ior));
            for (int c = 0; c < 3; ++c)
                f[c] = hn::IfThenElseZero(valid, hn::Add(hn::Mul(hn::Mul(load(L.tint[c]), F), glossy),
                                                         hn::Mul(load(L.base[c]), diffuse)));
            pdf = hn::IfThenElseZero(valid, hn::Add(hn::Mul(pickSpecular, glossyPdf),
                                                    hn::Mul(hn::Mul(hn::Sub(one, pickSpecular), li[2]), invPi)));
        };

        // The BSDF of a lane's model towards a light sample w at cosine cosW: Lambert albedo / pi
        // with pdf cos / pi, or rough plastic's lobes.
        VF albedoPi[3];
        for (int c = 0; c < 3; ++c) albedoPi[c] = hn::Mul(load(L.albedo[c]), invPi);
        const auto evalLanes = [&](const VF (&w)[3], VF cosW, VF (&f)[3], VF& pdf) __attribute__((always_inline)) {
            for (int c = 0; c < 3; ++c) f[c] = albedoPi[c];
            pdf = hn::Mul(cosW, invPi);
            if (!anyPlastic) return;
            VF fp[3], pdfPlastic;
            evalPlastic(w, fp, pdfPlastic);
            for (int c = 0; c < 3; ++c) f[c] = hn::IfThenElse(plastic, fp[c], f[c]);
            pdf = hn::IfThenElse(plastic, pdfPlastic, pdf);
        };

        // The BSDF towards the light and the power heuristic's weight over the light's pdf in one
        // division, as prepareNextEventFinite.
        VF f[3], pdfLight;
        evalLanes(wi, cs, f, pdfLight);
        const VF bsdfInv = hn::Mul(pdfLight, inv);
        const VF denominator = hn::Add(hn::Mul(pick, pick), hn::Mul(bsdfInv, bsdfInv));
        const auto shadow = hn::And(shaded, hn::And(ok, denominator > zero));
        storeMask(shadow, L.shadow + i);
        const VF weight = hn::Mul(cs, hn::Div(hn::Mul(pick, inv), denominator));
        for (int c = 0; c < 3; ++c) store(hn::Mul(hn::Mul(f[c], radiance[c]), weight), L.contribution[c]);

        // EnvironmentSampler::sample and nextEventInfinite's map sample: the cell by the guided
        // inversion of the marginal and the row's CDF, the direction from its sine and cosine, the
        // BSDF towards it and the power heuristic, for Lambert and rough plastic lanes.
        // Skipped where every lane is kOther: finishSimdLane samples their sky and never reads
        // their envShadow.
        if (t.envWidth > 0 && !hn::AllFalse(df, shaded)) {
            VF ux = Draw(df, keys, salts.env0), uy = Draw(df, keys, salts.env1);
            const int w = t.envWidth, h = t.envHeight;
            const VI row = Invert(df, t.envMarginal.data(), t.envMarginalGuide.data(), zeroI, zeroI, h, uy);
            const VI col = Invert(df, t.envConditional.data(), t.envConditionalGuide.data(),
                                  hn::Mul(row, hn::Set(di, w + 1)), hn::Mul(row, hn::Set(di, w)), w, ux);
            const VF kMax = hn::Set(df, kOneMinusUlp);
            const VF px = hn::Min(hn::Div(hn::Add(hn::ConvertTo(df, col), ux), hn::Set(df, static_cast<float>(w))), kMax);
            const VF py = hn::Min(hn::Div(hn::Add(hn::ConvertTo(df, row), uy), hn::Set(df, static_cast<float>(h))), kMax);
            const VI cell = hn::Add(hn::Mul(row, hn::Set(di, w)), col);
            const VF cellPdf = hn::GatherIndex(df, t.envPdf.data(), cell);
            const VF kPi = hn::Set(df, std::numbers::pi_v<float>);
            const VF theta = hn::Mul(py, kPi), phi = hn::Mul(hn::Mul(px, hn::Set(df, 2.0f)), kPi);
            const VF sinTheta = hn::Sin(df, theta), cosTheta = hn::Cos(df, theta);
            const VF local[3] = {hn::Mul(sinTheta, hn::Sin(df, phi)), cosTheta, hn::Neg(hn::Mul(sinTheta, hn::Cos(df, phi)))};
            VF ed[3];
            for (int c = 0; c < 3; ++c) {
                const float* m = t.envToWorld;
                ed[c] = hn::Add(hn::Add(hn::Mul(hn::Set(df, m[c]), local[0]), hn::Mul(hn::Set(df, m[3 + c]), local[1])),
                                hn::Mul(hn::Set(df, m[6 + c]), local[2]));
            }
            const VF edScale = hn::Div(one, hn::Sqrt(Dot(ed[0], ed[1], ed[2], ed[0], ed[1], ed[2])));
            for (int c = 0; c < 3; ++c) ed[c] = hn::Mul(ed[c], edScale);
            const VF envPdf = hn::Div(cellPdf, hn::Mul(hn::Set(df, 2.0f * std::numbers::pi_v<float> * std::numbers::pi_v<float>),
                                                       sinTheta));
            // lightToward: above both normals; the BSDF as for the area light's sample.
            const VF eg = Dot(g[0], g[1], g[2], ed[0], ed[1], ed[2]);
            const VF ec = Dot(n[0], n[1], n[2], ed[0], ed[1], ed[2]);
            VF ef[3], ePdf;
            evalLanes(ed, ec, ef, ePdf);
            const auto envOk = hn::And(shaded, hn::And(hn::And(cellPdf > zero, sinTheta > zero), hn::And(eg > zero, ec > zero)));
            storeMask(envOk, L.envShadow + i);
            // powerHeuristic(envPdf, ePdf), then cosSurface * weight / envPdf.
            const VF a2 = hn::Mul(envPdf, envPdf), b2 = hn::Mul(ePdf, ePdf);
            const VF sum2 = hn::Add(a2, b2);
            const VF heuristic = hn::IfThenElseZero(sum2 > zero, hn::Div(a2, sum2));
            const VF scale = hn::Div(hn::Mul(ec, heuristic), envPdf);
            for (int c = 0; c < 3; ++c) {
                const VF radianceC = hn::GatherIndex(df, t.envRadiance[c].data(), cell);
                store(hn::IfThenElseZero(envOk, hn::Mul(hn::Mul(ef[c], radianceC), scale)), L.envContribution[c]);
                store(ed[c], L.envDir[c]);
            }
        }

        // The bounce: bsdf::sampleCosine, or for the coating's share of rough plastic lanes a
        // visible GGX normal (Heitz 2018, as microfacet::Distribution::sampleVisibleGgx), then the
        // checks and weights of scatterPathVertex's non-delta branch. Both take the same r, phi.
        const VF r = hn::Sqrt(b0);
        const VF phi = hn::Mul(hn::Set(df, 2.0f * std::numbers::pi_v<float>), b1);
        const VF rc = hn::Mul(r, hn::Cos(df, phi)), rs = hn::Mul(r, hn::Sin(df, phi));
        const VF z = hn::Sqrt(hn::Max(zero, hn::Sub(one, b0)));
        VF dir[3];
        dir[0] = hn::Add(hn::Add(hn::Mul(rc, tx), hn::Mul(rs, bx)), hn::Mul(z, n[0]));
        dir[1] = hn::Add(hn::Add(hn::Mul(rc, ty), hn::Mul(rs, by)), hn::Mul(z, n[1]));
        dir[2] = hn::Add(hn::Add(hn::Mul(rc, tz), hn::Mul(rs, bz)), hn::Mul(z, n[2]));
        auto sampled = lambert;
        if (anyPlastic) {
            const auto specular = hn::And(plastic, load(L.uLobe) < pickSpecular);
            sampled = hn::Or(sampled, hn::And(plastic, lo[2] > zero));
            if (!hn::AllFalse(df, specular)) {
                VF vh[3] = {hn::Mul(alphaU, lo[0]), hn::Mul(alphaV, lo[1]), lo[2]};
                const VF vScale = hn::Div(one, hn::Sqrt(Dot(vh[0], vh[1], vh[2], vh[0], vh[1], vh[2])));
                for (int c = 0; c < 3; ++c) vh[c] = hn::Mul(vh[c], vScale);
                const VF len2 = hn::Add(hn::Mul(vh[0], vh[0]), hn::Mul(vh[1], vh[1]));
                const VF len = hn::Sqrt(len2);
                const auto tilted = len2 > zero;
                const VF t1[3] = {hn::IfThenElse(tilted, hn::Div(hn::Neg(vh[1]), len), one),
                                  hn::IfThenElseZero(tilted, hn::Div(vh[0], len)), zero};
                const VF t2[3] = {hn::Sub(hn::Mul(vh[1], t1[2]), hn::Mul(t1[1], vh[2])),
                                  hn::Sub(hn::Mul(vh[2], t1[0]), hn::Mul(t1[2], vh[0])),
                                  hn::Sub(hn::Mul(vh[0], t1[1]), hn::Mul(t1[0], vh[1]))};
                const VF s = hn::Mul(hn::Set(df, 0.5f), hn::Add(one, vh[2]));
                const VF rest = hn::Sub(one, hn::Mul(rc, rc));
                const VF p2 = hn::Add(hn::Mul(hn::Sub(one, s), hn::Sqrt(hn::Max(zero, rest))), hn::Mul(s, rs));
                const VF up = hn::Sqrt(hn::Max(zero, hn::Sub(rest, hn::Mul(p2, p2))));
                VF h[3];
                for (int c = 0; c < 3; ++c)
                    h[c] = hn::Add(hn::Add(hn::Mul(rc, t1[c]), hn::Mul(p2, t2[c])), hn::Mul(up, vh[c]));
                h[0] = hn::Mul(alphaU, h[0]);
                h[1] = hn::Mul(alphaV, h[1]);
                h[2] = StdMax(hn::Set(df, 1e-6f), h[2]);
                const VF hScale = hn::Div(one, hn::Sqrt(Dot(h[0], h[1], h[2], h[0], h[1], h[2])));
                for (int c = 0; c < 3; ++c) h[c] = hn::Mul(h[c], hScale);
                const VF twice = hn::Mul(hn::Set(df, 2.0f), Dot(lo[0], lo[1], lo[2], h[0], h[1], h[2]));
                VF li[3];
                for (int c = 0; c < 3; ++c) li[c] = hn::Sub(hn::Mul(twice, h[c]), lo[c]);
                sampled = hn::AndNot(hn::And(specular, li[2] <= zero), sampled);
                const VF world[3] = {hn::Add(hn::Add(hn::Mul(li[0], tx), hn::Mul(li[1], bx)), hn::Mul(li[2], n[0])),
                                     hn::Add(hn::Add(hn::Mul(li[0], ty), hn::Mul(li[1], by)), hn::Mul(li[2], n[1])),
                                     hn::Add(hn::Add(hn::Mul(li[0], tz), hn::Mul(li[1], bz)), hn::Mul(li[2], n[2]))};
                for (int c = 0; c < 3; ++c) dir[c] = hn::IfThenElse(specular, world[c], dir[c]);
            }
        }
        const VF cosI = Dot(n[0], n[1], n[2], dir[0], dir[1], dir[2]);
        VF pdf = hn::Mul(cosI, invPi);
        VF fBounce[3] = {albedoPi[0], albedoPi[1], albedoPi[2]};
        if (anyPlastic) {
            VF fp[3], pdfPlastic;
            evalPlastic(dir, fp, pdfPlastic);
            for (int c = 0; c < 3; ++c) fBounce[c] = hn::IfThenElse(plastic, fp[c], fBounce[c]);
            pdf = hn::IfThenElse(plastic, pdfPlastic, pdf);
        }
        auto next = hn::And(sampled, hn::And(cosI > zero, Dot(g[0], g[1], g[2], dir[0], dir[1], dir[2]) > zero));
        next = hn::And(next, pdf > zero);
        const VF ratio = hn::Div(cosI, pdf);
        VF beta[3];
        for (int c = 0; c < 3; ++c) beta[c] = hn::Mul(load(L.beta[c]), hn::Mul(fBounce[c], ratio));
        if (roulette) {
            // As Mitsuba: the throughput without the eta^2 factors.
            const VF largest = StdMax(beta[0], StdMax(beta[1], beta[2]));
            const VF survive = StdMin(hn::Mul(largest, load(L.etaScale)), hn::Set(df, 0.95f));
            next = hn::And(next, ur < survive);
            const VF boost = hn::Div(one, survive);
            for (int c = 0; c < 3; ++c) beta[c] = hn::Mul(beta[c], boost);
        }
        storeMask(next, L.next + i);
        for (int c = 0; c < 3; ++c) {
            store(dir[c], L.dir[c]);
            store(beta[c], L.beta[c]);
        }
        store(pdf, L.pdf);
    }
}

}  // namespace aamap::pathsimd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "tracer/integrator.h"
#include "tracer/environment.h"
#include "tracer/lights.h"

namespace aamap::pathsimd {

HWY_EXPORT(ShadeLanes);

void shade(const LightTable& lights, Lanes& lanes, int count, int depth, bool roulette) {
    using dims::PathSlot;
    const Salts salts{Sampler::dimSalt(dims::path(depth, PathSlot::Lobe)),
                      Sampler::dimSalt(dims::path(depth, PathSlot::Light)),
                      Sampler::dimSalt(dims::path(depth, PathSlot::Light) + 1),
                      Sampler::dimSalt(dims::path(depth, PathSlot::Bsdf)),
                      Sampler::dimSalt(dims::path(depth, PathSlot::Bsdf) + 1),
                      Sampler::dimSalt(dims::path(depth, PathSlot::Roulette)),
                      Sampler::dimSalt(dims::path(depth, PathSlot::EnvLight)),
                      Sampler::dimSalt(dims::path(depth, PathSlot::EnvLight) + 1)};
    HWY_DYNAMIC_DISPATCH(ShadeLanes)(lights, lanes, count, salts, roulette);
}

LightTable makeLightTable(const LightSet& lights) {
    LightTable t;
    t.selectCdf = lights.selectCdf;
    t.selectPdf = lights.selectPdf;
    for (std::size_t a = 0; a < lights.areas.size(); ++a) {
        const AreaLightSampler& light = lights.areas[a];
        const auto& tris = light.triangles();
        t.triStart.push_back(static_cast<std::int32_t>(t.cdf.size()));
        t.triCount.push_back(static_cast<std::int32_t>(tris.size()));
        for (int c = 0; c < 3; ++c) t.radiance[c].push_back(light.radiance()[c]);
        t.area.push_back(light.area());
        t.vertexScale.push_back(light.vertexScale());
        for (const AreaLightSampler::Tri& tri : tris) {
            t.cdfLow.push_back(tri.cdfLow);
            t.cdf.push_back(tri.cdf);
            t.invCdfWidth.push_back(tri.invCdfWidth);
            for (int c = 0; c < 3; ++c) {
                t.v0[c].push_back(tri.v0[c]);
                t.e1[c].push_back(tri.e1[c]);
                t.e2[c].push_back(tri.e2[c]);
                t.normal[c].push_back(tri.normal[c]);
            }
        }
    }
    if (lights.environment && !lights.environment->constant()) {
        const EnvironmentSampler& env = *lights.environment;
        const Distribution2D& d = env.distribution();
        t.envWidth = env.width();
        t.envHeight = env.height();
        t.envMarginal = d.marginalCdf();
        t.envConditional = d.conditionalCdfs();
        t.envMarginalGuide.assign(d.marginalGuide().begin(), d.marginalGuide().end());
        t.envConditionalGuide.assign(d.conditionalGuide().begin(), d.conditionalGuide().end());
        for (int y = 0; y < t.envHeight; ++y)
            for (int x = 0; x < t.envWidth; ++x) t.envPdf.push_back(d.pdf(x, y));
        for (const glm::vec3& r : env.map())
            for (int c = 0; c < 3; ++c) t.envRadiance[c].push_back(r[c]);
        for (int col = 0; col < 3; ++col)
            for (int c = 0; c < 3; ++c) t.envToWorld[3 * col + c] = env.toWorld()[col][c];
    }
    return t;
}

}  // namespace aamap::pathsimd
#endif  // HWY_ONCE
