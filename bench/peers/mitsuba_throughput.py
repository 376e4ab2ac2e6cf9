#!/usr/bin/env python3
"""Path-tracing throughput of aamap against Mitsuba 3 on the same machine, scene and settings.

Both render the same Mitsuba scene file (aamap reads Mitsuba XML) at the same resolution, samples
per pixel and maximum path depth, in interleaved rounds (Mitsuba, aamap, Mitsuba, aamap, ...) so
that the machine's drift hits both alike. Mitsuba runs its LLVM variant (llvm_ad_rgb) with its
kernels compiled once before the timed rounds; aamap runs bench_tracer in path mode with one light
sample per hit, as Mitsuba's path integrator takes one emitter sample per bounce, and samples the
lights by area as Mitsuba does for meshes (aamap's default in path mode; --light-sampling solid_angle
times the other choice).

Setup (not part of the test suite):
    apt-get install -y libllvm19             # Dr.Jit's LLVM backend
    .venv/bin/pip install mitsuba==3.6.4
    .venv/bin/python bench/peers/mitsuba_throughput.py [--scene ../shared/scenes/mitsuba-cbox/scene.xml]

Prints one line per round and the median ratio with its spread; --json writes them to a file.
"""
import argparse
import glob
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET


def find_libllvm():
    for pattern in ("/usr/lib/x86_64-linux-gnu/libLLVM-19.so*", "/usr/lib/llvm-19/lib/libLLVM*.so*",
                    "/usr/lib/x86_64-linux-gnu/libLLVM*.so*"):
        found = sorted(glob.glob(pattern))
        if found:
            return found[0]
    return None


def load_mitsuba(scene, variant="llvm_ad_rgb"):
    """Mitsuba 3 and Dr.Jit in `variant`, resolving files next to `scene`; exits with the setup
    step that is missing."""
    if not os.path.exists(scene):
        sys.exit(f"{scene}: no such scene")
    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        lib = find_libllvm()
        if lib is None:
            sys.exit("no libLLVM found: apt-get install -y libllvm19, or set DRJIT_LIBLLVM_PATH")
        os.environ["DRJIT_LIBLLVM_PATH"] = lib
    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError:
        sys.exit("no mitsuba module: .venv/bin/pip install mitsuba==3.6.4")
    mi.set_variant(variant)
    mi.Thread.thread().file_resolver().append(os.path.dirname(os.path.abspath(scene)))
    return mi, dr


def film_aspect(scene):
    """The film's height / width as the scene file gives it (1 without one)."""
    sensor = ET.parse(scene).getroot().find("sensor")
    film = sensor.find("film") if sensor is not None else None
    size = {c.attrib.get("name"): int(c.attrib["value"]) for c in (film if film is not None else [])
            if c.attrib.get("name") in ("width", "height")}
    return size["height"] / size["width"] if "width" in size and "height" in size else 1.0


