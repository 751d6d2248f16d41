"""The Python package's costs, measured in one run (docs/benchmarks.md, "Python"):

- the binding's overhead: `Scene.render` against the `penumbra render` command on the same
  scene (load, render, write the EXR, in one process each), as a ratio of medians;
- two threads rendering at once against one, the renders sharing the process's pool (a thread
  per core) or each on a pool of one thread of its own (`threads=1`);
- the memory a million-point `visibility_at` adds to the process beyond its arrays.

Run from the repository's root after `pip install ./python`, with the command built in release
(`cargo build --release -p penumbra-tools`):
`python python/benchmarks/bench.py [--cli target/release/penumbra] [--rounds 5]`.
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

import penumbra as pb

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "fixtures" / "scenes" / "spot.toml"


def overhead(cli, rounds):
    out = Path(tempfile.mkdtemp())
    cases = [("depth-complexity", 256), ("wedges-blend", 256), ("reference", 64)]
    rows = []
    for technique, samples in cases:
        py, cmd = [], []
        for _ in range(rounds):
            t = time.perf_counter()
            subprocess.run([cli, "render", str(SCENE), "--technique", technique, "--backend", "cpu",
                            "--samples", str(samples), "--out", str(out / "c.exr")],
                           check=True, capture_output=True)
            cmd.append(time.perf_counter() - t)
            t = time.perf_counter()
            v = pb.Scene.load(SCENE).render(technique, samples=samples, backend="cpu")
            pb.write_exr(out / "p.exr", v)
            py.append(time.perf_counter() - t)
        rows.append({"technique": technique, "samples": samples,
                     "command_s": statistics.median(cmd), "python_s": statistics.median(py),
                     "ratio": statistics.median(py) / statistics.median(cmd)})
    return rows


THREADS = """
import sys, threading, time, penumbra as pb
scene = pb.Scene.load(sys.argv[1])
threads = int(sys.argv[2]) or None
def render():
    scene.render("depth-complexity", samples=1024, backend="cpu", threads=threads)
render()
t = time.perf_counter(); render(); one = time.perf_counter() - t
ts = [threading.Thread(target=render) for _ in range(2)]
t = time.perf_counter()
for x in ts: x.start()
for x in ts: x.join()
print(one, time.perf_counter() - t)
"""


def threads(per_render):
    out = subprocess.run([sys.executable, "-c", THREADS, str(SCENE), str(per_render or 0)],
                         check=True, capture_output=True, text=True).stdout.split()
    one, two = float(out[0]), float(out[1])
    return {"threads_per_render": per_render or "shared pool", "one_s": one,
            "two_at_once_s": two, "ratio": two / one}


def memory():
    scene = pb.Scene.load(ROOT / "fixtures" / "scenes" / "sun.toml")
    n = 1_000_000
    rng = np.random.default_rng(1)
    points = np.column_stack([rng.uniform(-3, 3, n), np.zeros(n), rng.uniform(-3, 3, n)])
    normals = np.tile([0.0, 1.0, 0.0], (n, 1))
    scene.visibility_at(points[:1000], normals[:1000], samples=64)  # the hierarchy, once
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    t = time.perf_counter()
    v = scene.visibility_at(points, normals, samples=64)
    took = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    return {"points": n, "arrays_bytes": points.nbytes + normals.nbytes, "result_bytes": v.nbytes,
            "peak_growth_bytes": after - before, "seconds": took}


def main():
    a = argparse.ArgumentParser()
    a.add_argument("--cli", default=str(ROOT / "target" / "release" / "penumbra"))
    a.add_argument("--rounds", type=int, default=5)
    args = a.parse_args()
    report = {"overhead": overhead(args.cli, args.rounds),
              "threads": [threads(None), threads(1)],
              "memory": memory()}
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
