#!/usr/bin/env python3
"""Plots `meso trade`'s trade.csv: rmse against the reference over seconds (log axis).

Usage: plot_trade.py DIR/trade.csv DIR/trade.png

The CSV is the source (see README.md, `meso trade`): hybrid configurations are blue discs,
displacement alone red squares, the reference levels black diamonds; the Pareto front (the
"# pareto_front:" comment line) is joined and ringed, and the scene's own hybrid (the
"# default_hybrid:" comment line) is labelled "default". The PNG is written under a
temporary name and renamed into place, so DIR/trade.png is always a complete file.
Needs matplotlib (Debian: python3-matplotlib, installed by tools/install-deps).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_trade_csv(path):
    """Rows as dicts, the Pareto front's names and the default hybrid's name (comment lines)."""
    front, default, data = [], "", []
    with open(path, newline="") as f:
        for line in f:
            if line.startswith("# pareto_front:"):
                front = [n for n in line.split(":", 1)[1].strip().split(";") if n]
            elif line.startswith("# default_hybrid:"):
                default = line.split(":", 1)[1].strip()
            elif not line.startswith("#"):
                data.append(line)
    return list(csv.DictReader(data)), front, default


def plot(rows, front, default, out):
    fig, ax = plt.subplots(figsize=(9, 5.6), dpi=100)
    styles = {
        "hybrid": dict(marker="o", color="#1a59d9", label="hybrid (auto, D or dicing x spp)"),
        "displacement": dict(marker="s", color="#d9261a", label="displacement (dicing x spp)"),
        "reference": dict(marker="D", color="black", label="reference levels"),
    }
    groups = {k: ([], []) for k in styles}
    for r in rows:
        kind = "reference" if r["name"].startswith("reference") else (
            "hybrid" if r["algorithm"] == "auto" else "displacement")
        groups[kind][0].append(max(float(r["seconds"]), 1e-9))
        groups[kind][1].append(float(r["rmse"]))
    for kind, (x, y) in groups.items():
        if x:
            ax.scatter(x, y, s=36, linestyle="None", zorder=3, **styles[kind])
    by_name = {r["name"]: r for r in rows}
    fx = [float(by_name[n]["seconds"]) for n in front if n in by_name]
    fy = [float(by_name[n]["rmse"]) for n in front if n in by_name]
    if fx:
        ax.plot(fx, fy, color="black", linewidth=1.5, zorder=2, label="Pareto front")
        ax.scatter(fx, fy, s=160, facecolors="none", edgecolors="black", zorder=4)
    for r in rows:
        if r["name"] == default:
            ax.annotate("default", (float(r["seconds"]), float(r["rmse"])),
                        textcoords="offset points", xytext=(8, 8), fontsize=9)
    ax.set_xscale("log")
    ax.set_ylim(bottom=0)
    ax.set_xlabel("seconds (geometry + render, log scale)")
    ax.set_ylabel("rmse against the reference")
    ax.set_title("meso trade: error against time")
    ax.grid(True, which="both", color="#d9d9d9", linewidth=0.6)
    ax.legend(loc="upper right", fontsize=9)
    fig.tight_layout()
    tmp = out + ".tmp-plot.png"
    fig.savefig(tmp, format="png")
    plt.close(fig)
    os.replace(tmp, out)


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    rows, front, default = read_trade_csv(argv[1])
    if not rows:
        sys.stderr.write("plot_trade.py: %s has no rows\n" % argv[1])
        return 1
    plot(rows, front, default, argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
