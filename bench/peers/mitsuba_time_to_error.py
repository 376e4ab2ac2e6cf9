#!/usr/bin/env python3
"""Time to an error level: aamap's path mode against Mitsuba 3 on the same machine and scene.

Each renderer is measured against its own converged reference, and both against one common
reference (--common-reference: Mitsuba's or aamap's --reference-spp render, said in the output),
which shows a renderer's bias as well as its noise; the mean per channel of every image over the
common reference's says how much of the error is bias. Mitsuba 3 (llvm_ad_rgb, path integrator)
renders a ladder of samples per pixel and its --reference-spp image; aamap runs one experiment in
path mode with uniform and variance-driven renders at a ladder of rays per pixel and its own
path-traced reference of --reference-spp. Both use the same maximum path depth and pixel filter,
and the same error measure (aamap's LDR-FLIP: % pixels above 0.1, through `aamap diff` for
Mitsuba's images). The timed renders run in interleaved rounds (Mitsuba's ladder, then aamap's
experiment, again ...): aamap's later rounds reuse its first reference as a file and trace every
render again. Prints each setting's median time, its spread and its error, and the fastest setting
of each renderer at or below --target % pixels in error.

Both render at the film's aspect ratio (--size is the width), so a scene such as the Modern Hall
(`--scene ../shared/scenes/modern-hall/scene.xml --depth 65`) keeps its framing.

Setup as bench/peers/mitsuba_throughput.py (libllvm19, pip mitsuba==3.6.4 in .venv), then
    .venv/bin/python bench/peers/mitsuba_time_to_error.py [--size 256] [--filter gaussian]
        [--filter-mode convolution] [--common-reference mitsuba] [--reference-spp 4096]
        [--cache-rpp 16,64 [--cache-bounces 3]]   # and cache mode (its pre-pass in its time)
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
from mitsuba_throughput import film_aspect, load_mitsuba, mitsuba_scene_file  # noqa: E402


def ladder(text):
    values = [int(v) for v in text.split(",") if v]
    for v in values:
        if round(v ** 0.5) ** 2 != v:
            sys.exit(f"{v}: not a perfect square (aamap's n x n strata)")
    return values


def aamap_config(scene, size, height, depth, rfilter, filter_mode, uniform, variance, thresholds, min_samples, reference,
                 light_sampling, cache_bounces=None):
    """The experiment: path mode with one light sample per hit (as Mitsuba's one emitter sample per
    bounce), Russian roulette from depth 5 on as Mitsuba's default rr_depth. With cache_bounces,
    cache mode instead: that many bounces through the irradiance cache (the light transport of
    path mode's max_depth cache_bounces + 2) and its default light samples per hit."""
    renders = [f'  - {{name: "uniform{{rpp}}", series: Uniform, strategy: uniform, rpp: {json.dumps(uniform)}}}']
    if variance:
        renders.append(f'  - {{name: "variance{{rpp}}_t{{noise_threshold}}", series: "Variance {{noise_threshold}}", '
                       f'strategy: variance, rpp: {json.dumps(variance)}, noise_threshold: {json.dumps(thresholds)}, '
                       f'min_samples: {min_samples}, sample_step: 8}}')
    return "\n".join([
        f"scene: {json.dumps(os.path.abspath(scene))}",
        f"image: {{width: {size}, height: {height}, filter: {rfilter}, filter_mode: {filter_mode}}}",
        (f"shading: {{mode: path, max_depth: {depth}, area_light_samples: 1, light_sampling: {light_sampling}}}"
         if cache_bounces is None else
         f"shading: {{mode: cache, max_depth: {depth}, light_sampling: {light_sampling}, cache: {{bounces: {cache_bounces}}}}}"),
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
    ap.add_argument("--cache-rpp", type=ladder, default=[],
                    help="also aamap's cache mode, uniform at these rpp, against aamap's path reference "
                         "(default: none)")
    ap.add_argument("--cache-bounces", type=int, default=None,
                    help="cache mode's bounces (default --depth - 2: the same light transport)")
    ap.add_argument("--reference-spp", type=int, default=1024, help="each renderer's own reference")
    ap.add_argument("--common-reference", default="mitsuba", choices=["mitsuba", "aamap"],
                    help="whose --reference-spp render every image is also measured against")
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
    import numpy as np
    height = max(1, round(args.size * film_aspect(args.scene)))
    # aamap's reference.rpp stops at 1024: a larger --reference-spp is Mitsuba's alone.
    aamap_reference_spp = min(args.reference_spp, 1024)
    cache_bounces = args.cache_bounces if args.cache_bounces is not None else args.depth - 2
    if args.cache_rpp and not 0 <= cache_bounces <= 16:
        sys.exit(f"--cache-bounces {cache_bounces}: not in [0, 16] (give it, or a --depth in [2, 18])")

    def diff(reference, test):
        return json.loads(subprocess.run([args.aamap, "diff", reference, test, "--json"], check=True,
                                         capture_output=True, text=True).stdout)

    def channel_means(path):
        return np.array(mi.Bitmap(path))[:, :, :3].astype(np.float64).reshape(-1, 3).mean(0)

    times = {}  # (renderer, setting) -> [seconds per round]
    errors = {}  # (renderer, setting) -> aamap diff / results.json metrics
    common = {}  # (renderer, setting) -> aamap diff against the common reference, with channel ratios
    with tempfile.TemporaryDirectory() as tmp:
        scene = mi.load_file(mitsuba_scene_file(args.scene, args.size, args.reference_spp, args.depth, args.filter, tmp,
                                                height))

        def render(spp):
            t0 = time.perf_counter()
            image = mi.render(scene, spp=spp)
            dr.eval(image)
            dr.sync_thread()
            return image, time.perf_counter() - t0

        reference, t_ref = render(args.reference_spp)  # also compiles the kernels
        mitsuba_ref = os.path.join(tmp, "mitsuba_reference.exr")
        mi.Bitmap(reference).write(mitsuba_ref)
        print(f"mitsuba {mi.__version__} llvm_ad_rgb, {args.size}x{height}, depth {args.depth}, {args.filter} "
              f"filter; reference {args.reference_spp} spp in {t_ref:.1f} s", flush=True)
        for spp in args.mitsuba_spp:
            render(spp)  # kernels for every sample count before the timed rounds

        aamap_ref = os.path.join(tmp, "aamap_reference.exr")

        def run_aamap(name, renderer, r, config_text):
            """One `aamap run` of config_text: each render's trace time (the cache's pre-pass
            included: Tracer::render builds the cache first) and metrics under (renderer, render);
            the first round keeps the images, and the reference as aamap_ref."""
            config = os.path.join(tmp, name + ".yaml")
            with open(config, "w") as f:
                f.write(config_text)
            out = os.path.join(tmp, name)
            subprocess.run([args.aamap, "run", config, "-o", out, "--no-plots"], check=True, capture_output=True)
            with open(os.path.join(out, "results.json")) as f:
                results = json.load(f)
            if r == 0 and not os.path.exists(aamap_ref):
                os.replace(os.path.join(out, "reference.exr"), aamap_ref)
            for rec in results["renders"]:
                key = (renderer, rec["name"])
                times.setdefault(key, []).append(rec["times_s"]["trace"])
                errors[key] = dict(rec["metrics"], mean_rpp=rec["mean_primary_rpp"])
                if r == 0:
                    kept = os.path.join(tmp, f"{name}_{rec['name']}.exr")
                    os.replace(os.path.join(out, rec["name"] + ".exr"), kept)
                    aamap_images[key] = kept

        mitsuba_images = {}  # spp -> EXR of the first round
        aamap_images = {}  # (renderer, render name) -> EXR of the first round
        for r in range(args.rounds):
            for spp in args.mitsuba_spp:
                image, seconds = render(spp)
                times.setdefault(("mitsuba", f"{spp} spp"), []).append(seconds)
                if r == 0:
                    test = os.path.join(tmp, f"mitsuba_{spp}.exr")
                    mi.Bitmap(image).write(test)
                    errors[("mitsuba", f"{spp} spp")] = diff(mitsuba_ref, test)
                    mitsuba_images[spp] = test
            reference_yaml = (f"{{type: uniform, mode: path, rpp: {aamap_reference_spp}}}" if r == 0
                              else f"{{type: file, path: {json.dumps(aamap_ref)}}}")
            run_aamap(f"aamap_{r}", "aamap path", r,
                      aamap_config(args.scene, args.size, height, args.depth, args.filter, args.filter_mode,
                                   args.uniform_rpp, args.variance_rpp,
                                   [float(t) for t in args.variance_threshold.split(",") if t],
                                   args.variance_min_samples, reference_yaml, args.light_sampling))
            if args.cache_rpp:  # against aamap's path reference, traced in the first round above
                run_aamap(f"aamap_cache_{r}", "aamap cache", r,
                          aamap_config(args.scene, args.size, height, args.depth, args.filter, args.filter_mode,
                                       args.cache_rpp, [], [], args.variance_min_samples,
                                       f"{{type: file, path: {json.dumps(aamap_ref)}}}", args.light_sampling,
                                       cache_bounces))
            done = ", ".join(f"{k[0]} {k[1]} {v[-1]:.2f} s" for k, v in times.items())
            print(f"round {r + 1}: {done}", flush=True)

        # One reference for both: every first-round image against it, with its channel means.
        common_ref = mitsuba_ref if args.common_reference == "mitsuba" else aamap_ref
        ref_means = channel_means(common_ref)
        images = [(("mitsuba", f"{spp} spp"), p) for spp, p in mitsuba_images.items()]
        images += list(aamap_images.items())
        other_ref = aamap_ref if args.common_reference == "mitsuba" else mitsuba_ref
        images.append(((("aamap path" if args.common_reference == "mitsuba" else "mitsuba"),
                        f"reference {aamap_reference_spp if args.common_reference == 'mitsuba' else args.reference_spp}"),
                       other_ref))
        for key, path in images:
            common[key] = dict(diff(common_ref, path), ratio=list(channel_means(path) / np.maximum(ref_means, 1e-12)))

    rows = []
    for key, ts in times.items():
        e = errors[key]
        spp = e.get("mean_rpp", int(key[1].split()[0]) if key[0] == "mitsuba" else 0)
        c = common.get(key, {})
        rows.append({"renderer": key[0], "setting": key[1], "mean_spp": spp, "median_s": statistics.median(ts),
                     "min_s": min(ts), "max_s": max(ts), "pct_error_flip": e["pct_error_flip"],
                     "flip_mean": e["flip_mean"], "common_pct_error_flip": c.get("pct_error_flip"),
                     "common_flip_mean": c.get("flip_mean"), "common_channel_ratio": c.get("ratio")})
    print(f"\nown: each against its own reference (Mitsuba {args.reference_spp} spp, aamap {aamap_reference_spp} rpp); "
          f"common: against "
          f"{args.common_reference}'s, with the image's mean per channel over the reference's")
    print(f"{'renderer':<12} {'setting':<20} {'mean spp':>8} {'median s':>9} {'range s':>13} {'own %>0.1':>9} "
          f"{'own FLIP':>9} {'common %':>9} {'common FLIP':>11}  mean r/g/b ratio")
    for row in rows:
        ratio = row["common_channel_ratio"]
        print(f"{row['renderer']:<12} {row['setting']:<20} {row['mean_spp']:8.1f} {row['median_s']:9.2f} "
              f"{row['min_s']:6.2f}-{row['max_s']:<6.2f} {row['pct_error_flip']:9.2f} {row['flip_mean']:9.4f} "
              f"{row['common_pct_error_flip'] if row['common_pct_error_flip'] is not None else float('nan'):9.2f} "
              f"{row['common_flip_mean'] if row['common_flip_mean'] is not None else float('nan'):11.4f}  "
              + (" ".join(f"{x:.4f}" for x in ratio) if ratio else ""))
    for key, c in common.items():
        if key[1].startswith("reference"):
            print(f"{key[0]} {key[1]} against {args.common_reference}'s: {c['pct_error_flip']:.2f} % > 0.1, "
                  f"FLIP mean {c['flip_mean']:.4f}, mean r/g/b ratio " + " ".join(f"{x:.4f}" for x in c["ratio"]))
    print()
    for measure, label in (("pct_error_flip", "own reference"), ("common_pct_error_flip",
                                                                 f"{args.common_reference}'s reference")):
        fastest = {}
        for row in rows:
            if row[measure] is not None and row[measure] <= args.target:
                best = fastest.get(row["renderer"])
                if best is None or row["median_s"] < best["median_s"]:
                    fastest[row["renderer"]] = row
        for renderer in ("mitsuba", "aamap path") + (("aamap cache",) if args.cache_rpp else ()):
            best = fastest.get(renderer)
            print(f"fastest to <= {args.target} % against {label} ({renderer}): " +
                  (f"{best['setting']}, {best['median_s']:.2f} s, {best[measure]:.2f} %" if best else "none"))
        for renderer in ("aamap path", "aamap cache"):
            if "mitsuba" in fastest and renderer in fastest:
                print(f"mitsuba / {renderer} time to <= {args.target} % against {label}: "
                      f"{fastest['mitsuba']['median_s'] / fastest[renderer]['median_s']:.2f}")
    if args.json:
        tmp_json = args.json + ".tmp"
        with open(tmp_json, "w") as f:
            json.dump({"scene": os.path.abspath(args.scene), "size": args.size, "depth": args.depth,
                       "filter": args.filter, "filter_mode": args.filter_mode,
                       "reference_spp": args.reference_spp, "common_reference": args.common_reference,
                       "target": args.target, "height": height,
                       "mitsuba": mi.__version__, "rows": rows}, f, indent=2)
        os.replace(tmp_json, args.json)


if __name__ == "__main__":
    main()
