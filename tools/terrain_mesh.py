#!/usr/bin/env python3
"""Writes scenes/terrain.obj: N x N unit quads over [-N/2, N/2]^2 in y = 0, facing +y, with texture
coordinates in world units (u = x + N/2, v = z + N/2), for scenes/terrain.toml. Unit faces keep
view culling and per-face dicing fine-grained. Usage: tools/terrain_mesh.py [N] > scenes/terrain.obj"""
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 40
h = n / 2
print(f"# terrain ground: {n} x {n} unit quads over [{-h:g}, {h:g}]^2 in y = 0, uv in world units "
      f"over [0, {n}]^2 (written by tools/terrain_mesh.py)")
for i in range(n + 1):
    for j in range(n + 1):
        print(f"v {i - h:g} 0 {j - h:g}")
for i in range(n + 1):
    for j in range(n + 1):
        print(f"vt {i:g} {j:g}")
for i in range(n):
    for j in range(n):
        a = i * (n + 1) + j + 1
        b, c, d = a + 1, a + n + 2, a + n + 1
        print(f"f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")