def mitsuba_scene_file(scene, size, spp, depth, rfilter, out_dir, height=None):
    """The scene with the film size (size x height, default square), sample count, path depth and
    pixel filter replaced (the integrator becomes `path`; its hide_emitters stays)."""
    tree = ET.parse(scene)
    root = tree.getroot()
    integrator = root.find("integrator")
    if integrator is None:
        integrator = ET.SubElement(root, "integrator")
    integrator.attrib["type"] = "path"
    for child in list(integrator):
        # hide_emitters stays: aamap follows the file's, so both must render it.
        if child.attrib.get("name") not in ("hide_emitters", "hideEmitters"):
            integrator.remove(child)
    ET.SubElement(integrator, "integer", name="max_depth", value=str(depth))
    sensor = root.find("sensor")
    if sensor is None:
        sys.exit(f"{scene}: no <sensor>")
    sampler = sensor.find("sampler")
    if sampler is None:
        sampler = ET.SubElement(sensor, "sampler", type="independent")
    for child in list(sampler):
        sampler.remove(child)
    ET.SubElement(sampler, "integer", name="sample_count", value=str(spp))
    film = sensor.find("film")
    for child in list(film):
        # high_quality_edges is Mitsuba 0.6's; Mitsuba 3 refuses it.
        if child.attrib.get("name") in ("width", "height", "high_quality_edges") or child.tag == "rfilter":
            film.remove(child)
    ET.SubElement(film, "integer", name="width", value=str(size))
    ET.SubElement(film, "integer", name="height", value=str(height or size))
    ET.SubElement(film, "rfilter", type=rfilter)
    path = os.path.join(out_dir, "scene.xml")
    tree.write(path)
    return path


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=os.path.join(repo, "..", "shared", "scenes", "mitsuba-cbox", "scene.xml"))
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--spp", type=int, default=64, help="a perfect square (aamap's n x n strata)")
    ap.add_argument("--depth", type=int, default=5, help="longest path in segments, both renderers")
    ap.add_argument("--filter", default="box", choices=["box", "tent", "gaussian"],
                    help="pixel filter of both (Mitsuba's tent is aamap's tent)")
    ap.add_argument("--filter-mode", default="convolution", choices=["convolution", "importance"],
                    help="how aamap applies it (image.filter_mode; Mitsuba splats its samples)")
    ap.add_argument("--light-sampling", default="area", choices=["area", "solid_angle"],
                    help="aamap's shading.light_sampling; Mitsuba samples mesh emitters by area, so 'area' "
                         "compares the same estimator")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--bench", default=os.path.join(repo, "build", "release", "bench", "tracer", "bench_tracer"))
    ap.add_argument("--json", help="write the rounds and the summary here")
    ap.add_argument("--reference-spp", type=int, default=0,
                    help="also render Mitsuba at this many spp and print the error of its --spp image against it "
                         "(aamap diff: LDR-FLIP, %% pixels above 0.1): Mitsuba's time to that error")
    ap.add_argument("--aamap", default=os.path.join(repo, "build", "release", "aamap"))
    args = ap.parse_args()
    strata = round(args.spp ** 0.5)
    if strata * strata != args.spp:
        sys.exit(f"--spp {args.spp} is not a perfect square")
    if not os.path.exists(args.bench):
        sys.exit(f"{args.bench}: build it first (cmake --build --preset release)")
    mi, dr = load_mitsuba(args.scene)
    # The film's aspect ratio is kept: both render the same view at size x height pixels (aamap
    # fits the view in size x size, as `aamap run` does).
    height = max(1, round(args.size * film_aspect(args.scene)))
    samples = args.size * height * args.spp

    with tempfile.TemporaryDirectory() as tmp:
        scene = mi.load_file(mitsuba_scene_file(args.scene, args.size, args.spp, args.depth,
                                                "box" if args.filter == "box" else args.filter, tmp, height))

        last = {}

        def render_mitsuba():
            t0 = time.perf_counter()
            image = mi.render(scene, spp=args.spp)
            dr.eval(image)
            dr.sync_thread()
            seconds = time.perf_counter() - t0
            last["mitsuba"] = image
            return seconds

        cold = render_mitsuba()  # compiles the kernels (cached for the timed rounds)
        print(f"mitsuba {mi.__version__} llvm_ad_rgb, {args.size}x{height}, {args.spp} spp, depth {args.depth}, "
              f"{args.filter} filter; first render (kernel compilation) {cold:.2f} s", flush=True)

        aamap_exr = os.path.join(tmp, "aamap.exr")

        def render_aamap():
            out = subprocess.run([args.bench, "--scene", args.scene, "--size", str(args.size), "--strata",
                                  str(strata), "--mode", "path", "--max-depth", str(args.depth), "--light-samples",
                                  "1", "--filter", args.filter, "--filter-mode", args.filter_mode,
                                  "--light-sampling", args.light_sampling, "--repeat", "1", "--fit-view",
                                  "--out", aamap_exr],
                                 check=True, capture_output=True, text=True).stdout
            m = re.search(r"best time ([0-9.]+) s", out)
            if m is None:
                sys.exit("bench_tracer printed no time:\n" + out)
            return float(m.group(1))

        rounds = []
        for r in range(args.rounds):
            tm = render_mitsuba()
            ta = render_aamap()
            rounds.append({"mitsuba_s": tm, "aamap_s": ta, "ratio": tm / ta})
            print(f"round {r + 1}: mitsuba {tm:.2f} s ({samples / tm * 1e-6:.2f} M samples/s), "
                  f"aamap {ta:.2f} s ({samples / ta * 1e-6:.2f} M samples/s), aamap/mitsuba throughput "
                  f"{tm / ta:.2f}", flush=True)

        if args.reference_spp > 0:
            t0 = time.perf_counter()
            reference = mi.render(scene, spp=args.reference_spp)
            dr.eval(reference)
            dr.sync_thread()
            t_ref = time.perf_counter() - t0
            ref_exr, test_exr = os.path.join(tmp, "mitsuba_reference.exr"), os.path.join(tmp, "mitsuba.exr")
            mi.Bitmap(reference).write(ref_exr)
            mi.Bitmap(last["mitsuba"]).write(test_exr)
            diff = json.loads(subprocess.run([args.aamap, "diff", ref_exr, test_exr, "--json"], check=True,
                                             capture_output=True, text=True).stdout)
            print(f"mitsuba {args.spp} spp against its own {args.reference_spp}-spp reference ({t_ref:.1f} s): "
                  f"{json.dumps(diff)}")

        # The same scene? Mean radiance of the last images (both linear RGB).
        import numpy as np
        mean_m = float(np.mean(np.array(last["mitsuba"])))
        mean_a = float(np.mean(np.array(mi.Bitmap(aamap_exr))[:, :, :3]))
        print(f"mean radiance: mitsuba {mean_m:.5f}, aamap {mean_a:.5f} (aamap/mitsuba {mean_a / mean_m:.4f})")

    ratios = [r["ratio"] for r in rounds]
    summary = {"scene": os.path.abspath(args.scene), "size": args.size, "height": height, "spp": args.spp, "depth": args.depth,
               "filter": args.filter, "filter_mode": args.filter_mode, "mitsuba": mi.__version__,
               "mitsuba_first_render_s": cold,
               "mean_radiance": {"mitsuba": mean_m, "aamap": mean_a},
               "median_throughput_ratio": statistics.median(ratios), "min_ratio": min(ratios),
               "max_ratio": max(ratios), "rounds": rounds}
    print(f"aamap/mitsuba throughput: median {summary['median_throughput_ratio']:.2f} "
          f"(range {min(ratios):.2f}-{max(ratios):.2f} over {len(ratios)} rounds)")
    if args.json:
        tmp = args.json + ".tmp"
        with open(tmp, "w") as f:
            json.dump(summary, f, indent=2)
        os.replace(tmp, args.json)


if __name__ == "__main__":
    main()
