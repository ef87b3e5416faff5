#!/usr/bin/env python3
"""Mean luminance per band of rows of other renderers' EXRs against a meso EXR (the first argument).

  tools/row_means.py MESO.exr OTHER.exr ... [--rows 40]

Luminance is Rec. 709's, as `meso consistency` compares. The pixels are those where the meso image
hit a surface (depth.Z > 0) and every other image's alpha is 1 (a transparent film's partly covered
outline pixels are left out of all), so every image is averaged over the same pixels. Prints, per
band of rows (and the whole image), each image's difference from the meso image in percent. Reads
pixels with band_means.py's oiiotool --dumpdata reader (no Python image modules needed)."""
import sys

import band_means  # its oiiotool --dumpdata reader, from this folder


def channels(path, names):
    values = band_means.channels(path, names)
    if not values:
        sys.exit(f"row_means.py: {path}: no pixels read")
    return values


def luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def main(argv):
    rows = 40
    if "--rows" in argv:
        i = argv.index("--rows")
        rows = int(argv[i + 1])
        del argv[i:i + 2]
    if len(argv) < 3:
        sys.exit(__doc__)
    meso = channels(argv[1], ["R", "G", "B", "depth.Z"])
    others = [(path, channels(path, ["R", "G", "B", "A"])) for path in argv[2:]]
    keep = [p for p, v in meso.items() if v[3] > 0.0 and all(o.get(p, [0, 0, 0, 0])[3] >= 1.0
                                                              for _, o in others)]
    height = max(y for _, y in meso) + 1
    bands = [(0, height)] + [(r, min(r + rows, height)) for r in range(0, height, rows)]
    print("rows," + ",".join(f"{path} vs meso" for path, _ in others) + ",pixels")
    for r0, r1 in bands:
        band = [p for p in keep if r0 <= p[1] < r1]
        if not band:
            continue
        ref = sum(luminance(meso[p]) for p in band)
        diffs = [100.0 * (sum(luminance(o[p]) for p in band) / ref - 1.0) for _, o in others]
        print(f"{r0}-{r1 - 1}," + ",".join(f"{d:+.2f}%" for d in diffs) + f",{len(band)}")


if __name__ == "__main__":
    main(sys.argv)
