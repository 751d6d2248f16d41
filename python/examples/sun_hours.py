"""Sensor points: the share of the sun that a grid on the ground sees through a day, around
the meshes of a fixture. `python python/examples/sun_hours.py [OUT_DIR]` from the repository's
root writes the grid's sunlit hours as a CSV."""

import os
import sys
from pathlib import Path

import numpy as np

import penumbra as pb

root = Path(__file__).resolve().parents[2]
out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
out.mkdir(parents=True, exist_ok=True)
small = bool(os.environ.get("PENUMBRA_EXAMPLE_SMALL"))

meshes = [pb.Mesh([[-8, 0, -8], [8, 0, -8], [8, 0, 8], [-8, 0, 8]], [[0, 2, 1], [0, 3, 2]], name="ground")]
# A simple OBJ read: vertex and face lines of spot.obj (triangles only).
lines = (root / "fixtures" / "meshes" / "spot.obj").read_text().splitlines()
v = np.array([[float(x) for x in l.split()[1:4]] for l in lines if l.startswith("v ")])
f = np.array([[int(x.split("/")[0]) - 1 for x in l.split()[1:4]] for l in lines if l.startswith("f ")])
t = np.eye(4)
t[:3, :3] *= 1.6
t[:3, 3] = [0.3, 1.2, -0.2]
meshes.append((pb.Mesh(v, f, name="spot"), t))

n = 16 if small else 64
x, z = np.meshgrid(np.linspace(-3, 3, n), np.linspace(-3, 3, n))
grid = np.column_stack([x.ravel(), np.zeros(n * n), z.ravel()])
camera = pb.Camera(eye=(3, 4, 6), target=(0, 0, 0), width=8, height=6)

hours = np.zeros(len(grid))
for hour in range(7, 18):
    azimuth = 90 + (hour - 7) * 18          # east in the morning, west in the evening
    elevation = 10 + 40 * np.sin(np.pi * (hour - 7) / 10)
    sun = pb.DistantLight.sun(azimuth, elevation, 0.53)
    scene = pb.Scene(camera, sun, meshes)
    hours += scene.visibility_at(grid, (0, 1, 0), samples=64)
np.savetxt(out / "sun-hours.csv", np.column_stack([grid, hours]), delimiter=",",
           header="x,y,z,sunlit_hours", comments="")
print(f"{len(grid)} sensors, 11 sun positions: sunlit hours from {hours.min():.2f} to "
      f"{hours.max():.2f}, mean {hours.mean():.2f}; wrote {out / 'sun-hours.csv'}")
