"""A year of direct sun in a London courtyard: four buildings around a yard with Spot the cow
in it, the hours of direct sun at every pixel and at a grid of sensors on the yard's floor,
hourly over 2026, the sun by NREL's SPA (pvlib).

    python python/examples/sun_hours.py [OUT_DIR] [--ray [ADDRESS]]

writes OUT_DIR/sun-hours.png (the map with its legend in hours), sun-hours.npy (the hours,
float64) and courtyard-sensors.csv (x, y, z, hours). `--ray` runs the steps on Ray (a local
cluster, or the one at ADDRESS). PENUMBRA_EXAMPLE_SMALL=1 takes a week at 80 x 60 instead of
the year at 320 x 240 (docs/sun-studies.md gives both sizes' times).
"""

import os
import sys
import time
from pathlib import Path

import numpy as np

import penumbra as pb
from penumbra import study

root = Path(__file__).resolve().parents[2]
args = [a for a in sys.argv[1:] if not a.startswith("--")]
out = Path(args[0] if args else "out")
out.mkdir(parents=True, exist_ok=True)
engine, address = "local", None
if "--ray" in sys.argv:
    engine = "ray"
    rest = sys.argv[sys.argv.index("--ray") + 1:]
    address = rest[0] if rest and not rest[0].startswith("--") else None
small = bool(os.environ.get("PENUMBRA_EXAMPLE_SMALL"))


def box(lo, hi, name):
    """A closed box from corner `lo` to corner `hi`, wound outwards."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
         [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]]
    f = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
         [3, 7, 6], [3, 6, 2], [0, 4, 7], [0, 7, 3], [1, 2, 6], [1, 6, 5]]
    return pb.Mesh(v, f, name=name)


def obj(path, name):
    """The vertices and triangles of a triangulated OBJ file."""
    lines = path.read_text().splitlines()
    v = [[float(x) for x in line.split()[1:4]] for line in lines if line.startswith("v ")]
    f = [[int(x.split("/")[0]) - 1 for x in line.split()[1:4]]
         for line in lines if line.startswith("f ")]
    return pb.Mesh(v, f, name=name)


# The yard is 16 x 12 m (x east, z south, y up: north is -z); buildings 9 to 15 m high on
# its four sides, a gap in the south-west corner.
meshes = [
    pb.Mesh([[-30, 0, -30], [30, 0, -30], [30, 0, 30], [-30, 0, 30]],
            [[0, 2, 1], [0, 3, 2]], name="ground"),
    box((-12, 0, -10), (12, 15, -6), "north block"),
    box((8, 0, -6), (12, 12, 10), "east block"),
    box((-4, 0, 6), (8, 9, 10), "south block"),
    box((-12, 0, -6), (-8, 12, 3), "west block"),
]
spot = np.eye(4)
spot[:3, :3] *= 3.0
spot[:3, 3] = [0.0, 2.2, 0.0]
meshes.append((obj(root / "fixtures" / "meshes" / "spot.obj", "spot"), spot))
width, height = (80, 60) if small else (320, 240)
camera = pb.Camera(eye=(-14, 30, 26), target=(0, 0, 0), width=width, height=height)
scene = pb.Scene(camera, pb.DistantLight.sun(180, 45), meshes)

latitude, longitude, zone = 51.5074, -0.1278, "Europe/London"
start, end = ("2026-06-18", "2026-06-25") if small else ("2026-01-01", "2027-01-01")
x, z = np.meshgrid(np.linspace(-7, 7, 15), np.linspace(-5, 5, 11))
sensors = np.column_stack([x.ravel(), np.zeros(x.size), z.ravel()])

t0 = time.perf_counter()
hours = study.sun_hours(scene, latitude, longitude, start, end, timezone=zone, samples=64,
                        engine=engine, address=address)
at_sensors = study.sun_hours(scene, latitude, longitude, start, end, timezone=zone,
                             samples=256, points=sensors, normals=[0, 1, 0],
                             engine=engine, address=address)
seconds = time.perf_counter() - t0

pb.write_colour_map(out / "sun-hours.png", hours, unit="h")
np.save(out / "sun-hours.npy", hours)
np.savetxt(out / "courtyard-sensors.csv", np.column_stack([sensors, at_sensors]),
           delimiter=",", header="x,y,z,hours", comments="")
steps = study.sun_steps(latitude, longitude, start, end, timezone=zone)
print(f"{start} to {end} in {zone}: {len(steps.hours)} hourly steps, "
      f"{len(steps.daylight())} in daylight; {scene.triangle_count} triangles at "
      f"{width} x {height}, {engine}: {seconds:.1f} s")
print(f"yard sensors: {at_sensors.min():.1f} to {at_sensors.max():.1f} hours of direct sun "
      f"(mean {at_sensors.mean():.1f}); wrote {out / 'sun-hours.png'}")
