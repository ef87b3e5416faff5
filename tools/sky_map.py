#!/usr/bin/python3
"""Writes a procedural sky with a sun as a latitude-longitude Radiance HDR map (docs/environment.md)
that meso reads as an environment light: W x W/2 texels, top row the zenith, the centre column
facing -z (the map convention of docs/environment.md, up = +y).

  sky   radiance blue at the zenith, paler towards the horizon and around the sun
  sun   a disc of `--sun-radius` degrees whose texels together give `--sun-irradiance` at normal
        incidence (the disc is a few texels wide: a small, very bright source)
  ground below the horizon, uniform: a brown ground of albedo `--ground-albedo` lit by the sky and
         the sun above it (radiance albedo E / pi, E the irradiance of a horizontal plane), so a
         camera that sees past a scene's floor sees a plausible distant ground

  tools/sky_map.py OUT.hdr [--width 512] [--sun-elevation 35] [--sun-azimuth 40]
                           [--sun-irradiance 3] [--sun-radius 1.5] [--sky 0.25]
                           [--ground-albedo 0.3]

--sun-azimuth is degrees about the up axis from -z towards +x (the image's centre towards its
right). --sky scales the sky's radiance. Writes flat RGBE scanlines; plain Python 3, no modules
beyond the standard library."""
import argparse
import math


def texel_direction(x, y, w, h):
    """The unit direction (x, y, z) of texel (x, y)'s centre, y up."""
    theta = math.pi * (y + 0.5) / h
    phi = 2 * math.pi * (x + 0.5) / w - math.pi
    return (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))


def row_solid_angle(y, w, h):
    return (2 * math.pi / w) * (math.cos(math.pi * y / h) - math.cos(math.pi * (y + 1) / h))


def sky(args):
    """Rows of [r, g, b] texels, top row first."""
    w = args.width
    h = w // 2
    el, az = math.radians(args.sun_elevation), math.radians(args.sun_azimuth)
    sun = (math.cos(el) * math.sin(az), math.sin(el), -math.cos(el) * math.cos(az))
    cos_disc = math.cos(math.radians(args.sun_radius))
    rows, disc = [], []
    for y in range(h):
        row = []
        for x in range(w):
            d = texel_direction(x, y, w, h)
            cos_sun = max(-1.0, min(1.0, sum(a * b for a, b in zip(d, sun))))
            if cos_sun >= cos_disc:
                disc.append((x, y))
            if d[1] < 0:  # the ground, filled in below
                row.append(None)
                continue
            t = (1.0 - d[1]) ** 3  # paler towards the horizon
            glow = 0.8 * math.exp((cos_sun - 1.0) / 0.04) + 0.25 * (1 + cos_sun) ** 2 / 4
            zenith, horizon, warm = (0.35, 0.55, 1.0), (1.26, 1.33, 1.4), (1.0, 0.85, 0.6)
            row.append([args.sky * ((1 - t) * z + t * o + glow * g)
                        for z, o, g in zip(zenith, horizon, warm)])
        rows.append(row)
    if not disc:  # a disc smaller than a texel: the texel nearest the sun
        nearest = max(((x, y) for y in range(h) for x in range(w)),
                      key=lambda p: sum(a * b for a, b in zip(texel_direction(*p, w, h), sun)))
        disc = [nearest]
    # The disc's texels together: irradiance E at normal incidence, sum of L * solid angle = E.
    solid = sum(row_solid_angle(y, w, h) for _, y in disc)
    for x, y in disc:
        rows[y][x] = [c * args.sun_irradiance / solid for c in (1.0, 0.95, 0.85)]
    # The ground: a diffuse plane of the given albedo under the sky and sun above it.
    irradiance = [0.0, 0.0, 0.0]
    for y in range(h):
        for x in range(w):
            up = texel_direction(x, y, w, h)[1]
            if rows[y][x] is not None and up > 0:
                for c in range(3):
                    irradiance[c] += rows[y][x][c] * up * row_solid_angle(y, w, h)
    ground = [args.ground_albedo * e / math.pi * t for e, t in zip(irradiance, (1.0, 0.8, 0.6))]
    return [[texel if texel is not None else ground for texel in row] for row in rows]


def rgbe(rgb):
    top = max(rgb)
    if top < 1e-32:
        return bytes(4)
    mantissa, exponent = math.frexp(top)
    scale = mantissa * 256.0 / top
    return bytes([min(255, int(c * scale)) for c in rgb] + [exponent + 128])


def write_hdr(path, rows):
    h, w = len(rows), len(rows[0])
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {h} +X {w}\n".encode())
        for row in rows:  # flat scanlines (no run-length encoding)
            f.write(b"".join(rgbe(texel) for texel in row))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out")
    p.add_argument("--width", type=int, default=512)
    p.add_argument("--sun-elevation", type=float, default=35.0)
    p.add_argument("--sun-azimuth", type=float, default=40.0)
    p.add_argument("--sun-irradiance", type=float, default=3.0)
    p.add_argument("--sun-radius", type=float, default=1.5)
    p.add_argument("--sky", type=float, default=0.25)
    p.add_argument("--ground-albedo", type=float, default=0.3)
    args = p.parse_args()
    write_hdr(args.out, sky(args))


if __name__ == "__main__":
    main()
