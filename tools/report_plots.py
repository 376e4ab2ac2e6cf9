#!/usr/bin/env python3
"""Plots for an aamap experiment report, from OUTDIR/results.json (written by `aamap run`).

    .venv/bin/python tools/report_plots.py OUTDIR

Writes OUTDIR/plots/time_vs_rpp.png (the paper's Figures 6-7: render time against the mean primary
rays per pixel each render actually traced, one line per series with its least-squares fit and
R^2) and OUTDIR/plots/error_vs_time.png (the speed-accuracy trade: % FLIP error pixels against
time, one curve per series, the Pareto front marked). An axis whose values span a decade or more
is logarithmic; point labels that would collide are moved or left out. `aamap run` calls this
itself; `aamap report OUTDIR` reruns it.

    .venv/bin/python tools/report_plots.py --compare OUT.png TITLE LABEL DIR [LABEL DIR ...]

Writes one error-against-time plot of several runs of the same scene (`aamap compare`, and the
report of a sweep): one curve per run and series, labelled "LABEL: series", with the Pareto front
over all of them, so that shading modes, maps and strategies are read off one trade. Files are
written under a temporary name and renamed, like every aamap output.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def render_seconds(r):
    t = r["times_s"]
    return t.get("trace", 0.0) + t.get("snapshot_total", 0.0)


def mean_rpp(r):
    """Primary rays per pixel the render traced (a supersampled rpp 1 traces 4), else the nominal rpp."""
    v = r.get("mean_primary_rpp")
    return v if isinstance(v, (int, float)) and v > 0 else r["max_rays_per_pixel"]


def log_if_wide(ax, axis, values):
    """Log scale when positive values span a decade or more: points at 0.1 s and 10 s both readable."""
    values = [v for v in values if v > 0]
    if values and max(values) >= 10 * min(values):
        (ax.set_xscale if axis == "x" else ax.set_yscale)("log")


def label_points(ax, points):
    """Annotates (x, y, text) in data space where the label overlaps no other label or marker:
    tries four offsets around each point, drops the label when none is free."""
    fig = ax.figure
    fig.canvas.draw()  # fixes the limits and scales, so display positions are final
    to_px = ax.transData.transform
    placed = []  # label boxes in display pixels
    markers = [to_px((x, y)) for x, y, _ in points]
    dpi_scale = fig.dpi / 72.0
    for x, y, text in points:
        px, py = to_px((x, y))
        w, h = (5.0 * len(text) + 2) * dpi_scale, 9.0 * dpi_scale
        for dx, dy in ((4, 3), (4, -12), (-6 - 5.0 * len(text), 3), (-6 - 5.0 * len(text), -12)):
            box = (px + dx * dpi_scale, py + dy * dpi_scale, px + dx * dpi_scale + w, py + dy * dpi_scale + h)
            clash = any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in placed)
            clash = clash or any(box[0] - 3 < mx < box[2] + 3 and box[1] - 3 < my < box[3] + 3 for mx, my in markers)
            if not clash:
                placed.append(box)
                ax.annotate(text, (x, y), fontsize=7, xytext=(dx, dy), textcoords="offset points")
                break


def by_series(renders):
    series = {}
    for r in renders:
        series.setdefault(r.get("series") or r["strategy"], []).append(r)
    for rs in series.values():
        rs.sort(key=lambda r: r["max_rays_per_pixel"])
    return series


def save(fig, path):
    tmp = f"{path}.tmp-{os.getpid()}.png"
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


def linear_fit(x, y):
    """Least-squares y = a x + b and its R^2 (None with fewer than 2 distinct x)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if len(set(x)) < 2:
        return None
    a, b = np.polyfit(x, y, 1)
    ss_res = float(np.sum((y - (a * x + b)) ** 2))
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    return a, b, (1.0 - ss_res / ss_tot) if ss_tot > 0 else 1.0


