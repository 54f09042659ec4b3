#!/usr/bin/env python3
"""Plots of ephor-bench-sphere's JSON in the layout of the paper's Figures 3-5
(bias and sigma per axis against distance): figure3.png (Sphere Fitting),
figure4.png (Scan Line Extent), figure5.png (Scan Line Extent velocity).

    python3 procs/sphere/bench/plot_sphere_bench.py BENCH.json OUTDIR

Needs python3-matplotlib (Debian package).
"""
import json
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("plot_sphere_bench.py: needs python3-matplotlib (apt-get install python3-matplotlib)")


def series(method, key, axis):
    ds, vs = [], []
    for d in ("1", "2", "5", "10", "15", "20"):
        entry = method.get(d, {})
        if key in entry:
            ds.append(int(d))
            vs.append(1e3 * entry[key][axis])
    return ds, vs


def figure(bench, names, quantity, title, unit, path):
    fig, axes = plt.subplots(2, 3, figsize=(12, 6), sharex=True)
    for row, stat in enumerate(("bias", "sigma")):
        for axis, label in enumerate("xyz"):
            ax = axes[row][axis]
            for name in names:
                if name not in bench["methods"]:
                    continue
                ds, vs = series(bench["methods"][name], f"{quantity}_{stat}", axis)
                ax.plot(ds, vs, marker="o", label=name)
            if stat == "sigma" and quantity == "position_m":
                ax.axhline(8.0, color="grey", linestyle="--", linewidth=0.8)  # the 8 mm requirement
            ax.set_title(f"{label} {stat}")
            ax.set_xlabel("distance (m)")
            ax.set_ylabel(unit)
            ax.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        bench = json.load(f)
    out = sys.argv[2]
    os.makedirs(out, exist_ok=True)
    figure(bench, ["fit-paper", "fit-geometric-weighted", "fit-improved", "pcl-ransac-sphere"],
           "position_m", "Figure 3: Sphere Fitting position error", "mm", os.path.join(out, "figure3.png"))
    figure(bench, ["sle-paper", "sle+edge", "sle+edge+geometry", "sle+edge+geometry+weights", "sle-improved"],
           "position_m", "Figure 4: Scan Line Extent position error", "mm", os.path.join(out, "figure4.png"))
    figure(bench, ["sle-paper", "sle-improved"], "velocity_m_s",
           "Figure 5: Scan Line Extent velocity error", "mm/s", os.path.join(out, "figure5.png"))


if __name__ == "__main__":
    main()
