"""Sun studies: hours of direct sun over days or a year, at every pixel or at sensor points,
in one process or on a Ray cluster.

The sun's positions come from pvlib's implementation of NREL's Solar Position Algorithm
(Reda and Andreas 2004), not derived again. At each step whose sun shows any of its disk above
the horizon, the scene's lights are replaced by the sun (a distant light of the sun's angular
size) and the visibility of its disk is taken at every pixel or point; the hours of direct sun
are the sum of that visibility times each step's length (times a weight, where given)::

    import penumbra as pb
    from penumbra import study
    scene = pb.Scene.load("fixtures/scenes/sun.toml")
    hours = study.sun_hours(scene, 51.5, -0.13, "2026-06-21", "2026-06-22",
                            timezone="Europe/London")          # (height, width) float64

A study is split into runs of steps (`chunk_steps` daylight steps each), summed in f64 in the
steps' order within a run and in the runs' order across them: the same study gives the same
bits in one process and on Ray, however many workers there are and whichever of them fails.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass

import numpy as np

from . import _penumbra

__all__ = ["sun_positions", "sun_steps", "sun_hours", "SunSteps"]


def _pandas():
    try:
        import pandas as pd
        import pvlib
    except ImportError as e:  # pragma: no cover - the error names what to install
        raise ImportError(
            "penumbra.study needs pandas and pvlib: pip install 'penumbra[study]'"
        ) from e
    return pd, pvlib


def sun_positions(latitude, longitude, times, altitude=0.0, pressure=101325.0,
                  temperature=12.0, delta_t=None):
    """The sun's apparent position (refraction included) at `times`, seen from `latitude`,
    `longitude` (degrees, east positive) and `altitude` (metres): `(azimuth_deg,
    elevation_deg)`, float64 arrays, azimuth clockwise from north. `times` is a pandas
    `DatetimeIndex` or a sequence of datetimes, with a time zone (a naive time is refused:
    its instant is unknown). NREL's SPA by pvlib (`method="nrel_numpy"`); `pressure` (Pa) and
    `temperature` (degrees C) set the refraction, `delta_t` (TT - UT1, seconds) pvlib's
    estimate where None."""
    pd, pvlib = _pandas()
    if not (-90.0 <= float(latitude) <= 90.0):
        raise ValueError(f"latitude {latitude}: give degrees in [-90, 90]")
    if not (-180.0 <= float(longitude) <= 180.0):
        raise ValueError(f"longitude {longitude}: give degrees in [-180, 180], east positive")
    index = pd.DatetimeIndex(times)
    if index.tz is None:
        raise ValueError(
            "times have no time zone: give aware datetimes, or a DatetimeIndex with tz= "
            "(for example pandas.date_range(..., tz='Europe/London'))"
        )
    kwargs = {} if delta_t is None else {"delta_t": delta_t}
    sp = pvlib.solarposition.get_solarposition(
        index, latitude, longitude, altitude=altitude, pressure=pressure,
        temperature=temperature, method="nrel_numpy", **kwargs,
    )
    return sp["azimuth"].to_numpy(np.float64), sp["apparent_elevation"].to_numpy(np.float64)


@dataclass
class SunSteps:
    """The steps of a study: their times, the sun's azimuth and elevation at each (degrees),
    and each step's weight in hours (its length, times a weight where given)."""

    times: object
    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    hours: np.ndarray

    def daylight(self, angular_size_deg=0.53):
        """The indices of the steps whose sun shows any of its disk above the horizon (centre
        above minus its radius) and whose weight is not zero: the steps that are rendered."""
        return _penumbra._daylight(np.ascontiguousarray(self.elevation_deg, dtype=np.float64),
                                   np.ascontiguousarray(self.hours, dtype=np.float64),
                                   angular_size_deg)


