#!/usr/bin/env python3
"""Mean intensity per distance band of meso EXRs against a reference EXR (the last argument).

  tools/band_means.py A.exr B.exr ... REFERENCE.exr [--bands 5,8,13,21]

Intensity is the mean of R, G and B. Bands are by the reference's depth.Z (distance from the eye;
edges in world units, default 5, 8, 13, 21) over the pixels where the reference hit a surface, so
every image is averaged over the same pixels. Prints each image's band means and their difference
from the reference's in percent. Reads pixels with oiiotool --dumpdata (no Python image modules
needed)."""
import re
import subprocess
import sys
import tempfile


def channels(path, names):
    """{(x, y): [values of `names`]} of one image, read with oiiotool --dumpdata."""
    with tempfile.NamedTemporaryFile(suffix=".exr") as tmp:
        subprocess.run(["oiiotool", path, "--ch", ",".join(names), "-o", tmp.name], check=True)
        out = subprocess.run(["oiiotool", "--dumpdata", tmp.name], check=True,
                             capture_output=True, text=True).stdout
    values = {}
    for line in out.splitlines():
        m = re.match(r"\s*Pixel \((\d+), (\d+)\):(.*)", line)
        if m:
            values[(int(m.group(1)), int(m.group(2)))] = [float(v) for v in m.group(3).split()]
    return values


def pixels(path):
    rgbz = channels(path, ["R", "G", "B", "depth.Z"]).values()
    return [((r + g + b) / 3.0, z) for r, g, b, z in rgbz]


def main(argv):
    edges = [5.0, 8.0, 13.0, 21.0]
    if "--bands" in argv:
        i = argv.index("--bands")
        edges = [float(v) for v in argv[i + 1].split(",")]
        del argv[i:i + 2]
    if len(argv) < 2:
        sys.exit(__doc__)
    files = argv[1:]
    ref = pixels(files[-1])
    bounds = [0.0] + edges + [float("inf")]
    band = [next((k for k in range(len(bounds) - 1) if z > 0.0 and bounds[k] <= z < bounds[k + 1]),
                 None) for _, z in ref]
    names = [f"{bounds[k]:g}-{bounds[k + 1]:g}" for k in range(len(bounds) - 1)] + ["all"]

    def means(values):
        sums, counts = [0.0] * len(names), [0] * len(names)
        for (v, _), k in zip(values, band):
            if k is None:
                continue
            for j in (k, len(names) - 1):
                sums[j] += v
                counts[j] += 1
        return [s / c if c else float("nan") for s, c in zip(sums, counts)], counts

    refMeans, counts = means(ref)
    print("band (depth):  " + "  ".join(f"{n:>14}" for n in names))
    print("pixels:        " + "  ".join(f"{c:>14d}" for c in counts))
    for f in files:
        m, _ = means(pixels(f) if f != files[-1] else ref)
        cells = [f"{a:.5f} {100.0 * (a / b - 1.0):+6.2f}%" for a, b in zip(m, refMeans)]
        print(f"{f}\n               " + "  ".join(f"{c:>14}" for c in cells))


if __name__ == "__main__":
    main(sys.argv)
