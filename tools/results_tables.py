#!/usr/bin/env python3
"""Regenerates the measured tables of docs/results.md, one command per table set.

Every table in docs/results.md sits between a `<!-- table NAME -->` line and a `<!-- /table -->`
line. This script runs what measures it and rewrites the lines between: first a line with the
command, the machine (CPU model, cores, Vulkan device), the revision and the date, then the table.
The prose around the markers is left alone.

Table sets (--tables, repeatable; default: selective):
  selective    `aamap run` of the three shipped paper configs with timing.repeats 3 (interleaved):
               tables `headline`, and per scene (cornell, hall, conference) `<scene>-speedup`,
               `<scene>-oracle` and `<scene>-map`. The runs resume from --work.
  maps         the Cornell box and the Modern Hall at 512 with each snapshot.map (luminance,
               geometric, combined, subpixel), Non-adaptive 16 against the oracle: table `maps`.
  throughput   bench/peers/mitsuba_throughput.py on mitsuba-cbox and the Modern Hall: `throughput`.
  conformance  bench/peers/mitsuba_conformance.py over its scenes: `conformance`.

Timed figures need an otherwise idle machine (no build running): the script warns when the load
average exceeds the core count. Mitsuba 3 is a peer for the last two sets (see bench/peers/).

    .venv/bin/python tools/results_tables.py [--tables selective] [--work out/results] [--repeats 3]
        [--override KEY=VALUE ...]   # passed to every aamap run as --set (a quick look: image.width=128)
        [--print]                    # print the tables instead of rewriting docs/results.md
"""
import argparse
import datetime
import json
import math
import os
import platform
import re
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS_MD = os.path.join(REPO, "docs", "results.md")

# The shipped experiments the selective tables come from: (table prefix, label, config).
SCENES = [
    ("cornell", "Cornell box", "configs/paper-cornell.yaml"),
    ("hall", "Modern Hall", "configs/paper-room.yaml"),
    ("conference", "Conference room", "configs/conference.yaml"),
]
MAP_KINDS = ["luminance", "geometric", "combined", "subpixel"]


def machine_line(aamap):
    cpu, isa = "unknown CPU", ""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name") and cpu == "unknown CPU":
                    cpu = line.split(":", 1)[1].strip()
                elif line.startswith("flags") and not isa:
                    # The widest vector ISA: Mitsuba's LLVM backend (and Highway) pick their width from it.
                    flags = line.split(":", 1)[1].split()
                    isa = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else "SSE"
    except OSError:
        pass
    if isa:
        cpu += f" ({isa})"
    device = ""
    try:
        out = subprocess.run([aamap, "run", "--list-devices"], capture_output=True, text=True, timeout=60).stdout
        device = next((re.sub(r"^\d+:\s*", "", l.strip()) for l in out.splitlines() if l.strip()), "")
    except (OSError, subprocess.SubprocessError):
        pass
    rev = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    date = datetime.date.today().isoformat()
    return f"{cpu}, {os.cpu_count()} cores; Vulkan: {device or 'none'}; aamap {rev}; {date}"


def warn_if_busy():
    load = os.getloadavg()[0]
    if load > (os.cpu_count() or 1):
        print(f"warning: load average {load:.1f} on {os.cpu_count()} cores: timed figures will be skewed",
              file=sys.stderr)


def num(d, key, default=math.nan):
    v = d.get(key) if isinstance(d, dict) else None
    return v if isinstance(v, (int, float)) else default


def render_time(r):
    """Trace + the Snapshot's per-frame cost, as aamap's report counts a render's time."""
    t = r.get("times_s", {})
    return num(t, "trace", 0.0) + num(t, "snapshot_total", 0.0)


def time_range(r):
    t = r.get("times_s", {})
    runs = t.get("trace_runs") or [num(t, "trace", 0.0)]
    snap = num(t, "snapshot_total", 0.0)
    return min(runs) + snap, max(runs) + snap


