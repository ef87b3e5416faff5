#!/usr/bin/python3
"""Writes height images as users bring them, periodic, N x N (default 256), as 16-bit PGM that
OpenImageIO reads (oiiotool FILE.pgm -d uint8 -o FILE.png makes the PNG a user would have):

  bricks  running-bond bricks with 3-texel mortar, bevelled edges, a height offset per brick and
          per-texel noise: sharp edges, energy up to the Nyquist limit
  photo   a random field with a 1/f amplitude spectrum, as a photograph's luminance used as height
  blobs   smooth bumps of many sizes with fine scratches across them, as a sculpted map

  tools/height_maps.py OUTDIR [N] [SEED]

Uses numpy (Debian's python3-numpy, which matplotlib depends on; hence /usr/bin/python3)."""
import os
import sys

import numpy as np


def normalized(a):
    return (a - a.min()) / max(a.max() - a.min(), 1e-12)


def bricks(n, rng):
    y, x = np.mgrid[0:n, 0:n] + 0.5
    rows, per = 8, 4
    bh, bw = n / rows, n / per
    r = np.floor(y / bh)
    xs = (x + (r % 2) * bw / 2) % n
    c = np.floor(xs / bw)
    d = np.minimum(np.minimum(xs - c * bw, (c + 1) * bw - xs), np.minimum(y - r * bh, (r + 1) * bh - y))
    brick = np.clip((d - 1.5) / 2.0, 0.0, 1.0)  # 3-texel mortar, 2-texel bevel
    offset = rng.normal(0.0, 0.08, (rows, per))[r.astype(int) % rows, c.astype(int) % per]
    return 0.2 + 0.6 * brick + offset * brick + 0.02 * rng.standard_normal((n, n))


def photo(n, rng):
    k = np.fft.fftfreq(n) * n
    kk = np.sqrt(k[None, :] ** 2 + k[:, None] ** 2)
    kk[0, 0] = 1.0
    spectrum = (rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))) / kk
    spectrum[0, 0] = 0.0
    return np.real(np.fft.ifft2(spectrum))


def blobs(n, rng):
    y, x = np.mgrid[0:n, 0:n] + 0.5
    h = np.zeros((n, n))
    for _ in range(40):
        cx, cy, s, a = rng.uniform(0, n), rng.uniform(0, n), rng.uniform(8, 30), rng.uniform(-1, 1)
        dx, dy = (x - cx + n / 2) % n - n / 2, (y - cy + n / 2) % n - n / 2
        h += a * np.exp(-(dx * dx + dy * dy) / (2 * s * s))
    for _ in range(25):
        angle, offset = rng.uniform(0, np.pi), rng.uniform(0, n)
        d = (np.cos(angle) * x + np.sin(angle) * y - offset) % n
        h -= 0.08 * np.exp(-np.minimum(d, n - d) ** 2 / 0.8)
    return h


def write_pgm(path, a):
    n = a.shape[0]
    with open(path + ".tmp", "wb") as f:
        f.write(b"P5\n%d %d\n65535\n" % (a.shape[1], n))
        f.write((normalized(a) * 65535.0 + 0.5).astype(">u2").tobytes())
    os.replace(path + ".tmp", path)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 256
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 7
    os.makedirs(out, exist_ok=True)
    for name, make in (("bricks", bricks), ("photo", photo), ("blobs", blobs)):
        write_pgm(os.path.join(out, name + ".pgm"), make(n, np.random.default_rng(seed)))
        print(os.path.join(out, name + ".pgm"))


if __name__ == "__main__":
    main()
