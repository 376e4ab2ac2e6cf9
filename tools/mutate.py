#!/usr/bin/env python3
"""Mutation run: does the test suite catch the bugs users would suffer?

Each mutant is one realistic bug (a line deleted, an index swapped, a comparison off by one) given
as file, exact original snippet, replacement and the smallest ctest regex whose tests should catch
it. The run applies one mutant at a time to a scratch copy of the tree, rebuilds (incrementally,
through ccache), runs the mutant's tests, restores the file, and prints a table and the kill ratio.
A mutant the tests do not catch is a "survivor": either a missing test, or an equivalent mutant
(argued in docs/robustness.md, "Mutation testing").

Not part of CI: a full run rebuilds the tree once per mutant. Python standard library only.

  tools/mutate.py --list                       # the mutants
  tools/mutate.py                              # all, in a scratch copy under /tmp/aamap-mutate
  tools/mutate.py --only film-diagonal,seed-key
  tools/mutate.py --suite                      # each mutant against the release suite
                                               # (labels fuzz and viewer excluded) instead
  tools/mutate.py --in-place                   # mutate this tree and its build/release (the
                                               # mutated files must be committed; always restored)
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def m(ident, area, file, original, replacement, tests, what):
    return {"id": ident, "area": area, "file": file, "original": original, "replacement": replacement,
            "tests": tests, "what": what}


MUTANTS = [
    # --- tracer -----------------------------------------------------------------------------
    m("film-diagonal", "tracer", "tracer/tracer.cpp",
      "sampler.stratified2D(dims::kFilm, sx, sy, k)", "sampler.stratified2D(dims::kFilm, sx, sx, k)",
      r"^tracer\.FilmSampling", "film strata on the diagonal only: k of the k^2 cells sampled"),
    m("film-v-from-x", "tracer", "tracer/tracer.cpp",
      "const float v = (static_cast<float>(y) + j.y) * invH_;", "const float v = (static_cast<float>(y) + j.x) * invH_;",
      r"^tracer\.FilmSampling", "the film's v jitter reuses the u jitter"),
    m("pixel-mean-over-all", "tracer", "tracer/tracer.cpp",
      "        return halvesOf(sum, kept, half, halfKept);", "        return halvesOf(sum, k * k, half, halfKept);",
      r"^tracer\.FilmSampling", "dropped non-finite samples still count in the pixel mean (darkens it)"),
    m("roulette-weight", "tracer", "tracer/path_integrator.cpp",
      "        s.beta *= 1.0f / survive;\n", "",
      r"^tracer\.PathMode", "path mode: surviving paths not reweighted by 1/p (biased dark)"),
    m("roulette-depth", "tracer", "tracer/path_integrator.cpp",
      "depth + 1 >= shading_.rouletteDepth", "depth >= shading_.rouletteDepth",
      r"^tracer\.PathMode", "roulette starts one segment late"),
    m("area-light-pdf", "tracer", "tracer/direct_integrator.cpp",
      "geometry = a.inversePdf(view, cosLight, d2);", "geometry = cosLight / d2;",
      r"^tracer\.ManyLights", "many lights: an area light's sample not divided by its area pdf"),
    m("area-light-area", "tracer", "tracer/direct_integrator.cpp",
      "const float scale = (bySolidAngle ? view.solidAngle : light.area()) * invCount;",
      "const float scale = invCount;",
      r"^tracer\.KnownAnswer", "few lights: the area-light estimate not scaled by the area (or solid angle)"),
    m("emitter-back-face", "tracer", "tracer/direct_integrator.cpp",
      "if (m.emissive && hit.front && !(cameraHit && shading_.hideEmitters)) L += m.ke * emission;",
      "if (m.emissive && !(cameraHit && shading_.hideEmitters)) L += m.ke * emission;",
      r"^tracer\.KnownAnswer", "one-sided emitters glow from the back too"),
    m("strata-truncate", "tracer", "tracer/strategy.cpp",
      "k = 1 + static_cast<int>(std::lround(c * static_cast<float>(n - 1)));",
      "k = 1 + static_cast<int>(c * static_cast<float>(n - 1));",
      r"^tracer\.StrategyMapping", "aamap value to strata truncated instead of rounded"),
    m("strata-nan", "tracer", "tracer/strategy.cpp",
      "if (std::isnan(a)) return n;", "if (std::isnan(a)) return 1;",
      r"^tracer\.StrategyMapping", "an unsure (NaN) map value samples least instead of most"),
    m("stratum-upper-border", "tracer", "tracer/sampler.h",
      "        if (static_cast<double>(v) >= hi) v = std::nextafter(v, 0.0f);\n", "",
      r"^tracer\.Sampler", "a jitter rounded up onto the next stratum's border stays there"),
    m("variance-normalise", "tracer", "tracer/strategies/variance.cpp",
      "const double normalise = std::sqrt(std::max(0.0, all.x + all.y + all.z));",
      "const double normalise = std::max(0.0, all.x + all.y + all.z);",
      r"^tracer\.(Variance|Baselines)", "Cycles' error estimate normalised by the sum, not its square root"),
    m("subsample-split", "tracer", "tracer/strategies/subsample.cpp",
      "if (!(sums.sum(b.x0, b.y0, b.x1, b.y1) > threshold)) {", "if (!(sums.sum(b.x0, b.y0, b.x1, b.y1) >= threshold)) {",
      r"^tracer\.Subsample", "a block whose aamap sum equals the threshold is split"),
    m("spot-falloff", "scene", "scene/lights.h",
      "    return t * t;\n}", "    return t;\n}",
      r"^tracer\.SpotLight|^scene\.(GltfSpotLight|LightFileLights)|^SpotShading\.", "spot falloff linear instead of glTF's quadratic"),
    # --- passes (CPU reference chain) and GLSL ----------------------------------------------
    m("cpu-dead-zone", "passes", "passes/cpu_aamap.cpp",
      "o[i] = clamp01(gain * (in[i] - noiseFloor));", "o[i] = clamp01(gain * in[i]);",
      r"^Filters\.", "CPU aamap: noise floor ignored"),
    m("glsl-dead-zone", "glsl", "glsl/blur.comp",
      "precise float m = clamp(pc.gain * (b - pc.noiseFloor), 0.0, 1.0);",
      "precise float m = clamp(pc.gain * b, 0.0, 1.0);",
      r"^FilterTest\.", "GPU aamap: noise floor ignored"),
    m("glsl-blur-window", "glsl", "glsl/blur.comp",
      "if (abs(j - k) <= r) sums[k] += v;", "if (abs(j - k) < r) sums[k] += v;",
      r"^FilterTest\.", "GPU blur: the window's last rows left out"),
    m("glsl-laplacian-abs", "glsl", "glsl/laplacian.comp",
      "hi - lo >= pc.flatRange ? abs(sum) : 0.0));", "hi - lo >= pc.flatRange ? sum : 0.0));",
      r"^FilterTest\.", "GPU Laplacian: signed instead of absolute"),
    m("glsl-reduce-max", "glsl", "glsl/reduce.comp",
      "v = max(v, imageLoad(map, ivec2(i, j)).r);", "v = imageLoad(map, ivec2(i, j)).r;",
      r"^FilterTest\.", "GPU reduction: last texel instead of the max"),
    m("glsl-exposure-green", "glsl", "glsl/display_luma.glsl",
      "srgbEncode(clamp(exposure * rgb.g, 0.0, 1.0))", "srgbEncode(clamp(rgb.g, 0.0, 1.0))",
      r"^FilterTest\.", "GPU greyscale: exposure not applied to green"),
    # --- scene loaders ------------------------------------------------------------------------
    m("obj-emission-blue", "scene", "scene/obj_loader.cpp",
      "out.ke = {m.emission[0], m.emission[1], m.emission[2]};", "out.ke = {m.emission[0], m.emission[1], m.emission[0]};",
      r"^scene\.ObjLoader", "MTL Ke: blue channel read from red"),
    m("obj-mirror-illum", "scene", "scene/obj_loader.cpp",
      "if (m.illum == 3 || m.illum == 5) out.kind = MaterialKind::Mirror;",
      "if (m.illum == 3) out.kind = MaterialKind::Mirror;",
      r"^scene\.(ObjLoader|LoadScene|AlphaMaterials)", "MTL illum 5 no longer a mirror"),
    m("view-vv", "scene", "scene/view_file.cpp",
      "                v.verticalFovDeg = number(tok, i);",
      "                v.verticalFovDeg = v.horizontalFovDeg;\n                number(tok, i);",
      r"^scene\.ViewFile", "view files: -vv ignored"),
    m("view-vl-sign", "scene", "scene/view_file.cpp",
      "v.shiftY = number(tok, i);", "v.shiftY = -number(tok, i);",
      r"^scene\.ViewOptions", "view files: -vl shifts the wrong way"),
    # --- metrics ------------------------------------------------------------------------------
    m("flip-threshold-ignored", "metrics", "eval/metrics/image_comparison.cpp",
      "    fo.threshold = options.flipThreshold;\n", "",
      r"^eval\.(MetricSettings|SettingsReach)", "metrics.flip_threshold ignored: pct_error_flip always at 0.1"),
    m("flip-ppd-ignored", "metrics", "eval/metrics/image_comparison.cpp",
      "    fo.ppd = options.ppd;\n", "",
      r"^eval\.(MetricSettings|SettingsReach)", "metrics.ppd ignored"),
    m("mse-threshold-ignored", "metrics", "eval/metrics/image_comparison.cpp",
      "    po.errorThreshold = options.mseThreshold;\n", "",
      r"^eval\.(MetricSettings|SettingsReach)", "metrics.mse_threshold ignored"),
    m("mse-count-strict", "metrics", "eval/metrics/pixel_error.cpp",
      "count += e >= options.errorThreshold ? 1 : 0;", "count += e > options.errorThreshold ? 1 : 0;",
      r"^metrics\.PixelError|^eval\.MetricSettings", "a pixel exactly at the MSE threshold no longer counts"),
    m("psnr-factor", "metrics", "eval/metrics/pixel_error.cpp",
      "return 10.0 * std::log10(peak * peak / mse);", "return 20.0 * std::log10(peak * peak / mse);",
      r"^metrics\.PixelError", "PSNR doubled"),
    # --- config, cache keys, runner -------------------------------------------------------------
    m("snapshot-section-dropped", "runner", "eval/experiment.cpp",
      "    SnapshotSettings s(c.snapshot);", "    SnapshotSettings s;",
      r"^eval\.SettingsReach", "the config's snapshot section never reaches the Snapshot (its defaults do)"),
    m("exposure-dropped", "runner", "eval/experiment.cpp",
      "    s.filter.exposure = static_cast<float>(c.image.exposure);  // edges as the viewer will see them\n", "",
      r"^eval\.SettingsReach", "image.exposure never reaches the Snapshot's greyscale"),
    m("trace-seed-dropped", "runner", "eval/experiment.cpp",
      "    ts.seed = config.seed;\n", "",
      r"^eval\.SettingsReach", "seed never reaches the tracer"),
    m("seed-key", "runner", "eval/config.cpp",
      '    j["seed"] = c.seed;\n    j["shading"] = shadingJson(c, r.shadingMode, true);',
      '    j["shading"] = shadingJson(c, r.shadingMode, true);',
      r"^eval\.(CacheKeys|SettingsReach)", "seed left out of the render cache key"),
    m("snapshot-key-of-aamap-renders", "runner", "eval/config.cpp",
      '        j["snapshot"] = snapshotJson(c, true);\n', "",
      r"^eval\.(CacheKeys|SettingsReach)", "aamap renders' keys ignore the Snapshot settings"),
    m("changed-keys-dropped", "runner", "core/schema.h",
      "            if (!(v == f.spec.defaultParam())) out.set(f.spec.name, std::move(v));\n", "",
      r"^eval\.(CacheKeys|SettingsReach|ConfigSchema)", "no schema key set away from its default enters the cache keys"),
    m("cache-section-key", "runner", "eval/config.cpp",
      '            if (!cache.empty()) j["cache"] = cache;\n', "",
      r"^eval\.(CacheKeys|SettingsReach|ShadingSettings)", "shading.cache left out of the keys"),
    m("light-map-content-key", "runner", "eval/config.cpp",
      '    if (!maps.empty()) j["light_map_content"] = maps;\n', "",
      r"^eval\.(CacheKeys|SettingsReach)", "an environment map edited in place reuses the old images"),
    m("strategy-params-dropped", "runner", "eval/strategy_settings.cpp",
      "    s.params = r.params;", "",
      r"^eval\.SettingsReach", "a render's strategy parameters never reach the tracer (defaults run)"),
    m("filter-radius-dropped", "tracer", "tracer/strategies/supersample.cpp",
      'p.real("filter_radius")', "0.6",
      r"^tracer\.StrategyParams", "supersample filter_radius never reaches the sampler"),
    m("light-selection-dropped", "runner", "tracer/shading_params.cpp",
      '{{"contribution", LightSelection::Contribution}, {"power", LightSelection::Power}}',
      '{{"contribution", LightSelection::Contribution}, {"power", LightSelection::Contribution}}',
      r"^eval\.SettingsReach", "shading.light_selection: power never reaches the tracer (the schema binds the wrong value)"),
    m("cache-seed-dropped", "runner", "eval/strategy_settings.cpp",
      "    s.cache.seed = c.seed;", "",
      r"^eval\.ShadingSettings", "the irradiance cache's records ignore the experiment's seed"),
    m("cache-mode-as-direct", "tracer", "tracer/make_integrator.cpp",
      "if (indirect != nullptr) return std::make_unique<CacheIntegrator>(geometry, lights, shading, *indirect);",
      "if (indirect != nullptr) return std::make_unique<DirectIntegrator>(geometry, lights, shading);",
      r"^tracer\.(CacheMode|Integrators)", "cache mode renders without its irradiance cache"),
    m("reference-mode-dropped", "runner", "eval/runner.cpp",
      'RenderConfig r{"reference", "reference", baselineStrategyName(), c.reference.rpp, {}, c.reference.mode};',
      'RenderConfig r{"reference", "reference", baselineStrategyName(), c.reference.rpp, {}, std::nullopt};',
      r"^eval\.(SettingsReach|Runner)", "reference.mode ignored: the reference traced in the renders' mode"),
    m("cache-entry-without-record", "runner", "eval/render_cache.cpp",
      "return fs::is_regular_file(record(key), ec);", "return fs::exists(entry(key), ec);",
      r"^eval\.(RenderCache|Runner)", "a cache folder without record.json (a killed run) counts as complete"),
]


# The test executables behind a regex's suites: a mutant rebuilds only those (the restore makes
# ninja rebuild the file again for whatever needs it next).
EXECUTABLES = [
    (r"tracer\.", ["test_tracer"]), (r"scene\.", ["test_scene"]), ("SettingsReach", ["test_settings_reach"]),
    ("CacheKeys", ["test_eval"]), ("RenderCache", ["test_eval"]), ("MetricSettings", ["test_eval"]), ("Runner", ["test_eval"]),
    (r"Filters\.", ["test_cpu_filters"]), ("FilterTest", ["test_gpu_filters"]), ("SpotShading", ["test_gpu_spot"]),
    (r"metrics\.", ["test_metrics"]), ("ShadingSettings", ["test_camera"]),
]


def executables(regex):
    found = []
    for key, targets in EXECUTABLES:
        if key in regex:
            found += [t for t in targets if t not in found]
    return found


def run(cmd, cwd, log, timeout=None, env=None):
    """Runs cmd, appending its output to log; returns (rc, output)."""
    try:
        p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           timeout=timeout, env=env)
        out, rc = p.stdout, p.returncode
    except subprocess.TimeoutExpired as e:
        out, rc = (e.stdout or b"").decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or ""), 124
    with open(log, "a") as f:
        f.write(f"$ {' '.join(cmd)}\n{out}\n[rc {rc}]\n")
    return rc, out


def tracked_files(repo):
    out = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=repo, check=True,
                         stdout=subprocess.PIPE).stdout.decode()
    return [f for f in out.split("\0") if f]


def sync_scratch(repo, scratch):
    """Copies the tree into scratch, touching only files whose bytes differ (keeps the build
    incremental)."""
    files = tracked_files(repo)
    for rel in files:
        src, dst = repo / rel, scratch / rel
        if not src.is_file():
            continue
        if dst.is_file() and dst.read_bytes() == src.read_bytes():
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src, dst)
    shared = repo.parent / "shared"  # the public scenes beside each checkout, for the "shared" tests
    if shared.is_dir() and not (scratch.parent / "shared").exists():
        (scratch.parent / "shared").symlink_to(shared)


def failed_tests(output):
    # "  12 - suite.name (Failed)", parameterised ones with "  # GetParam() = ..." before the "(".
    names = re.findall(r"^\s*\d+ - (\S+)", output, re.MULTILINE)
    return names


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--list", action="store_true", help="print the mutants and exit")
    ap.add_argument("--only", help="comma-separated mutant ids")
    ap.add_argument("--scratch", default="/tmp/aamap-mutate", help="scratch copy (default %(default)s)")
    ap.add_argument("--in-place", action="store_true", help="mutate this tree and its build/release")
    ap.add_argument("--suite", action="store_true",
                    help="run the release suite (labels fuzz, viewer excluded) instead of each mutant's regex")
    ap.add_argument("--jobs", type=int, default=2, help="build and ctest parallelism (default %(default)s)")
    ap.add_argument("--test-timeout", type=int, default=600, help="seconds per ctest run (default %(default)s)")
    ap.add_argument("--no-baseline", action="store_true", help="skip checking that the tests pass unmutated")
    ap.add_argument("--json", help="also write the results here")
    args = ap.parse_args()

    mutants = MUTANTS
    if args.only:
        wanted = args.only.split(",")
        unknown = [w for w in wanted if w not in {x["id"] for x in MUTANTS}]
        if unknown:
            sys.exit(f"unknown mutant(s): {', '.join(unknown)}")
        mutants = [x for x in MUTANTS if x["id"] in wanted]
    if args.list:
        for x in mutants:
            print(f"{x['id']:30} {x['area']:8} {x['file']:38} {x['tests']:45} {x['what']}")
        print(f"{len(mutants)} mutants")
        return 0

    if args.in_place:
        tree = REPO
        dirty = subprocess.run(["git", "status", "--porcelain", "--"] + sorted({x["file"] for x in mutants}),
                               cwd=REPO, stdout=subprocess.PIPE, text=True).stdout.strip()
        if dirty:
            sys.exit(f"--in-place: commit or stash these first (they are restored from their current bytes):\n{dirty}")
    else:
        tree = Path(args.scratch) / "src"
        tree.mkdir(parents=True, exist_ok=True)
        sync_scratch(REPO, tree)
    build = tree / "build" / "release"
    log = (Path(args.scratch) if not args.in_place else REPO / "build") / "mutate.log"
    log.parent.mkdir(parents=True, exist_ok=True)
    log.write_text("")
    # ccache, where installed, makes each mutant's rebuild incremental across runs.
    env = dict(os.environ)
    if shutil.which("ccache"):
        env.update(CMAKE_CXX_COMPILER_LAUNCHER="ccache", CMAKE_C_COMPILER_LAUNCHER="ccache")
    print(f"tree {tree}, build {build}, log {log}", flush=True)

    # Every snippet must occur exactly once, or the mutant tests nothing.
    for x in mutants:
        n = (tree / x["file"]).read_text().count(x["original"])
        if n != 1:
            sys.exit(f"mutant {x['id']}: the original snippet occurs {n} times in {x['file']}")

    for x in mutants:
        if not args.suite and not executables(x["tests"]):
            sys.exit(f"mutant {x['id']}: no test executable known for {x['tests']} (add it to EXECUTABLES)")
    if not (build / "build.ninja").exists():
        rc, _ = run(["cmake", "--preset", "release"], tree, log, env=env)
        if rc:
            sys.exit(f"configure failed (see {log})")
    # The test executables the run needs (all of them for --suite).
    needed = [] if args.suite else sorted({t for x in mutants for t in executables(x["tests"])})
    full_build = ["cmake", "--build", str(build), "-j", str(args.jobs)] + (["--target"] + needed if needed else [])
    rc, _ = run(full_build, tree, log, env=env)
    if rc:
        sys.exit(f"the unmutated tree does not build (see {log})")

    def tests_for(x):
        if args.suite:
            return ["ctest", "--test-dir", str(build), "-LE", "fuzz|viewer", "-j", str(args.jobs), "--timeout",
                    str(args.test_timeout)]
        return ["ctest", "--test-dir", str(build), "-R", x["tests"], "-j", str(args.jobs), "--timeout",
                str(args.test_timeout)]

    if not args.no_baseline:
        for cmd in {tuple(tests_for(x)) for x in mutants}:
            rc, out = run(list(cmd), tree, log, timeout=args.test_timeout * 4, env=env)
            if rc or "No tests were found" in out:
                sys.exit(f"baseline: {' '.join(cmd)} fails or finds no tests unmutated (see {log})")

    results = []
    for i, x in enumerate(mutants, 1):
        path = tree / x["file"]
        original = path.read_bytes()
        start = time.monotonic()
        with open(log, "a") as f:
            f.write(f"\n### mutant {x['id']}: {x['what']}\n")
        try:
            path.write_bytes(original.replace(x["original"].encode(), x["replacement"].encode(), 1))
            targets = [] if args.suite else executables(x["tests"])
            build_cmd = ["cmake", "--build", str(build), "-j", str(args.jobs)] + (["--target"] + targets if targets else [])
            rc, out = run(build_cmd, tree, log, env=env)
            if rc:
                status, failing = "invalid (does not build)", []
            else:
                rc, out = run(tests_for(x), tree, log, timeout=args.test_timeout * 4, env=env)
                if "No tests were found" in out:
                    status, failing = "invalid (no tests match)", []
                else:
                    status, failing = ("killed" if rc else "SURVIVED"), failed_tests(out)
        finally:
            path.write_bytes(original)
        seconds = time.monotonic() - start
        results.append(dict(x, status=status, failing=failing, seconds=round(seconds, 1)))
        print(f"[{i}/{len(mutants)}] {x['id']:30} {status:26} {seconds:6.0f} s  {' '.join(failing[:3])}", flush=True)
    # Leave the build matching the restored tree.
    run(full_build, tree, log, env=env)

    print()
    print(f"| mutant | area | file | what | tests | result | s |")
    print(f"|---|---|---|---|---|---|---|")
    for r in results:
        print(f"| {r['id']} | {r['area']} | {r['file']} | {r['what']} | `{r['tests']}` | {r['status']} | {r['seconds']:.0f} |")
    valid = [r for r in results if not r["status"].startswith("invalid")]
    killed = sum(r["status"] == "killed" for r in valid)
    print()
    if valid:
        print(f"kill ratio: {killed}/{len(valid)} = {100.0 * killed / len(valid):.0f} %"
              f" ({len(results) - len(valid)} invalid)")
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))
    return 0 if valid and killed == len(valid) else 1


if __name__ == "__main__":
    sys.exit(main())
