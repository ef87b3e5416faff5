#!/usr/bin/env python3
"""Writes scenes/terrain.obj: N x N unit quads over [-N/2, N/2]^2 in y = 0, facing +y, with texture
coordinates in world units (u = x + N/2, v = z + N/2), for scenes/terrain.toml. Unit faces keep
view culling and per-face dicing fine-grained. With --hills the vertices rise to
y = 1.5 sin(0.21 x) cos(0.17 z) + 0.8 sin(0.05 x + 0.07 z), a ground whose own shape is curved (as a
sculpted terrain is), to be read with scheme = "catmull-clark".
Usage: tools/terrain_mesh.py [N] [--hills] > scenes/terrain.obj"""
import math
import sys

args = [a for a in sys.argv[1:] if a != "--hills"]
hills = "--hills" in sys.argv[1:]
n = int(args[0]) if args else 40
h = n / 2


def height(x, z):
    if not hills:
        return "0"
    return f"{1.5 * math.sin(0.21 * x) * math.cos(0.17 * z) + 0.8 * math.sin(0.05 * x + 0.07 * z):.5f}"


shape = "rising to hills" if hills else "in y = 0"
print(f"# terrain ground: {n} x {n} unit quads over [{-h:g}, {h:g}]^2 {shape}, uv in world units "
      f"over [0, {n}]^2 (written by tools/terrain_mesh.py)")
for i in range(n + 1):
    for j in range(n + 1):
        print(f"v {i - h:g} {height(i - h, j - h)} {j - h:g}")
for i in range(n + 1):
    for j in range(n + 1):
        print(f"vt {i:g} {j:g}")
for i in range(n):
    for j in range(n):
        a = i * (n + 1) + j + 1
        b, c, d = a + 1, a + n + 2, a + n + 1
        print(f"f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")
