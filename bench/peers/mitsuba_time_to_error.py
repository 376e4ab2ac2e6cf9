#!/usr/bin/env python3
"""Time to an error level: aamap's path mode against Mitsuba 3 on the same machine and scene.

Each renderer is measured against its own converged reference (the two project spectra to RGB
differently, so one's reference is biased for the other): Mitsuba 3 (llvm_ad_rgb, path integrator)
renders a ladder of samples per pixel and its --reference-spp image; aamap runs one experiment in
path mode with uniform and variance-driven renders at a ladder of rays per pixel and its own
path-traced reference of --reference-spp. Both use the same maximum path depth and pixel filter,
and the same error measure (aamap's LDR-FLIP: % pixels above 0.1, through `aamap diff` for
Mitsuba's images). The timed renders run in interleaved rounds (Mitsuba's ladder, then aamap's
experiment, again ...): aamap's later rounds reuse its first reference as a file and trace every
render again. Prints each setting's median time, its spread and its error, and the fastest setting
of each renderer at or below --target % pixels in error.

Setup as bench/peers/mitsuba_throughput.py (libllvm19, pip mitsuba==3.6.4 in .venv), then
    .venv/bin/python bench/peers/mitsuba_time_to_error.py [--size 256] [--filter gaussian]
        [--filter-mode convolution]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_throughput import load_mitsuba, mitsuba_scene_file  # noqa: E402


def ladder(text):
    values = [int(v) for v in text.split(",") if v]
    for v in values:
        if round(v ** 0.5) ** 2 != v:
            sys.exit(f"{v}: not a perfect square (aamap's n x n strata)")
    return values


def aamap_config(scene, size, depth, rfilter, filter_mode, uniform, variance, thresholds, min_samples, reference,
                 light_sampling):
    """The experiment: path mode with one light sample per hit (as Mitsuba's one emitter sample per
    bounce), Russian roulette from depth 5 on as Mitsuba's default rr_depth."""
    renders = [f'  - {{name: "uniform{{rpp}}", series: Uniform, strategy: uniform, rpp: {json.dumps(uniform)}}}']
    if variance:
        renders.append(f'  - {{name: "variance{{rpp}}_t{{noise_threshold}}", series: "Variance {{noise_threshold}}", '
                       f'strategy: variance, rpp: {json.dumps(variance)}, noise_threshold: {json.dumps(thresholds)}, '
                       f'min_samples: {min_samples}, sample_step: 8}}')
    return "\n".join([
        f"scene: {json.dumps(os.path.abspath(scene))}",
        f"image: {{width: {size}, height: {size}, filter: {rfilter}, filter_mode: {filter_mode}}}",
        f"shading: {{mode: path, max_depth: {depth}, area_light_samples: 1, light_sampling: {light_sampling}}}",
        "renders:", *renders,
        f"reference: {reference}",
        "metrics: {map_quality: false}",
        "report: {plots: false}", ""])


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=os.path.join(repo, "..", "shared", "scenes", "mitsuba-cbox", "scene.xml"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--depth", type=int, default=5, help="longest path in segments, both renderers")
    ap.add_argument("--filter", default="gaussian", choices=["box", "tent", "gaussian"],
                    help="pixel filter of both (gaussian: Mitsuba's default)")
    ap.add_argument("--filter-mode", default="convolution", choices=["convolution", "importance"],
                    help="how aamap applies it (image.filter_mode; Mitsuba splats its samples)")
    ap.add_argument("--mitsuba-spp", type=ladder, default=ladder("16,36,64,100,144"))
    ap.add_argument("--uniform-rpp", type=ladder, default=ladder("16,36,64,100,144"))
    ap.add_argument("--variance-rpp", type=ladder, default=ladder("64,144"),
                    help="the variance strategy's most rays per pixel")
    ap.add_argument("--variance-threshold", default="0.01,0.04,0.08",
                    help="its noise_threshold values (0.01: Cycles' default)")
    ap.add_argument("--variance-min-samples", type=int, default=16)
    ap.add_argument("--reference-spp", type=int, default=1024)
    ap.add_argument("--target", type=float, default=1.0, help="%% pixels above FLIP 0.1")
    ap.add_argument("--light-sampling", default="auto", choices=["auto", "solid_angle", "area"],
                    help="aamap's shading.light_sampling")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--aamap", default=os.path.join(repo, "build", "release", "aamap"))
    ap.add_argument("--json", help="write every setting's times and errors here")
    args = ap.parse_args()
    if not os.path.exists(args.aamap):
        sys.exit(f"{args.aamap}: build it first (cmake --build --preset release)")
    mi, dr = load_mitsuba(args.scene)

    times = {}  # (renderer, setting) -> [seconds per round]
    errors = {}  # (renderer, setting) -> aamap diff / results.json metrics
    with tempfile.TemporaryDirectory() as tmp:
        scene = mi.load_file(mitsuba_scene_file(args.scene, args.size, args.reference_spp, args.depth, args.filter, tmp))

        def render(spp):
            t0 = time.perf_counter()
            image = mi.render(scene, spp=spp)
            dr.eval(image)
            dr.sync_thread()
            return image, time.perf_counter() - t0

        reference, t_ref = render(args.reference_spp)  # also compiles the kernels
        mitsuba_ref = os.path.join(tmp, "mitsuba_reference.exr")
        mi.Bitmap(reference).write(mitsuba_ref)
        print(f"mitsuba {mi.__version__} llvm_ad_rgb, {args.size}x{args.size}, depth {args.depth}, {args.filter} "
              f"filter; reference {args.reference_spp} spp in {t_ref:.1f} s", flush=True)
        for spp in args.mitsuba_spp:
            render(spp)  # kernels for every sample count before the timed rounds

        aamap_ref = os.path.join(tmp, "aamap_reference.exr")
        for r in range(args.rounds):
            for spp in args.mitsuba_spp:
                image, seconds = render(spp)
                times.setdefault(("mitsuba", f"{spp} spp"), []).append(seconds)
                if r == 0:
                    test = os.path.join(tmp, f"mitsuba_{spp}.exr")
                    mi.Bitmap(image).write(test)
                    errors[("mitsuba", f"{spp} spp")] = json.loads(subprocess.run(
                        [args.aamap, "diff", mitsuba_ref, test, "--json"], check=True, capture_output=True,
                        text=True).stdout)
            reference_yaml = (f"{{type: uniform, mode: path, rpp: {args.reference_spp}}}" if r == 0
                              else f"{{type: file, path: {json.dumps(aamap_ref)}}}")
            config = os.path.join(tmp, f"aamap_{r}.yaml")
            with open(config, "w") as f:
                f.write(aamap_config(args.scene, args.size, args.depth, args.filter, args.filter_mode,
                                     args.uniform_rpp, args.variance_rpp, [float(t) for t in args.variance_threshold.split(",") if t],
                                     args.variance_min_samples, reference_yaml, args.light_sampling))
            out = os.path.join(tmp, f"aamap_{r}")
            subprocess.run([args.aamap, "run", config, "-o", out, "--no-plots"], check=True, capture_output=True)
            with open(os.path.join(out, "results.json")) as f:
                results = json.load(f)
            if r == 0:
                os.replace(os.path.join(out, "reference.exr"), aamap_ref)
            for rec in results["renders"]:
                key = ("aamap path", rec["name"])
                times.setdefault(key, []).append(rec["times_s"]["trace"])
                errors[key] = dict(rec["metrics"], mean_rpp=rec["mean_primary_rpp"])
            done = ", ".join(f"{k[0]} {k[1]} {v[-1]:.2f} s" for k, v in times.items())
            print(f"round {r + 1}: {done}", flush=True)

    rows = []
    for key, ts in times.items():
        e = errors[key]
        spp = e.get("mean_rpp", int(key[1].split()[0]) if key[0] == "mitsuba" else 0)
        rows.append({"renderer": key[0], "setting": key[1], "mean_spp": spp, "median_s": statistics.median(ts),
                     "min_s": min(ts), "max_s": max(ts), "pct_error_flip": e["pct_error_flip"],
                     "flip_mean": e["flip_mean"]})
    print(f"\n{'renderer':<12} {'setting':<20} {'mean spp':>8} {'median s':>9} {'range s':>13} {'% > 0.1':>8} "
          f"{'FLIP mean':>10}")
    for row in rows:
        print(f"{row['renderer']:<12} {row['setting']:<20} {row['mean_spp']:8.1f} {row['median_s']:9.2f} "
              f"{row['min_s']:6.2f}-{row['max_s']:<6.2f} {row['pct_error_flip']:8.2f} {row['flip_mean']:10.4f}")
    fastest = {}
    for row in rows:
        if row["pct_error_flip"] <= args.target:
            best = fastest.get(row["renderer"])
            if best is None or row["median_s"] < best["median_s"]:
                fastest[row["renderer"]] = row
    print()
    for renderer in ("mitsuba", "aamap path"):
        best = fastest.get(renderer)
        print(f"fastest to <= {args.target} % ({renderer}): " +
              (f"{best['setting']}, {best['median_s']:.2f} s, {best['pct_error_flip']:.2f} %" if best else "none"))
    if len(fastest) == 2:
        print(f"mitsuba / aamap time to <= {args.target} %: "
              f"{fastest['mitsuba']['median_s'] / fastest['aamap path']['median_s']:.2f}")
    if args.json:
        tmp_json = args.json + ".tmp"
        with open(tmp_json, "w") as f:
            json.dump({"scene": os.path.abspath(args.scene), "size": args.size, "depth": args.depth,
                       "filter": args.filter, "filter_mode": args.filter_mode,
                       "reference_spp": args.reference_spp, "target": args.target,
                       "mitsuba": mi.__version__, "rows": rows}, f, indent=2)
        os.replace(tmp_json, args.json)


if __name__ == "__main__":
    main()
