#!/usr/bin/env python3
"""Writes the scenes of the "Scale" table of docs/benchmarks.md into a folder:

  many-meshes.toml     700,000 [[mesh]] entries naming one quad (1.4M triangles) over a ground;
  bumpy-grid.toml      a 1000 x 1000-quad bumpy grid (2M triangles) over a ground;
  nefertiti-N.toml     N = 1, 5, 10 copies of the Nefertiti scan (99,938 triangles each) 3 m
                       apart on a ground under a 5 x 5 light (the GPU build's growth table).

Usage: python3 scripts/scale-scenes.py OUT_DIR
"""
import math
import os
import random
import sys

CAMERA_LIGHT = """[camera]
eye = [{eye}]
target = [{target}]
up = [0.0, 1.0, 0.0]
fov_y_deg = 45.0
width = {w}
height = {h}

[light]
center = [{center}]
normal = [0.0, -1.0, 0.0]
tangent = [1.0, 0.0, 0.0]
size = [{size}, {size}]

[[mesh]]
obj = "quad.obj"
scale = {ground}
"""

QUAD = "v -0.5 0 -0.5\nv -0.5 0 0.5\nv 0.5 0 0.5\nv 0.5 0 -0.5\nf 1 2 3\nf 1 3 4\n"


def many_meshes(out):
    rng = random.Random(1)
    with open(os.path.join(out, "many-meshes.toml"), "w") as f:
        f.write(CAMERA_LIGHT.format(eye="0.0, 60.0, 80.0", target="0.0, 0.0, 0.0", w=160, h=120,
                                    center="0.0, 100.0, 0.0", size="10.0", ground="200.0"))
        for _ in range(700000):
            f.write('[[mesh]]\nobj = "quad.obj"\nscale = 0.1\ntranslate = [%.3f, %.3f, %.3f]\n'
                    % (rng.uniform(-50, 50), rng.uniform(1, 20), rng.uniform(-50, 50)))


def bumpy_grid(out):
    n = 1000
    with open(os.path.join(out, "bumpy.obj"), "w") as f:
        for j in range(n + 1):
            for i in range(n + 1):
                x, z = -1 + 2 * i / n, -1 + 2 * j / n
                f.write("v %.6f %.6f %.6f\n" % (x, 0.05 * math.sin(200 * x) * math.cos(170 * z), z))
        w = n + 1
        for j in range(n):
            for i in range(n):
                a = j * w + i + 1
                f.write("f %d %d %d\nf %d %d %d\n" % (a, a + w, a + w + 1, a, a + w + 1, a + 1))
    with open(os.path.join(out, "bumpy-grid.toml"), "w") as f:
        f.write(CAMERA_LIGHT.format(eye="0.0, 4.0, 5.0", target="0.0, 0.5, 0.0", w=320, h=240,
                                    center="0.3, 6.0, 0.2", size="1.0", ground="20.0"))
        f.write('\n[[mesh]]\nobj = "bumpy.obj"\ntranslate = [0.0, 1.5, 0.0]\n')


NEFERTITI = """[camera]
eye = [0.0, 9.0, 12.0]
target = [0.0, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 50.0
width = 320
height = 240

[light]
center = [-1.5, 9.0, 2.5]
normal = [0.15094638162798826, -0.9559937503105924, -0.2515773027133138]
tangent = [0.987762965329069, 0.15596257347301087, 0.0]
size = [5.0, 5.0]

[[mesh]]
obj = "quad.obj"
scale = 20.0
"""


def nefertiti(out, n):
    meshes = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "meshes")
    scan = os.path.normpath(os.path.join(meshes, "nefertiti.obj"))
    with open(os.path.join(out, f"nefertiti-{n}.toml"), "w") as f:
        f.write(NEFERTITI)
        for i in range(n):
            x, z = -4.5 + 3.0 * (i % 4), -3.0 + 3.0 * (i // 4)
            f.write(f'\n[[mesh]]\nobj = "{scan}"\nscale = 0.006\n'
                    f'rotate_axis_angle = [1.0, 0.0, 0.0, -90.0]\n'
                    f'translate = [{x}, 1.504, {z}]\n')


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "quad.obj"), "w") as f:
        f.write(QUAD)
    many_meshes(out)
    bumpy_grid(out)
    for n in (1, 5, 10):
        nefertiti(out, n)