def time_vs_rpp(series, path, title):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, (name, rs) in enumerate(series.items()):
        x = [mean_rpp(r) for r in rs]
        y = [render_seconds(r) for r in rs]
        colour = f"C{i % 10}"
        fit = linear_fit(x, y)
        label = name if fit is None else f"{name}: {fit[0]:.3g} s/rpp, R²={fit[2]:.3f}"
        ax.plot(x, y, "o", color=colour, label=label)
        if fit is not None:
            xs = np.linspace(min(x), max(x), 50)
            ax.plot(xs, fit[0] * xs + fit[1], "-", color=colour, alpha=0.6)
    all_x = [mean_rpp(r) for rs in series.values() for r in rs]
    all_y = [render_seconds(r) for rs in series.values() for r in rs]
    log_if_wide(ax, "x", all_x)
    log_if_wide(ax, "y", all_y)
    ax.set_xlabel("mean primary rays per pixel traced")
    ax.set_ylabel("render time (s): trace + Snapshot")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, path)


def pareto(points):
    """Points (time, error) not dominated by a faster-and-no-worse one, sorted by time."""
    front, best = [], float("inf")
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def error_vs_time(series, path, key, ylabel, title, many_runs=False):
    """many_runs: curves of several runs (markers cycle per ten curves, legend beside the axes, error
    axis logarithmic when it spans a decade: 1 % and 90 % are both readable)."""
    fig, ax = plt.subplots(figsize=(9 if many_runs else 7, 4.5))
    points = []
    for i, (name, rs) in enumerate(series.items()):
        pts = [(render_seconds(r), r["metrics"][key], r["max_rays_per_pixel"]) for r in rs
               if isinstance(r.get("metrics", {}).get(key), (int, float))]
        if not pts:
            continue
        marker = "osD^v<>"[(i // 10) % 7]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker + "-", color=f"C{i % 10}", label=name)
        points += pts
    if points:
        front = pareto([(t, e) for t, e, _ in points])
        ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=1, label="Pareto front")
        ax.scatter([p[0] for p in front], [p[1] for p in front], s=90, facecolors="none", edgecolors="k")
    log_if_wide(ax, "x", [t for t, _, _ in points])
    if many_runs and all(e > 0 for _, e, _ in points):
        log_if_wide(ax, "y", [e for _, e, _ in points])
    ax.set_xlabel("render time (s): trace + Snapshot")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3, which="both")
    if many_runs:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    else:
        ax.legend(fontsize=8)
    label_points(ax, [(t, e, str(rpp)) for t, e, rpp in points])
    save(fig, path)


def error_metric(renders):
    """The error key the plots use ("pct_error_flip", else "pct_error_mse"; None without metrics) and its label."""
    metrics = [r.get("metrics", {}) for r in renders]
    if any("pct_error_flip" in m for m in metrics):
        return "pct_error_flip", "% pixels in error (FLIP)"
    if any("pct_error_mse" in m for m in metrics):
        return "pct_error_mse", "% pixels in error (MSE)"
    return None, None


def read_renders(run_dir):
    with open(os.path.join(run_dir, "results.json")) as f:
        return json.load(f).get("renders", [])


def compare(out_png, title, runs):
    """runs: (label, dir) pairs; every (run, series) pair is one curve."""
    series = {}
    for label, run_dir in runs:
        for name, rs in by_series(read_renders(run_dir)).items():
            series[f"{label}: {name}"] = rs
    key, ylabel = error_metric([r for rs in series.values() for r in rs])
    if key is None:
        print("report_plots: the runs have no error metrics", file=sys.stderr)
        return 1
    os.makedirs(os.path.dirname(out_png) or ".", exist_ok=True)
    error_vs_time(series, out_png, key, ylabel, title, many_runs=True)
    return 0


def main(argv):
    if len(argv) >= 6 and argv[1] == "--compare" and len(argv) % 2 == 0:
        pairs = argv[4:]
        return compare(argv[2], argv[3], list(zip(pairs[0::2], pairs[1::2])))
    if len(argv) != 2 or argv[1].startswith("--"):
        print(__doc__, file=sys.stderr)
        return 2
    out = argv[1]
    renders = read_renders(out)
    if not renders:
        print("report_plots: no renders in results.json", file=sys.stderr)
        return 1
    os.makedirs(os.path.join(out, "plots"), exist_ok=True)
    series = by_series(renders)
    scene = os.path.basename(renders[0].get("scene", ""))
    time_vs_rpp(series, os.path.join(out, "plots", "time_vs_rpp.png"), f"Time against rays per pixel ({scene})")
    key, ylabel = error_metric(renders)
    if key is not None:
        error_vs_time(series, os.path.join(out, "plots", "error_vs_time.png"), key, ylabel,
                      "Speed against accuracy (labels: rpp)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
