"""The throughput of sun studies, measured in one run (docs/sun-studies.md, "Throughput"):

- seconds per daylight step of `depth-complexity` and of `reference` at the same samples on a
  scene (by default the 209,388-triangle scale scene at 320 x 240, 64 samples), once the
  study's set-up is paid, and their ratio; and that set-up (the hierarchies, the meshes'
  half-edge structures, the camera's surface points), paid once a study;
- the growth of a step's time with the pixels (80 x 60 to 320 x 240) and of a study's with its
  steps (a day, three days);
- a Ray cluster on this machine with one worker against two (`ray.init(num_cpus=1)` and `=2`),
  each run on one thread: the speed-up, and each worker's peak resident memory.

Run from the repository's root after `pip install "./python[ray]"` (a release build):
`python python/benchmarks/sun_hours.py [--scene fixtures/scale/scale.toml] [--steps 6]`.
"""

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

import penumbra as pb
from penumbra import _penumbra, study

ROOT = Path(__file__).resolve().parents[2]
PLACE = dict(latitude=40.42, longitude=-3.70)  # Madrid
DAY = ("2026-06-21", "2026-06-22")


def per_step(scene, technique, steps, samples, with_setup=False, repeats=3):
    """Seconds per daylight step of a June day once the study's set-up is paid (one process,
    every core): a study of `steps` steps less one of its first step, over `steps - 1`, the
    median of `repeats` such pairs (single runs move by a tenth on a shared machine). With
    `with_setup`, also the set-up: the one-step study less a step."""
    s = study.sun_steps(PLACE["latitude"], PLACE["longitude"], *DAY, timezone="Europe/Madrid")
    index = s.daylight()[:steps]

    def run(k):
        # A scene object of its own: a scene keeps its renderer, and with it what a study
        # shares, from one study to the next.
        own = scene.with_size(scene.width, scene.height)
        t0 = time.perf_counter()
        _penumbra._sun_hours(own, s.azimuth_deg[index[:k]], s.elevation_deg[index[:k]],
                             s.hours[index[:k]], technique=technique, samples=samples)
        return time.perf_counter() - t0

    pairs = [(run(1), run(len(index))) for _ in range(repeats)]
    step = float(np.median([(many - one) / (len(index) - 1) for one, many in pairs]))
    setup = float(np.median([one for one, _ in pairs])) - step
    return (step, setup) if with_setup else step


def on_ray(scene, cpus, samples, days):
    import ray

    ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False)
    try:
        seen = []
        end = str(np.datetime64(DAY[0]) + np.timedelta64(days, "D"))
        t0 = time.perf_counter()
        study.sun_hours(scene, PLACE["latitude"], PLACE["longitude"], DAY[0], end,
                        timezone="Europe/Madrid", samples=samples, engine="ray", chunk_steps=8,
                        progress=seen.append)
        seconds = time.perf_counter() - t0
    finally:
        ray.shutdown()
    peak = {}
    for r in seen:
        peak[r["node"]] = max(peak.get(r["node"], 0.0), r["peak_mb"])
    return seconds, max(peak.values())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=str(ROOT / "fixtures" / "scale" / "scale.toml"))
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--steps", type=int, default=12, help="daylight steps timed per figure")
    ap.add_argument("--ray-days", type=int, default=7)
    ap.add_argument("--ray-size", default="160x120")
    args = ap.parse_args()
    scene = pb.Scene.load(args.scene)
    out = {"scene": os.path.relpath(args.scene, ROOT), "triangles": scene.triangle_count,
           "samples": args.samples}

    dc, dc_setup = per_step(scene, "depth-complexity", args.steps, args.samples, True)
    ref, ref_setup = per_step(scene, "reference", args.steps, args.samples, True)
    out["step_s"] = {"depth-complexity": round(dc, 3), "reference": round(ref, 3),
                     "ratio": round(dc / ref, 3), "size": f"{scene.width}x{scene.height}",
                     "setup_s": {"depth-complexity": round(dc_setup, 2),
                                 "reference": round(ref_setup, 2)}}
    print(json.dumps(out["step_s"]), flush=True)

    out["by_pixels"] = {}
    for w, h in ((80, 60), (160, 120), (320, 240)):
        out["by_pixels"][f"{w}x{h}"] = round(
            per_step(scene.with_size(w, h), "depth-complexity", args.steps, args.samples), 3)
    print(json.dumps(out["by_pixels"]), flush=True)

    small = scene.with_size(80, 60)
    out["by_steps"] = {}
    for days in (1, 3):
        end = str(np.datetime64(DAY[0]) + np.timedelta64(days, "D"))
        t0 = time.perf_counter()
        study.sun_hours(small.with_size(80, 60), PLACE["latitude"], PLACE["longitude"], DAY[0], end,
                        timezone="Europe/Madrid", samples=args.samples)
        out["by_steps"][f"{days} d"] = round(time.perf_counter() - t0, 2)
    print(json.dumps(out["by_steps"]), flush=True)

    w, h = (int(x) for x in args.ray_size.split("x"))
    ray_scene = scene.with_size(w, h)
    one, peak1 = on_ray(ray_scene, 1, args.samples, args.ray_days)
    two, peak2 = on_ray(ray_scene, 2, args.samples, args.ray_days)
    out["ray"] = {"size": args.ray_size, "days": args.ray_days, "one_worker_s": round(one, 2),
                  "two_workers_s": round(two, 2), "speedup": round(one / two, 2),
                  "peak_mb_per_worker": round(max(peak1, peak2))}
    print(json.dumps(out["ray"]), flush=True)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
