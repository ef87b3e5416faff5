#!/usr/bin/env python3
"""Plots `meso tables`' CSVs: a level's visible-normal histogram and its BRDF table.

Usage: plot_tables.py CSV PNG [CSV PNG ...]

Each CSV is one of the two kinds src/appearance/table_plots.h writes, told apart by its header:
- histogram (theta_v_deg,theta_n_deg,phi_deg,density): one panel per theta_V, theta_N across,
  phi_{N-V} up, colour = density of visible normals per steradian, each panel on its own scale
  (its colour bar), since the density peaks sharpen as theta_V grows;
- BRDF (theta_v_deg,theta_l_deg,phi_deg,diffuse,specular): one panel per theta_V for the
  diffuse part, then one per theta_V for the specular part, theta_L across, phi_{V-L} up; each
  part on one scale (its colour bar).
Each PNG is written under a temporary name and renamed into place, so it is always complete.
Needs matplotlib (Debian: python3-matplotlib, installed by tools/install-deps).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HISTOGRAM = ["theta_v_deg", "theta_n_deg", "phi_deg", "density"]
BRDF = ["theta_v_deg", "theta_l_deg", "phi_deg", "diffuse", "specular"]


def read(path):
    """The header and the rows as floats."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        return header, [[float(v) for v in row] for row in reader if row]


def grids(rows, value):
    """Per theta_V (in order): the sorted x and y axes and the value grid z[y][x]."""
    out = {}
    for r in rows:
        out.setdefault(r[0], {})[(r[1], r[2])] = r[value]
    result = []
    for theta_v in sorted(out):
        cells = out[theta_v]
        xs = sorted({x for x, _ in cells})
        ys = sorted({y for _, y in cells})
        z = [[cells.get((x, y), 0.0) for x in xs] for y in ys]
        result.append((theta_v, xs, ys, z))
    return result


def edges(centres, lo, hi):
    """Cell edges around sorted centres, clamped to [lo, hi]."""
    if len(centres) == 1:
        return [lo, hi]
    mids = [(a + b) / 2 for a, b in zip(centres, centres[1:])]
    return [max(lo, 2 * centres[0] - mids[0])] + mids + [min(hi, 2 * centres[-1] - mids[-1])]


def save(fig, out):
    tmp = out + ".tmp-plot.png"
    fig.savefig(tmp, format="png")
    plt.close(fig)
    os.replace(tmp, out)


def plot_histogram(rows, out):
    panels = grids(rows, 3)
    cols = min(len(panels), 4)
    rows_of_panels = (len(panels) + cols - 1) // cols
    fig, axes = plt.subplots(rows_of_panels, cols, figsize=(3.6 * cols, 3.0 * rows_of_panels),
                             dpi=100, squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    for ax, (theta_v, xs, ys, z) in zip(axes.flat, panels):
        mesh = ax.pcolormesh(edges(xs, 0, 90), edges(ys, -180, 180), z, cmap="viridis",
                             shading="flat")
        fig.colorbar(mesh, ax=ax, label="density (1/sr)")
        ax.set_title("theta_V = %.3g deg" % theta_v, fontsize=10)
        ax.set_xlabel("theta_N (deg)")
        ax.set_ylabel("phi_N - phi_V (deg)")
    fig.suptitle("visible normals: density per solid angle at each view angle")
    fig.tight_layout()
    save(fig, out)


def plot_brdf(rows, out):
    parts = [("diffuse", grids(rows, 3)), ("specular", grids(rows, 4))]
    n = len(parts[0][1])
    cols = min(n, 4)
    rows_per_part = (n + cols - 1) // cols
    fig, axes = plt.subplots(2 * rows_per_part, cols, dpi=100, squeeze=False,
                             figsize=(3.4 * cols + 1.0, 2.8 * 2 * rows_per_part),
                             layout="constrained")
    for part, (name, panels) in enumerate(parts):
        block = [ax for line in axes[part * rows_per_part:(part + 1) * rows_per_part]
                 for ax in line]
        for ax in block[n:]:
            ax.set_visible(False)
        top = max((max(max(line) for line in z) for _, _, _, z in panels), default=1.0) or 1.0
        for k, (ax, (theta_v, xs, ys, z)) in enumerate(zip(block, panels)):
            mesh = ax.pcolormesh(edges(xs, 0, 90), edges(ys, 0, 180), z, cmap="viridis",
                                 vmin=0.0, vmax=top, shading="flat")
            ax.set_title("%s, theta_V = %.3g deg" % (name, theta_v), fontsize=10)
            ax.set_xlabel("theta_L (deg)")
            if k % cols == 0:
                ax.set_ylabel("phi_V - phi_L (deg)")
        fig.colorbar(mesh, ax=block[:n], label=name + " reflectance")
    fig.suptitle("BRDF table: area-averaged reflectance of the relief (diffuse, then specular)")
    save(fig, out)


def main(argv):
    if len(argv) < 3 or len(argv) % 2 == 0:
        sys.stderr.write(__doc__)
        return 2
    for csv_path, png in zip(argv[1::2], argv[2::2]):
        header, rows = read(csv_path)
        if not rows:
            sys.stderr.write("plot_tables.py: %s has no rows\n" % csv_path)
            return 1
        if header == HISTOGRAM:
            plot_histogram(rows, png)
        elif header == BRDF:
            plot_brdf(rows, png)
        else:
            sys.stderr.write("plot_tables.py: %s: unknown header %s\n" % (csv_path, header))
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
