#!/usr/bin/env python3
"""Conformance of aamap's path mode with Mitsuba 3, one scene feature at a time.

Each scene in bench/peers/conformance/ exercises one feature with tiny procedural geometry
(constant sky, a rotated and scaled envmap, a room lit through an opening, dielectric and
thindielectric panes, directional, rectangle and sphere emitters, bitmap textures in sRGB and raw,
a Mitsuba 0.5 file, the materials of furnished interiors, serialized meshes with hidden emitters,
blendbsdf, normal and bump maps, a textured roughness, and all of them in one furnished room lit
through a glazed window). Both renderers render it at the same
size, spp and path depth (the file's max_depth) with a box pixel filter: Mitsuba 3 in llvm_ad_rgb,
aamap with bench_tracer in path mode. One line per scene: the mean linear RGB of each, aamap /
Mitsuba per channel, the LDR (clamped sRGB, 0-255) mean absolute difference, the LDR-FLIP mean
(flip-evaluator), and the standard
error of Mitsuba's mean (from two half renders with different seeds) so that a ratio can be told
from noise. Not part of the test suite; Mitsuba is a peer, never a dependency.

Setup as bench/peers/mitsuba_throughput.py (libllvm19 from apt, .venv/bin/pip install
mitsuba==3.6.4), then
    .venv/bin/python bench/peers/mitsuba_conformance.py [--only c_room_opening,e_room_thindielectric]
        [--bench build/release/bench/tracer/bench_tracer] [--spp-scale 2] [--keep OUTDIR]

The scenes' maps (sky.exr: a sky gradient, a dark ground and a soft "sun"; checker.png; leaf.png;
normal.png, a grid of domes; height.png, ripples; roughness.png, a ramp) are written next to them
on the first run (--make-assets rewrites them).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_throughput import film_aspect, load_mitsuba, mitsuba_scene_file  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES_DIR = os.path.join(HERE, "conformance")

# name: (size, spp). spp is a perfect square (aamap renders n x n strata per pixel).
SCENES = {
    "a_constant_box": (64, 256),
    "b_envmap_rotated": (64, 256),
    "c_room_opening": (64, 1024),
    "d_room_dielectric": (64, 1024),
    "d2_room_dielectric_sheet": (64, 1024),
    "e_room_thindielectric": (64, 1024),
    "f_directional": (64, 256),
    "g_area_rectangle": (64, 256),
    "h_sphere_emitter": (64, 256),
    "i_bitmap_srgb": (64, 64),
    "i2_bitmap_raw": (64, 64),
    "j_room_v05": (64, 1024),
    "k_roughplastic": (64, 256),
    "l_roughconductor": (64, 256),
    "m_mask_leaf": (64, 256),
    "n_onesided_back": (64, 64),
    "o_glass_sphere": (64, 1024),
    "p_roughconductor_aniso": (64, 256),
    "q_beckmann_plastic_gold": (64, 256),
    "r_roughdielectric": (64, 1024),
    "s_serialized_hidden_sky": (64, 256),
    "t_blendbsdf": (64, 256),
    "s_normalmap": (64, 256),
    "t_bumpmap": (64, 256),
    "u_roughness_texture": (64, 256),
    "v_furnished_room": (128, 1024),
}

# The sky's sun, in world space: up 38.7 degrees, towards -z (through the rooms' window), and the
# envmap's to_world in the scenes (a rotation of 70 degrees about +y).
SUN_WORLD = (0.0, 0.8, -1.0)
ENV_ROTATE_Y_DEG = 70.0


def make_assets(mi, force):
    import numpy as np

    sky = os.path.join(SCENES_DIR, "sky.exr")
    if force or not os.path.exists(sky):
        w, h = 128, 64
        u = (np.arange(w) + 0.5) / w
        v = (np.arange(h) + 0.5) / h
        phi, theta = np.meshgrid(2 * np.pi * u, np.pi * v)
        # Mitsuba's lat-long convention (envmap.cpp): d = (sin phi sin theta, cos theta, -cos phi sin theta)
        d = np.stack([np.sin(phi) * np.sin(theta), np.cos(theta), -np.cos(phi) * np.sin(theta)], -1)
        a = math.radians(ENV_ROTATE_Y_DEG)
        rot = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
        sun_world = np.array(SUN_WORLD) / np.linalg.norm(SUN_WORLD)
        sun_local = rot.T @ sun_world
        t = np.clip(d[..., 1], 0, 1)[..., None]
        horizon, zenith = np.array([0.9, 0.85, 0.75]), np.array([0.25, 0.45, 0.95])
        sky_rgb = horizon * (1 - t) + zenith * t
        # an azimuthal variation, so that a turned map shows
        sky_rgb = sky_rgb * (1.0 + 0.4 * np.cos(phi - 1.0))[..., None]
        ground = np.array([0.12, 0.10, 0.08])
        img = np.where(d[..., 1:2] > 0, sky_rgb, ground)
        ang = np.arccos(np.clip(d @ sun_local, -1, 1))
        sigma = math.radians(6.0)
        img = img + 100.0 * np.exp(-0.5 * (ang / sigma) ** 2)[..., None] * np.array([1.0, 0.9, 0.75])
        mi.Bitmap(img.astype(np.float32)).write(sky)
    from PIL import Image  # matplotlib's dependency, in the venv

    checker = os.path.join(SCENES_DIR, "checker.png")
    if force or not os.path.exists(checker):
        n = 64
        y, x = np.mgrid[0:n, 0:n]
        check = ((x // 8 + y // 8) % 2)[..., None]
        ramp = (x / (n - 1))[..., None]
        c0 = np.array([200, 80, 40]) * (0.6 + 0.4 * ramp)
        c1 = np.array([40, 120, 220]) * (1.0 - 0.5 * ramp)
        Image.fromarray(np.where(check == 1, c0, c1).round().astype(np.uint8), "RGB").save(checker)
    leaf = os.path.join(SCENES_DIR, "leaf.png")
    if force or not os.path.exists(leaf):
        n = 64
        y, x = (np.mgrid[0:n, 0:n] + 0.5) / n * 2 - 1
        inside = (x / 0.9) ** 2 + (y / 0.45) ** 2 < 1.0  # an ellipse
        inside &= ~((np.abs(y) < 0.04) & (x > -0.8))      # a cut along the vein
        Image.fromarray((inside * 255).astype(np.uint8), "L").save(leaf)
    normal = os.path.join(SCENES_DIR, "normal.png")
    if force or not os.path.exists(normal):
        # A 4 x 4 grid of domes: in each cell the normal of a sphere cap, tilting up to 40 degrees at
        # its rim, flat between the domes; tangent-space xyz stored as (n + 1) / 2 (raw).
        n, cells = 64, 4
        y, x = (np.mgrid[0:n, 0:n] + 0.5) / (n / cells) % 1.0 * 2 - 1
        r = np.sqrt(x * x + y * y)
        tilt = np.where(r < 1.0, np.radians(40.0) * r, 0.0)
        scale = np.where(r > 0, np.sin(tilt) / np.maximum(r, 1e-9), 0.0)
        nrm = np.stack([x * scale, y * scale, np.cos(tilt)], -1)
        Image.fromarray(((nrm + 1) * 0.5 * 255).round().astype(np.uint8), "RGB").save(normal)
    height = os.path.join(SCENES_DIR, "height.png")
    if force or not os.path.exists(height):
        # Ripples: 3 periods across u times 2 across v, grey (raw).
        n = 64
        v, u = (np.mgrid[0:n, 0:n] + 0.5) / n
        h = 0.5 + 0.5 * np.sin(2 * np.pi * 3 * u) * np.cos(2 * np.pi * 2 * v)
        Image.fromarray((h * 255).round().astype(np.uint8), "L").save(height)
    roughness = os.path.join(SCENES_DIR, "roughness.png")
    if force or not os.path.exists(roughness):
        # A roughness ramp along u, modulated along v: alpha 0.05 to 0.55, grey (raw).
        n = 64
        v, u = (np.mgrid[0:n, 0:n] + 0.5) / n
        a = 0.05 + 0.5 * u * (0.5 + 0.5 * np.cos(2 * np.pi * v))
        Image.fromarray((a * 255).round().astype(np.uint8), "L").save(roughness)
    make_serialized(force)


def write_serialized(path, meshes):
    """Mitsuba's .serialized format, version 4: per mesh the header (0x041C, 4) and a zlib stream of
    flags, name, counts, positions, optional normals and uvs, and triangles; then every mesh's
    offset and the count. meshes: dicts of numpy arrays p (V x 3), n (V x 3 or None), uv (V x 2 or
    None), f (F x 3), and double (bool)."""
    import struct
    import zlib

    import numpy as np

    out, offsets = bytearray(), []
    for m in meshes:
        offsets.append(len(out))
        out += struct.pack("<HH", 0x041C, 4)
        dt = "<f8" if m["double"] else "<f4"
        flags = (0x1 if m["n"] is not None else 0) | (0x2 if m["uv"] is not None else 0) | (0x2000 if m["double"] else 0x1000)
        raw = struct.pack("<I", flags) + b"mesh\0" + struct.pack("<QQ", len(m["p"]), len(m["f"]))
        for key in ("p", "n", "uv"):
            if m[key] is not None:
                raw += np.ascontiguousarray(m[key], dtype=dt).tobytes()
        raw += np.ascontiguousarray(m["f"], dtype="<u4").tobytes()
        out += zlib.compress(raw)
    for o in offsets:
        out += struct.pack("<Q", o)
    out += struct.pack("<I", len(meshes))
    with open(path, "wb") as f:
        f.write(bytes(out))


def make_serialized(force):
    """meshes.serialized: mesh 0 a coarse sphere without normals (both renderers compute them),
    single precision; mesh 1 a torus with normals and uvs, double precision."""
    import numpy as np

    path = os.path.join(SCENES_DIR, "meshes.serialized")
    if not force and os.path.exists(path):
        return

    def grid(nu, nv, point, normal):
        u, v = np.meshgrid(np.arange(nu + 1) / nu, np.arange(nv + 1) / nv)
        p = point(u.ravel(), v.ravel())
        n = normal(u.ravel(), v.ravel()) if normal else None
        idx = np.arange((nu + 1) * (nv + 1)).reshape(nv + 1, nu + 1)
        a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
        f = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
        # Wound counter-clockwise seen from outside (away from the centre): the front is outside.
        e = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
        outward = np.einsum("ij,ij->i", e, normal(u.ravel(), v.ravel())[f[:, 0]] if normal else p[f[:, 0]])
        f[outward < 0] = f[outward < 0][:, [0, 2, 1]]
        return p, n, np.stack([u.ravel(), v.ravel()], 1), f

    def sphere_point(u, v):
        th, ph = np.pi * v, 2 * np.pi * u
        return np.stack([np.sin(th) * np.cos(ph), np.cos(th), -np.sin(th) * np.sin(ph)], 1)

    sp, _, _, sf = grid(12, 8, sphere_point, None)
    R, r = 0.6, 0.25

    def torus_point(u, v):
        a, b = 2 * np.pi * u, -2 * np.pi * v
        return np.stack([(R + r * np.cos(b)) * np.cos(a), r * np.sin(b), -(R + r * np.cos(b)) * np.sin(a)], 1)

    def torus_normal(u, v):
        a, b = 2 * np.pi * u, -2 * np.pi * v
        return np.stack([np.cos(b) * np.cos(a), np.sin(b), -np.cos(b) * np.sin(a)], 1)

    tp, tn, tuv, tf = grid(48, 24, torus_point, torus_normal)
    write_serialized(path, [dict(p=sp, n=None, uv=None, f=sf, double=False),
                            dict(p=tp, n=tn, uv=tuv, f=tf, double=True)])


def scene_depth(path):
    integrator = ET.parse(path).getroot().find("integrator")
    for child in integrator if integrator is not None else []:
        if child.attrib.get("name") in ("max_depth", "maxDepth"):
            return int(child.attrib["value"])
    return 5


def ldr_flip(reference_exr, test_exr):
    """LDR-FLIP mean of two linear EXRs (flip-evaluator, from tools/python-env.sh); nan without it."""
    try:
        import flip_evaluator as flip
    except ImportError:
        return float("nan")
    _, mean, _ = flip.evaluate(reference_exr, test_exr, "LDR", applyMagma=False)
    return float(mean)


def ldr(img):
    import numpy as np

    c = np.clip(img, 0.0, 1.0)
    return 255.0 * np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def main():
    repo = os.path.dirname(os.path.dirname(HERE))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", help="comma-separated scene names (default: all)")
    ap.add_argument("--scene", action="append", default=[],
                    help="a whole Mitsuba scene file to compare (repeatable); renders only these")
    ap.add_argument("--size", type=int, default=128, help="--scene: image width and height")
    ap.add_argument("--spp", type=int, default=256, help="--scene: samples per pixel (a perfect square)")
    ap.add_argument("--bench", default=os.path.join(repo, "build", "release", "bench", "tracer", "bench_tracer"))
    ap.add_argument("--spp-scale", type=int, default=1, help="multiply every scene's spp by this square (1, 4, ...)")
    ap.add_argument("--make-assets", action="store_true", help="rewrite sky.exr and the PNG maps")
    ap.add_argument("--keep", help="write both renders of each scene here (EXR)")
    ap.add_argument("--json", help="write one row per scene here (tools/results_tables.py reads it)")
    args = ap.parse_args()
    if not os.path.exists(args.bench):
        sys.exit(f"{args.bench}: build it first (cmake --build --preset release), or pass --bench")
    # Whole scene files beside the one-feature ones: each at --size and --spp, its own max_depth.
    for extra in args.scene:
        SCENES[extra] = (args.size, args.spp)
    names = args.only.split(",") if args.only else (list(args.scene) if args.scene else list(SCENES))
    for n in names:
        if n not in SCENES and n not in args.scene:
            sys.exit(f"unknown scene {n} (have: {', '.join(SCENES)})")
    mi, _ = load_mitsuba(os.path.join(SCENES_DIR, "a_constant_box.xml"))
    for extra in args.scene:  # their meshes and textures, relative to their own folders
        mi.Thread.thread().file_resolver().append(os.path.dirname(os.path.abspath(extra)))
    import numpy as np

    make_assets(mi, args.make_assets)
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
    rows = []
    failed = []
    print(f"mitsuba {mi.__version__} llvm_ad_rgb vs aamap path mode ({args.bench}); box filter, "
          f"same size/spp/max_depth", flush=True)
    header = (f"{'scene':<26} {'size':>4} {'spp':>5} {'dep':>3}  {'mitsuba mean rgb':<26} {'aamap mean rgb':<26} "
              f"{'aamap/mitsuba':<22} {'LDR |d|':>7} {'FLIP':>6} {'noise %':>7}")
    for name in names:
        size, spp = SCENES[name]
        spp *= args.spp_scale
        strata = round(math.sqrt(spp))
        if strata * strata != spp:
            sys.exit(f"{name}: spp {spp} is not a perfect square")
        path = name if name in args.scene else os.path.join(SCENES_DIR, name + ".xml")
        depth = scene_depth(path)
        with tempfile.TemporaryDirectory() as tmp:
            t0 = time.perf_counter()
            # A scene whose film is not square (a whole scene file, the furnished room) keeps its
            # aspect ratio: aamap fits its view in size x size, as `aamap run` does.
            whole = name in args.scene or film_aspect(path) != 1.0
            height = max(1, round(size * film_aspect(path))) if whole else size
            scene = mi.load_file(mitsuba_scene_file(path, size, spp, depth, "box", tmp, height))
            halves = [np.array(mi.render(scene, spp=spp // 2, seed=seed))[:, :, :3].astype(np.float64)
                      for seed in (0, 1)]
            t_mi = time.perf_counter() - t0
            ref = 0.5 * (halves[0] + halves[1])
            # Standard error of the image mean: pixels are independent, each half's noise is (a - b) / 2.
            se = np.sqrt(((halves[0] - halves[1]) ** 2 / 4.0).reshape(-1, 3).mean(0) / (size * height))
            exr = os.path.join(tmp, "aamap.exr")
            aamap_scene = path
            t0 = time.perf_counter()
            r = subprocess.run([args.bench, "--scene", aamap_scene, "--size", str(size), "--strata", str(strata), "--mode",
                                "path", "--max-depth", str(depth), "--light-samples", "1", "--repeat", "1",
                                "--out", exr] + (["--fit-view"] if whole else []), capture_output=True, text=True)
            t_aa = time.perf_counter() - t0
            if r.returncode != 0:
                print(f"{name}: bench_tracer failed ({r.returncode}):\n{r.stderr[-2000:]}", file=sys.stderr)
                failed.append(name)
                continue
            img = np.array(mi.Bitmap(exr))[:, :, :3].astype(np.float64)
            ref_exr = os.path.join(tmp, "mitsuba.exr")
            mi.Bitmap(ref.astype(np.float32)).write(ref_exr)
            flip_mean = ldr_flip(ref_exr, exr)
            if args.keep:  # a whole scene file by its folder's name: never beside the scene itself
                stem = os.path.basename(os.path.dirname(os.path.abspath(name))) if name in args.scene else name
                mi.Bitmap(ref.astype(np.float32)).write(os.path.join(args.keep, f"{stem}.mitsuba.exr"))
                mi.Bitmap(img.astype(np.float32)).write(os.path.join(args.keep, f"{stem}.aamap.exr"))
        m_ref, m_img = ref.reshape(-1, 3).mean(0), img.reshape(-1, 3).mean(0)
        ratio = m_img / np.maximum(m_ref, 1e-12)
        dldr = np.abs(ldr(img) - ldr(ref)).mean()
        noise = 100.0 * (se / np.maximum(m_ref, 1e-12)).max()
        rows.append((name, size, spp, depth, m_ref, m_img, ratio, dldr, noise, flip_mean))
        flag = "  <--" if np.any(np.abs(ratio - 1.0) > 0.02) else ""
        if len(rows) == 1:
            print(header)
        label = os.path.relpath(name, os.path.dirname(os.path.dirname(name))) if name in args.scene else name
        print(f"{label:<26} {size:>4} {spp:>5} {depth:>3}  {m_ref[0]:.4f} {m_ref[1]:.4f} {m_ref[2]:.4f}    "
              f"{m_img[0]:.4f} {m_img[1]:.4f} {m_img[2]:.4f}    {ratio[0]:.3f} {ratio[1]:.3f} {ratio[2]:.3f}   "
              f"{dldr:7.2f} {flip_mean:6.3f} {noise:7.2f}{flag}   ({t_mi:.0f} s / {t_aa:.0f} s)", flush=True)
    bad = [r[0] for r in rows if np.any(np.abs(r[6] - 1.0) > 0.02)]
    print(f"{len(rows)} scenes; off by more than 2 % in a channel: {', '.join(bad) if bad else 'none'}"
          + (f"; failed to render: {', '.join(failed)}" if failed else ""))
    if args.json:
        out = [{"scene": r[0], "size": r[1], "spp": r[2], "depth": r[3], "mitsuba": list(map(float, r[4])),
                "aamap": list(map(float, r[5])), "ratio": list(map(float, r[6])), "ldr_abs_diff": float(r[7]),
                "noise": float(r[8]) / 100.0, "flip_mean": float(r[9])} for r in rows]
        tmp = args.json + ".tmp"
        with open(tmp, "w") as f:
            json.dump({"mitsuba": mi.__version__, "rows": out}, f, indent=2)
        os.replace(tmp, args.json)
    if failed:
        sys.exit(1)


if __name__ == "__main__":
    main()