def sun_steps(latitude, longitude, start, end, step_minutes=60, timezone="UTC",
              weights=None, **position):
    """The steps from `start` (included) to `end` (excluded) every `step_minutes`, in
    `timezone` (an IANA name such as "Europe/Paris"; times given with a zone keep theirs),
    the sun at each step's start, each weighing `step_minutes / 60` hours times its weight in
    `weights` (one per step) where given. `position` goes to `sun_positions`."""
    pd, _ = _pandas()
    if not (step_minutes > 0):
        raise ValueError(f"step_minutes {step_minutes}: give a positive length")
    start, end = pd.Timestamp(start), pd.Timestamp(end)
    start = start.tz_localize(timezone) if start.tz is None else start
    end = end.tz_localize(timezone) if end.tz is None else end
    if not end > start:
        raise ValueError(f"the study ends at {end}, not after its start {start}")
    times = pd.date_range(start, end, freq=pd.Timedelta(minutes=step_minutes),
                          inclusive="left")
    azimuth, elevation = sun_positions(latitude, longitude, times, **position)
    hours = np.full(len(times), step_minutes / 60.0)
    if weights is not None:
        w = np.asarray(weights, dtype=np.float64).reshape(-1)
        if len(w) != len(times):
            raise ValueError(f"{len(w)} weights for {len(times)} steps: give one per step")
        if not np.all(np.isfinite(w)):
            raise ValueError("weights: every weight must be a finite number")
        hours = hours * w
    return SunSteps(times, azimuth, elevation, hours)


def _chunks(indices, size):
    return [indices[i:i + size] for i in range(0, len(indices), size)]


# Per worker process: the scenes it has loaded, by the key the driver gave them, so that a
# worker takes its scene from the object store once for all its runs.
_LOADED = {}


def _run(scene, steps, index, options, threads=None):
    """The sum over the steps `index` of `steps`: one run."""
    return _penumbra._sun_hours(
        scene, steps.azimuth_deg[index], steps.elevation_deg[index], steps.hours[index],
        threads=threads, **options,
    )


def _worker():
    """Where a run ran: the Ray node's id (None outside Ray) and the process's peak resident
    memory in MB (0 where the system does not say)."""
    node = None
    if "ray" in sys.modules:
        import ray

        if ray.is_initialized():
            node = ray.get_runtime_context().get_node_id()
    try:
        import resource

        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kB on Linux
    except ImportError:  # Windows
        peak = 0.0
    return node, peak


def _ray_run(key, boxed, azimuth, elevation, hours, options):
    """One run as a Ray task, on one thread, the scene loaded once per worker process."""
    import ray

    loaded = _LOADED.get(key)
    if loaded is None:
        loaded = ray.get(boxed[0])
        _LOADED.clear()
        _LOADED[key] = loaded
    total = _penumbra._sun_hours(loaded, azimuth, elevation, hours, threads=1, **options)
    return total, _worker()


def _report(progress, done, total, node, peak_mb, terminal=True):
    """Tells `progress` of a finished run, or shows it on a terminal (where `terminal`: in one
    process each run shows its own)."""
    if progress is not None:
        progress({"done": done, "total": total, "node": node, "peak_mb": peak_mb})
    elif terminal and sys.stderr.isatty():
        print(f"\rsun steps {done}/{total}", end="\n" if done == total else "",
              file=sys.stderr)


def _ray():
    """Ray, or an ImportError that says how to install it."""
    try:
        import ray
    except ImportError as e:
        raise ImportError(
            'engine="ray" needs Ray: pip install "penumbra[ray]" (or pip install ray)'
        ) from e
    return ray