def speedup(base, r):
    """Median ratio and the worst-to-best range the timed runs allow."""
    b_lo, b_hi = time_range(base)
    r_lo, r_hi = time_range(r)
    return render_time(base) / render_time(r), b_lo / r_hi, b_hi / r_lo


def fmt_speedup(s):
    med, lo, hi = s
    if not math.isfinite(med):
        return "—"
    return f"{med:.1f}x" if abs(hi - lo) < 0.05 else f"{med:.1f}x ({lo:.1f}-{hi:.1f})"


def pct(v, digits=2):
    return "—" if not math.isfinite(v) else f"{v:.{digits}f} %"


def flip_pct(r):
    return num(r.get("metrics", {}), "pct_error_flip")


class Run:
    """One experiment's results.json, with the lookups the tables need."""

    def __init__(self, path):
        with open(path) as f:
            self.j = json.load(f)
        self.renders = self.j.get("renders", [])
        baseline = [r for r in self.renders if r.get("strategy") == "uniform"]
        self.base_series = baseline[0]["series"] if baseline else None

    def find(self, series, rpp):
        return next((r for r in self.renders if r.get("series") == series and r.get("max_rays_per_pixel") == rpp), None)

    def baseline(self, rpp):
        return self.find(self.base_series, rpp) if self.base_series else None

    def map_driven(self):
        return [r for r in self.renders if num(r.get("times_s", {}), "snapshot_total", 0.0) > 0]

    def top_rpp(self):
        """The largest rpp at which a map-driven render has a baseline twin."""
        shared = [r["max_rays_per_pixel"] for r in self.map_driven() if self.baseline(r["max_rays_per_pixel"])]
        return max(shared) if shared else None

    def oracle_of(self, name):
        for run in self.j.get("oracle", {}).get("runs", []):
            if run.get("map_render") == name:
                return run["render"]
        return None

    def label(self, name, config):
        """'Cornell box (`paper-cornell.yaml`, 512x512, direct)': the size and mode as rendered."""
        r = self.renders[0] if self.renders else {}
        mode = self.j.get("config", {}).get("shading", {}).get("mode", "")
        return f"{name} (`{os.path.basename(config)}`, {r.get('width', '?')}x{r.get('height', '?')}, {mode})"

    def snapshot_ms(self):
        s = self.j.get("snapshot")
        return 1000 * num(s, "total_s") if s else math.nan


def run_aamap(aamap, config, out, overrides, sweep=False):
    """Runs (or resumes) one experiment; its Run, or None for a sweep (each variant has its own)."""
    cmd = [aamap, "run", config, "-o", out, "--no-plots"] + [a for kv in overrides for a in ("--set", kv)]
    print("$ " + " ".join(os.path.relpath(c, REPO) if c.startswith(REPO) else c for c in cmd), file=sys.stderr, flush=True)
    subprocess.run(cmd, check=True, cwd=REPO)
    return None if sweep else Run(os.path.join(out, "results.json"))


