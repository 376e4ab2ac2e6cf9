#!/usr/bin/env python3
"""Figure 4 of the paper, from bench_filter's CSV: filter time against resolution, log axes, one
line per implementation (min-max as error bars), the copy of the same image on each side as the
bandwidth limit (dashed). Prints the speedup table.

Usage: plot_filter_bench.py CSV OUT.png
Run it with the repo's .venv (tools/python-env.sh makes it).
"""
import csv
import sys

IMPLS = [  # (impl, label, style)
    ("cpu_scalar", "CPU 1 thread, scalar", dict(color="tab:red", marker="o")),
    ("cpu_parallel", "CPU all threads, TBB + SIMD", dict(color="tab:orange", marker="s")),
    ("cpu_parallel_new", "CPU all threads, + new output image", dict(color="tab:brown", marker="s", ls=":")),
    ("gpu_kernel", "Vulkan compute, kernel (timestamps)", dict(color="tab:blue", marker="^")),
    ("gpu_total", "Vulkan compute, with upload + readback", dict(color="tab:purple", marker="v")),
    ("cpu_copy", "copy limit, CPU (parallel memcpy)", dict(color="tab:orange", ls="--", marker="")),
    ("gpu_copy", "copy limit, GPU (vkCmdCopyBuffer)", dict(color="tab:blue", ls="--", marker="")),
]
SPEEDUPS = [  # (numerator, denominator, header)
    ("cpu_scalar", "cpu_parallel", "1T/MT CPU"),
    ("cpu_scalar", "gpu_kernel", "1T CPU/GPU krn"),
    ("cpu_parallel", "gpu_kernel", "MT CPU/GPU krn"),
    ("cpu_parallel", "gpu_total", "MT CPU/GPU tot"),
]


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no rows")
    for r in rows:
        for key in ("width", "height"):
            r[key] = int(r[key])
        for key in ("median_ms", "min_ms", "max_ms", "fraction_of_copy"):
            r[key] = float(r[key]) if r[key] else float("nan")
    return rows


def lookup(rows):
    return {(r["stage"], r["impl"], r["width"]): r for r in rows}


def speedup_table(rows):
    table = lookup(rows)
    stages = [s for s in dict.fromkeys(r["stage"] for r in rows) if s != "copy"]
    sizes = sorted({r["width"] for r in rows})
    lines = [f"{'stage':<10}{'size':>11}" + "".join(f"{h:>16}" for _, _, h in SPEEDUPS)
             + f"{'MT CPU % copy':>15}{'GPU krn % copy':>16}"]
    for stage in stages:
        for s in sizes:
            cells = []
            for num, den, _ in SPEEDUPS:
                a, b = table.get((stage, num, s)), table.get((stage, den, s))
                cells.append(f"{a['median_ms'] / b['median_ms']:.2f}x" if a and b and b["median_ms"] > 0 else "-")
            frac = []
            for impl in ("cpu_parallel", "gpu_kernel"):
                r = table.get((stage, impl, s))
                frac.append(f"{100 * r['fraction_of_copy']:.0f}%" if r else "-")
            lines.append(f"{stage:<10}{f'{s}x{s}':>11}" + "".join(f"{c:>16}" for c in cells)
                         + f"{frac[0]:>15}{frac[1]:>16}")
    return "\n".join(lines)


def plot(rows, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    table = lookup(rows)
    stages = [s for s in dict.fromkeys(r["stage"] for r in rows) if s != "copy"]
    sizes = sorted({r["width"] for r in rows})
    fig, axes = plt.subplots(1, len(stages), figsize=(5.2 * len(stages), 4.4), squeeze=False, sharey=True)
    for ax, stage in zip(axes[0], stages):
        for impl, label, style in IMPLS:
            source = "copy" if impl.endswith("_copy") else stage
            pts = [table[(source, impl, s)] for s in sizes if (source, impl, s) in table]
            if not pts:
                continue
            x = [p["width"] for p in pts]
            y = [p["median_ms"] for p in pts]
            err = [[p["median_ms"] - p["min_ms"] for p in pts], [p["max_ms"] - p["median_ms"] for p in pts]]
            ax.errorbar(x, y, yerr=err, label=label, capsize=2, lw=1.4, ms=4, **style)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xticks(sizes)
        ax.set_xticklabels([str(s) for s in sizes], fontsize=8)
        ax.set_xlabel("image size (square, pixels per side)")
        ax.set_title(f"{stage}: median time, min-max bars", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("time (ms)")
    axes[0][-1].legend(fontsize=7, loc="upper left")
    first = rows[0]
    fig.suptitle(f"aamap filters - device: {first['device']}; CPU: {first['cpu']}", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=90)


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        rows = read_rows(argv[1])
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_filter_bench: {e}", file=sys.stderr)
        return 2
    print(f"device: {rows[0]['device']}\ncpu:    {rows[0]['cpu']}")
    print("speedups (ratio of medians; > 1: the second-named is faster); % copy = copy median / median")
    print(speedup_table(rows))
    try:
        plot(rows, argv[2])
    except ImportError as e:
        print(f"plot_filter_bench: cannot import matplotlib ({e}); run tools/python-env.sh", file=sys.stderr)
        return 3
    print(f"wrote {argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
