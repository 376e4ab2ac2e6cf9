#!/usr/bin/env python3
"""Colour and brightness of aamap's path mode against Mitsuba 3's RGB and spectral modes.

The same Mitsuba scene file (sampled reflectance and emission spectra) rendered by Mitsuba 3 in
llvm_ad_rgb and llvm_ad_spectral, and by aamap's bench_tracer in path mode, at the same size, spp
and depth with a box filter; prints each image's mean linear RGB and the ratios per channel to the
spectral render, which is what the spectra mean. Noise in the means is far below the differences
that matter here (a few 0.1 %).

Setup as bench/peers/mitsuba_throughput.py, then
    .venv/bin/python bench/peers/mitsuba_colour_check.py [--scene ../shared/scenes/mitsuba-cbox/scene.xml]
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_throughput import load_mitsuba, mitsuba_scene_file  # noqa: E402


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=os.path.join(repo, "..", "shared", "scenes", "mitsuba-cbox", "scene.xml"))
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--spp", type=int, default=256, help="a perfect square (aamap's n x n strata)")
    ap.add_argument("--depth", type=int, default=5)
    ap.add_argument("--bench", default=os.path.join(repo, "build", "release", "bench", "tracer", "bench_tracer"))
    args = ap.parse_args()
    strata = round(args.spp ** 0.5)
    if strata * strata != args.spp:
        sys.exit(f"--spp {args.spp} is not a perfect square")
    mi, _ = load_mitsuba(args.scene)
    import numpy as np

    means = {}
    with tempfile.TemporaryDirectory() as tmp:
        path = mitsuba_scene_file(args.scene, args.size, args.spp, args.depth, "box", tmp)
        for variant in ("llvm_ad_rgb", "llvm_ad_spectral"):
            mi, _ = load_mitsuba(args.scene, variant)
            image = np.array(mi.render(mi.load_file(path), spp=args.spp))[:, :, :3]
            means[f"mitsuba {variant}"] = image.reshape(-1, 3).mean(0)
        exr = os.path.join(tmp, "aamap.exr")
        subprocess.run([args.bench, "--scene", args.scene, "--size", str(args.size), "--strata", str(strata),
                        "--mode", "path", "--max-depth", str(args.depth), "--light-samples", "1", "--repeat", "1",
                        "--out", exr], check=True, capture_output=True)
        means["aamap path"] = np.array(mi.Bitmap(exr))[:, :, :3].reshape(-1, 3).mean(0)
    spectral = means["mitsuba llvm_ad_spectral"]
    print(f"{args.size}x{args.size}, {args.spp} spp, depth {args.depth}, box filter, mitsuba {mi.__version__}")
    for name, m in means.items():
        r = m / spectral
        print(f"{name:<26} mean rgb {m[0]:.5f} {m[1]:.5f} {m[2]:.5f}   / spectral {r[0]:.4f} {r[1]:.4f} {r[2]:.4f}")


if __name__ == "__main__":
    main()