def runs_text(repeats):
    return "one timed run" if repeats == 1 else f"medians of {repeats} interleaved runs, with their range"


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def selective_tables(args, machine):
    tables = {}
    headline = []
    overrides = [f"timing.repeats={args.repeats}", "timing.interleave=true", "metrics.oracle=true"]
    for key, label, config in SCENES:
        run = run_aamap(args.aamap, os.path.join(REPO, config), os.path.join(args.work, key), overrides + args.override)
        cmd = f"`aamap run {config} --set timing.repeats={args.repeats} --set metrics.oracle=true" + \
            "".join(f" --set {o}" for o in args.override) + "`"
        top = run.top_rpp()
        series = []
        for r in run.renders:
            if r["series"] not in series and r["series"] != run.base_series:
                series.append(r["series"])
        rpps = sorted({r["max_rays_per_pixel"] for r in run.renders if run.baseline(r["max_rays_per_pixel"])})
        rows = []
        for rpp in rpps:
            b = run.baseline(rpp)
            row = [rpp, f"{render_time(b):.3f} s"]
            for s in series:
                r = run.find(s, rpp)
                row.append("" if r is None else f"{fmt_speedup(speedup(b, r))}, {pct(flip_pct(r))}")
            rows.append(row)
        tables[f"{key}-speedup"] = (f"{cmd}; {runs_text(args.repeats)}. Cells: "
                                    f"speedup over {run.base_series} at the same rpp, % of pixels above FLIP 0.1 "
                                    f"against the reference.",
                                    md_table(["rpp", f"{run.base_series} time"] + series, rows))
        orows = []
        best = None
        for r in run.map_driven():
            o = run.oracle_of(r["name"])
            b = run.baseline(r["max_rays_per_pixel"])
            if o is None or b is None:
                continue
            s, so = speedup(b, r), speedup(b, o)
            orows.append([r["name"], r["max_rays_per_pixel"], fmt_speedup(s), fmt_speedup(so), f"{s[0] / so[0]:.2f}",
                          pct(flip_pct(r)), pct(flip_pct(o)), f"{num(r, 'mean_primary_rpp'):.2f}",
                          f"{num(o, 'mean_primary_rpp'):.2f}"])
        oracle = run.j.get("oracle", {})
        tables[f"{key}-oracle"] = (f"{cmd}; the oracle map covers {100 * num(oracle, 'flagged_fraction'):.1f} % of the "
                                   f"pixels after {int(num(oracle, 'rounds', 0))} rounds "
                                   f"({num(oracle, 'residual_pct_error_flip'):.2f} % error left); its time is the trace alone.",
                                   md_table(["render", "rpp", "speedup", "oracle speedup", "efficiency", "% FLIP",
                                             "oracle % FLIP", "rays/px", "oracle rays/px"], orows))
        q = run.j.get("map_quality", {})
        tables[f"{key}-map"] = (f"{cmd}; truly aliased: the 1-ray image's pixels above FLIP 0.1 against the reference.",
                                md_table(["truly aliased", "flagged", "recall", "own recall", "precision",
                                          "Snapshot per frame"],
                                         [[pct(100 * num(q, "true_fraction"), 1), pct(100 * num(q, "flagged_fraction"), 1),
                                           f"{num(q, 'recall'):.3f}", f"{num(q, 'own_recall'):.3f}",
                                           f"{num(q, 'precision'):.3f}", f"{run.snapshot_ms():.0f} ms"]]))
        # Headline: Non-adaptive and the fastest map-driven render at the top rpp, and the oracle.
        if top is not None:
            b = run.baseline(top)
            at_top = [r for r in run.map_driven() if r["max_rays_per_pixel"] == top]
            non_adaptive = next((r for r in at_top if r.get("strategy") == "aamap"), None)
            best = max(at_top, key=lambda r: speedup(b, r)[0]) if at_top else None
            o = run.oracle_of(non_adaptive["name"]) if non_adaptive else None
            cell = lambda r: f"{fmt_speedup(speedup(b, r))} at {pct(flip_pct(r))}" if r else "—"
            headline.append([run.label(label, config), top, cell(non_adaptive), f"{best['series']}: {cell(best)}" if best else "—",
                             cell(o), f"{speedup(b, non_adaptive)[0] / speedup(b, o)[0]:.2f}" if o and non_adaptive else "—",
                             pct(100 * num(q, "true_fraction"), 1), pct(100 * num(q, "flagged_fraction"), 1),
                             f"{num(q, 'precision'):.3f}", f"{run.snapshot_ms():.0f} ms"])
    tables["headline"] = (f"`.venv/bin/python tools/results_tables.py --tables selective` ({runs_text(args.repeats)} "
                          "per render; speedups over uniform sampling at the same rpp, error as % of "
                          "pixels above FLIP 0.1 against the scene's uniform reference).",
                          md_table(["scene", "rpp", "Non-adaptive", "fastest map-driven", "oracle map",
                                    "efficiency", "truly aliased", "flagged", "precision", "Snapshot per frame"],
                                   headline))
    return tables