def _on_ray(scene, steps, runs, options, address, progress):
    """The runs' sums as Ray tasks, in the runs' order."""
    ray = _ray()

    started = False
    if not ray.is_initialized():
        if address is None:
            ray.init(include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=address, log_to_driver=False)
        started = True
    try:
        scene_ref = ray.put(scene)
        key = f"{os.getpid()}-{id(scene)}-{time.time_ns()}"
        # Runs spread over the nodes (each a CPU-bound task). A task whose worker or node dies
        # is run again (Ray's retries of system failures);
        # an error of the request itself is raised at once.
        run = ray.remote(num_cpus=1, max_retries=5, retry_exceptions=False,
                         scheduling_strategy="SPREAD")(_ray_run)
        pending = {}
        for k, index in enumerate(runs):
            ref = run.remote(key, [scene_ref], steps.azimuth_deg[index],
                             steps.elevation_deg[index], steps.hours[index], options)
            pending[ref] = k
        results = [None] * len(runs)
        done, total = 0, sum(len(i) for i in runs)
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                k = pending.pop(ref)
                results[k], (node, peak) = ray.get(ref)
                done += len(runs[k])
                _report(progress, done, total, node, peak)
        return results
    finally:
        if started:
            ray.shutdown()


def sun_hours(scene, latitude, longitude, start, end, step_minutes=60, timezone="UTC",
              technique="depth-complexity", samples=64, angular_size_deg=0.53, points=None,
              normals=None, weights=None, engine="local", address=None, chunk_steps=24,
              north=None, up=None, backend="cpu", progress=None):
    """The hours of direct sun of `scene` (a `Scene` or a scene file's path) at `latitude`,
    `longitude` from `start` to `end` every `step_minutes` (see `sun_steps`): float64,
    `(height, width)` for the camera's pixels, or `(n,)` for `points` and `normals` (`(n, 3)`;
    one normal for all may be given). The scene's lights are replaced by the sun, of full
    angle `angular_size_deg`, at each step; `technique` is "depth-complexity" (exact for its
    `samples`) or "reference" (rays), or for pixels any technique. `weights`, one per step
    (direct normal irradiance from a weather file, say), turn hours into a weighted sum.
    `north` and `up` give the scene's frame (default `-z` north, `+y` up).

    `engine="local"` runs here on every core; `engine="ray"` sends runs of `chunk_steps`
    daylight steps out as Ray tasks, the scene put in the object store once: `address=None`
    starts a local cluster (and stops it after), `"auto"` or `"ray://host:port"` joins one
    (a cluster already joined with `ray.init` is used as it is). A run whose worker dies is
    run again elsewhere. The result is the same bits on either engine.

    `progress`, where given, is called after each run with a dict: `done` and `total`
    daylight steps, the Ray `node` that ran it (None in one process) and that worker's peak
    resident memory `peak_mb`; without it, progress is shown on a terminal."""
    if isinstance(scene, (str, os.PathLike)):
        scene = _penumbra.Scene.load(scene)
    if engine not in ("local", "ray"):
        raise ValueError(f'engine {engine!r}: "local" or "ray"')
    if int(chunk_steps) < 1:
        raise ValueError(f"chunk_steps {chunk_steps}: give 1 or more")
    steps = sun_steps(latitude, longitude, start, end, step_minutes, timezone, weights)
    # Sensors as arrays: compact in Ray's object store, and read once by each run.
    def array(a):
        return None if a is None else np.ascontiguousarray(a, dtype=np.float64)

    options = dict(angular_size_deg=angular_size_deg, technique=technique, samples=samples,
                   backend=backend, points=array(points), normals=array(normals), north=north,
                   up=up)
    runs = _chunks(steps.daylight(angular_size_deg), int(chunk_steps))
    # An empty run checks the request and gives the result's shape (a study all night).
    total = _run(scene, steps, np.zeros(0, dtype=np.int64), options)
    if engine == "ray" and runs:
        results = _on_ray(scene, steps, runs, options, address, progress)
    else:
        results = _here(scene, steps, runs, options, progress)
    for r in results:
        total = total + r
    return total


def _here(scene, steps, runs, options, progress):
    """The runs' sums in this process, one after the other."""
    done, total = 0, sum(len(i) for i in runs)
    for index in runs:
        r = _run(scene, steps, index, options)
        done += len(index)
        _report(progress, done, total, None, _worker()[1], terminal=False)
        yield r
