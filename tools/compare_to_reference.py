#!/usr/bin/env python3
"""A render against a published reference render: brightness ratio and LDR-FLIP, at full size
and after box-filtering both images by FACTOR (which averages away the render's path-tracing
noise, leaving the difference in what was rendered).

Usage: compare_to_reference.py REFERENCE.exr RENDER.exr [--factor 4] [--exposure 1]
                               [--render-scale R,G,B]

Both are linear RGB EXRs of the same size. --render-scale multiplies the render's channels first:
an RGB render is linear in each channel's emission, so this compares scenes whose lights differ
only in colour and brightness. LDR-FLIP is computed on exposure * radiance, clamped
to [0, 1] and sRGB-encoded, as aamap's own LDR-FLIP (eval/metrics) sees the images. The
brightness ratio is mean luminance (Rec. 709 weights) of the render over the reference's, and
per channel. Run it with the repo's .venv (tools/python-env.sh makes it).
"""
import sys


def main(argv):
    import argparse

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("reference")
    parser.add_argument("render")
    parser.add_argument("--factor", type=int, default=4)
    parser.add_argument("--exposure", type=float, default=1.0)
    parser.add_argument("--render-scale", default="1,1,1")
    args = parser.parse_args(argv[1:])
    import flip_evaluator as flip
    import numpy as np

    ref = flip.load(args.reference)[..., :3].astype(np.float64)
    test = flip.load(args.render)[..., :3].astype(np.float64)
    test *= np.array([float(v) for v in args.render_scale.split(",")])
    factor, exposure = args.factor, args.exposure
    if ref.shape != test.shape:
        print(f"compare_to_reference: sizes differ: {ref.shape} vs {test.shape}", file=sys.stderr)
        return 1
    weights = np.array([0.2126, 0.7152, 0.0722])
    print(f"brightness ratio (luminance): {(test @ weights).mean() / (ref @ weights).mean():.4f}")
    print("brightness ratio (r, g, b): " + ", ".join(f"{v:.4f}" for v in test.mean(axis=(0, 1)) / ref.mean(axis=(0, 1))))

    def srgb(img):
        x = np.clip(img * exposure, 0.0, 1.0)
        return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055).astype(np.float32)

    def box(img, f):
        h, w = img.shape[0] // f * f, img.shape[1] // f * f
        return img[:h, :w].reshape(h // f, f, w // f, f, 3).mean(axis=(1, 3))

    for f in sorted({1, factor}):
        r, t = (box(ref, f), box(test, f)) if f > 1 else (ref, test)
        _, mean, _ = flip.evaluate(srgb(r), srgb(t), "LDR", applyMagma=False)
        print(f"LDR-FLIP mean at {r.shape[1]}x{r.shape[0]} (box {f}x{f}): {mean:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