def maps_tables(args, machine):
    """One sweep of snapshot.map per shipped config (shared renders traced once, one cache): each
    map kind's quality, its Non-adaptive and Space 8 renders at the top rpp, and its efficiency
    against the same render on the oracle map."""
    kinds = [k.strip() for k in args.map_kinds.split(",") if k.strip()]
    rows = []
    for key, label, config in SCENES:
        out = os.path.join(args.work, f"maps-{key}")
        run_aamap(args.aamap, os.path.join(REPO, config), out,
                  [f"snapshot.map=[{','.join(kinds)}]", "metrics.oracle=true", f"timing.repeats={args.repeats}"] +
                  args.override, sweep=True)
        for kind in kinds:
            run = Run(os.path.join(out, f"map-{kind}", "results.json"))
            q = run.j.get("map_quality", {})
            top = run.top_rpp()
            b = run.baseline(top) if top else None
            cells = []
            for series in ("Non-adaptive", "Space 8"):
                r = run.find(series, top) if top else None
                o = run.oracle_of(r["name"]) if r else None
                eff = speedup(b, r)[0] / speedup(b, o)[0] if r and o and b else math.nan
                cells += [f"{fmt_speedup(speedup(b, r))} at {pct(flip_pct(r))}" if r and b else "—",
                          f"{num(r, 'mean_primary_rpp'):.2f}" if r else "—",
                          f"{eff:.2f}" + (f" (oracle {pct(flip_pct(o))})" if o else "") if math.isfinite(eff) else "—"]
            rows.append([label, top or "—", kind, pct(100 * num(q, "flagged_fraction"), 1), f"{num(q, 'precision'):.3f}",
                         f"{num(q, 'recall'):.3f}", f"{num(q, 'own_recall'):.3f}"] + cells +
                        [f"{run.snapshot_ms():.0f} ms"])
    kinds_text = ",".join(kinds)
    return {"maps": (f"`.venv/bin/python tools/results_tables.py --tables maps --map-kinds {kinds_text}` (each "
                     f"shipped config with `--set snapshot.map=[{kinds_text}] --set metrics.oracle=true --set "
                     f"timing.repeats={args.repeats}`, one sweep per scene; {runs_text(args.repeats)}; speedups over "
                     "uniform sampling at the same rpp, error as % of pixels above FLIP 0.1; efficiency: the "
                     "speedup over the same render's on the oracle map)",
                     md_table(["scene", "rpp", "map", "flagged", "precision", "recall", "own recall",
                               "Non-adaptive", "rays/px", "efficiency", "Space 8", "rays/px", "efficiency",
                               "Snapshot per frame"], rows))}


def peer_json(script, extra):
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        path = f.name
    cmd = [sys.executable, os.path.join(REPO, "bench", "peers", script), "--json", path] + extra
    print("$ " + " ".join(cmd), file=sys.stderr, flush=True)
    subprocess.run(cmd, check=True, cwd=REPO)
    with open(path) as f:
        data = json.load(f)
    os.unlink(path)
    return data


