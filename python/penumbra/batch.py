"""Batches of renders, in one process or on a Ray cluster, that survive a crash.

A job is a dict: `scene` (a scene file's path or a `Scene`), `technique` and any of
`Scene.render`'s options (`samples`, `backend`, `jitter`, `light`), and a `name` for its output
(by default its position and the scene file's stem). `run` writes each job's image to
`out_dir/<name>.exr` atomically (a whole file or none; on Ray the driver writes it, so that
`out_dir` need only be the driver's) and records each job in
`out_dir/manifest.jsonl`, one JSON object a line: its name, status ("done" or "failed"),
seconds, output, error and the Ray node that ran it. Run again over the same `out_dir`, it skips the jobs already done:
a batch stopped halfway resumes where it stopped. A failing job records its error and the
others go on::

    from penumbra import batch
    jobs = [{"scene": f, "technique": t} for f in files for t in ("reference", "pcss")]
    report = batch.run(jobs, "out", engine="ray")     # [{"name": ..., "status": ...}, ...]
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

from . import _penumbra

__all__ = ["run", "MANIFEST"]

MANIFEST = "manifest.jsonl"
_OPTIONS = ("samples", "backend", "jitter", "light", "threads")


def _name(k, job):
    if "name" in job:
        name = str(job["name"])
    else:
        scene = job.get("scene")
        stem = Path(scene).stem if isinstance(scene, (str, os.PathLike)) else "scene"
        name = f"{k:05d}-{stem}-{job.get('technique', 'wedges-blend')}"
    if not name or "/" in name or "\\" in name or name.startswith("."):
        raise ValueError(f"job {k}: name {name!r} must be a plain file name")
    return name


def _check(k, job):
    if not isinstance(job, dict) or "scene" not in job:
        raise ValueError(f"job {k}: give a dict with at least a 'scene' (a file or a Scene)")
    unknown = set(job) - {"scene", "technique", "name", *_OPTIONS}
    if unknown:
        raise ValueError(
            f"job {k}: unknown keys {sorted(unknown)}; a job takes scene, technique, name "
            f"and {', '.join(_OPTIONS)}"
        )


def _compute(job):
    """Renders one job: `(image, seconds, error, node)`, the image None where it failed, the
    Ray node that ran it (None outside Ray). Never raises for the job's own failure: it is the
    job's record, and the batch goes on."""
    from .study import _worker

    t0 = time.perf_counter()
    try:
        scene = job["scene"]
        if isinstance(scene, (str, os.PathLike)):
            scene = _penumbra.Scene.load(scene)
        options = {k: job[k] for k in _OPTIONS if k in job}
        v = scene.render(job.get("technique", "wedges-blend"), **options)
        return v, time.perf_counter() - t0, None, _worker()[0]
    except Exception as e:
        return None, time.perf_counter() - t0, f"{type(e).__name__}: {e}", _worker()[0]


def _write(name, out_dir, result):
    """Writes a computed job's image to `out_dir/<name>.exr` atomically (a temporary file
    renamed over it) and gives its manifest record."""
    v, seconds, error, node = result
    rec = {"name": name, "status": "failed", "seconds": round(seconds, 3), "output": None,
           "error": error, "node": node}
    if v is None:
        return rec
    out_path = Path(out_dir) / f"{name}.exr"
    tmp = out_path.with_name(f".{out_path.name}.{os.getpid()}.tmp")
    try:
        _penumbra.write_exr(tmp, v)
        os.replace(tmp, out_path)
        rec.update(status="done", output=str(out_path))
    except Exception as e:
        rec["error"] = f"{type(e).__name__}: {e}"
    finally:
        if tmp.exists():
            tmp.unlink()
    return rec


def _done(out_dir):
    """The names the manifest records as done, whose outputs are still there."""
    path = Path(out_dir) / MANIFEST
    done = set()
    if not path.exists():
        return done
    for line in path.read_text().splitlines():
        try:
            rec = json.loads(line)
        except json.JSONDecodeError:
            continue  # a line cut by a crash
        if rec.get("status") == "done" and rec.get("output") and Path(rec["output"]).exists():
            done.add(rec["name"])
        elif rec.get("status") == "failed":
            done.discard(rec.get("name"))
    return done


def _record(out_dir, rec):
    with open(Path(out_dir) / MANIFEST, "a") as f:
        f.write(json.dumps(rec) + "\n")
        f.flush()
        os.fsync(f.fileno())


def run(jobs, out_dir, engine="local", address=None):
    """Runs `jobs` (see the module) into `out_dir` on `engine` ("local": one after the other
    here; "ray": each a Ray task, `address` as for `penumbra.study.sun_hours`), skipping those
    the manifest records as done. Returns this run's records, in the jobs' order (a skipped
    job's status is "skipped")."""
    if engine not in ("local", "ray"):
        raise ValueError(f'engine {engine!r}: "local" or "ray"')
    jobs = list(jobs)
    names = []
    for k, job in enumerate(jobs):
        _check(k, job)
        names.append(_name(k, job))
    if len(set(names)) != len(names):
        raise ValueError("two jobs have the same name: give each a 'name' of its own")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    done = _done(out_dir)
    todo = [k for k, n in enumerate(names) if n not in done]
    records = [{"name": n, "status": "skipped"} for n in names]
    if engine == "local" or not todo:
        for k in todo:
            records[k] = _write(names[k], out_dir, _compute(jobs[k]))
            _record(out_dir, records[k])
        return records
    from .study import _ray

    ray = _ray()
    started = False
    if not ray.is_initialized():
        ray.init(address=address, include_dashboard=False, log_to_driver=False) \
            if address is None else ray.init(address=address, log_to_driver=False)
        started = True
    try:
        task = ray.remote(num_cpus=1, max_retries=5, retry_exceptions=False,
                          scheduling_strategy="SPREAD")(_compute)
        pending = {task.remote(jobs[k]): k for k in todo}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                k = pending.pop(ref)
                records[k] = _write(names[k], out_dir, ray.get(ref))
                _record(out_dir, records[k])
        return records
    finally:
        if started:
            ray.shutdown()
