"""A scene built from numpy arrays, lit by a lamp and by the sun: one image per light.
`python python/examples/scene_from_arrays.py [OUT_DIR]`."""

import sys
from pathlib import Path

import numpy as np

import penumbra as pb

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
out.mkdir(parents=True, exist_ok=True)

# A 12 x 12 ground and a box 1 high standing on it, as vertex and face arrays.
ground = pb.Mesh([[-6, 0, -6], [6, 0, -6], [6, 0, 6], [-6, 0, 6]], [[0, 2, 1], [0, 3, 2]], name="ground")
corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (0, 1) for z in (-0.5, 0.5)], dtype=float)
faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
box = pb.Mesh(corners, faces, name="box")
turned = np.eye(4)
turned[:3, :3] = [[np.cos(0.5), 0, np.sin(0.5)], [0, 1, 0], [-np.sin(0.5), 0, np.cos(0.5)]]

camera = pb.Camera(eye=(0, 4, 6), target=(0, 0, 0), up=(0, 1, 0), fov_y_deg=45, width=160, height=120)
lamp = pb.RectLight(center=(0, 5, 0), normal=(0, -1, 0), tangent=(1, 0, 0), size=(2, 1), name="lamp")
sun = pb.DistantLight.sun(azimuth_deg=135, elevation_deg=30, angular_size_deg=0.53, name="sun")
scene = pb.Scene(camera, [lamp, sun], [ground, (box, turned)])

images = scene.render("depth-complexity", samples=256, backend="cpu")
for name, v in images.items():
    lit = (v == 1).mean()
    print(f"{name}: {v.shape[1]} x {v.shape[0]}, {100 * lit:.1f}% of pixels fully lit, "
          f"{100 * (v == 0).mean():.1f}% in umbra")
pb.write_exr(out / "box.exr", images)
print(f"wrote {out / 'box.exr'} with channels {list(pb.read_exr(out / 'box.exr'))}")