def throughput_tables(args, machine):
    shared = os.path.join(REPO, "..", "shared", "scenes")
    cases = [("mitsuba-cbox `scene.xml`", os.path.join(shared, "mitsuba-cbox", "scene.xml"), ["--size", "256", "--depth", "5"]),
             ("Modern Hall `scene.xml`", os.path.join(shared, "modern-hall", "scene.xml"), ["--size", "320", "--depth", "65"]),
             ("furnished room `v_furnished_room.xml` (envmap through a window)",
              os.path.join(REPO, "bench", "peers", "conformance", "v_furnished_room.xml"), ["--size", "320", "--depth", "65"])]
    rows = []
    for label, scene, extra in cases:
        if not os.path.exists(scene):
            print(f"skipping {label}: {scene} is missing", file=sys.stderr)
            continue
        s = peer_json("mitsuba_throughput.py", ["--scene", scene, "--rounds", str(args.repeats)] + extra)
        rows.append([label, " ".join(extra), f"{s['median_throughput_ratio']:.2f}x "
                     f"({s['min_ratio']:.2f}-{s['max_ratio']:.2f})"])
    return {"throughput": ("`.venv/bin/python tools/results_tables.py --tables throughput` (bench/peers/mitsuba_throughput.py: "
                           "64 spp, path mode, interleaved rounds; aamap's throughput over Mitsuba 3 llvm_ad_rgb's).",
                           md_table(["scene", "settings", "aamap / Mitsuba throughput (median, range)"], rows))}


def conformance_tables(args, machine):
    data = peer_json("mitsuba_conformance.py", [])
    rows = [[r["scene"], r["spp"], " ".join(f"{x:.3f}" for x in r["ratio"]), f"{r['flip_mean']:.3f}",
             f"{100 * r['noise']:.2f} %"] for r in data["rows"]]
    return {"conformance": ("`.venv/bin/python tools/results_tables.py --tables conformance` "
                            "(bench/peers/mitsuba_conformance.py: Mitsuba 3 llvm_ad_rgb against aamap's path mode, "
                            "64x64, box filter, the file's max_depth).",
                            md_table(["scene", "spp", "aamap / Mitsuba (r, g, b)", "LDR-FLIP mean", "noise of the mean"],
                                     rows))}


SETS = {"selective": selective_tables, "maps": maps_tables, "throughput": throughput_tables,
        "conformance": conformance_tables}


def rewrite(path, tables, machine):
    with open(path) as f:
        text = f.read()
    for name, (how, table) in tables.items():
        pattern = re.compile(r"(<!-- table " + re.escape(name) + r" -->\n).*?(<!-- /table -->)", re.S)
        if not pattern.search(text):
            print(f"warning: docs/results.md has no `<!-- table {name} -->` marker; table not written", file=sys.stderr)
            continue
        body = f"Measured by {how}\nMachine: {machine}.\n\n{table}\n"
        text = pattern.sub(lambda m: m.group(1) + body + m.group(2), text)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tables", action="append", choices=sorted(SETS), help="table sets to measure (default: selective)")
    ap.add_argument("--override", action="append", default=[], metavar="KEY=VALUE",
                    help="an aamap --set for every run of the selective and maps sets")
    ap.add_argument("--work", default=os.path.join(REPO, "out", "results"), help="where the runs go (they resume)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs per render (interleaved)")
    ap.add_argument("--map-kinds", default="luminance,subpixel",
                    help="the maps set: the snapshot.map kinds to sweep, comma-separated")
    ap.add_argument("--aamap", default=os.path.join(REPO, "build", "release", "aamap"))
    ap.add_argument("--print", action="store_true", help="print the tables; leave docs/results.md alone")
    args = ap.parse_args()
    if not os.path.exists(args.aamap):
        sys.exit(f"error: {args.aamap} not found: build it first (cmake --build --preset release --target aamap)")
    warn_if_busy()
    machine = machine_line(args.aamap)
    tables = {}
    for name in args.tables or ["selective"]:
        tables.update(SETS[name](args, machine))
    if args.print:
        for name, (how, table) in tables.items():
            print(f"<!-- table {name} -->\nMeasured by {how}\nMachine: {machine}.\n\n{table}\n")
    else:
        rewrite(RESULTS_MD, tables, machine)
        print(f"rewrote {len(tables)} table(s) in docs/results.md", file=sys.stderr)


if __name__ == "__main__":
    main()
