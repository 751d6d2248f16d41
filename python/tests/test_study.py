"""Sun studies and batches in one process: the sun's positions against NREL's published SPA
values, the days' first and last steps with the sun across the horizon, sums that do not depend
on how a study is split, and batches that write atomically, record failures and resume."""

import json

import numpy as np
import pandas as pd
import pytest

import penumbra as pb
from penumbra import batch, study
from conftest import FIXTURES, ROOT


def open_ground(width=8, height=6):
    """A ground 40 wide with nothing on it, seen from above."""
    ground = pb.Mesh([[-20, 0, -20], [20, 0, -20], [20, 0, 20], [-20, 0, 20]],
                     [[0, 2, 1], [0, 3, 2]], name="ground")
    camera = pb.Camera(eye=(0, 5, 5), target=(0, 0, 0), width=width, height=height)
    return pb.Scene(camera, pb.DistantLight.sun(180, 45), [ground])


def test_sun_positions_match_spa_s_published_example():
    # Reda and Andreas (2004), "Solar position algorithm for solar radiation applications",
    # Table A5.1: Golden, Colorado, 17 October 2003 12:30:30 at UTC-7, 1830.14 m, 820 mbar,
    # 11 degrees C, delta T 67 s: topocentric zenith 50.11162, azimuth 194.34024 degrees.
    times = pd.DatetimeIndex(["2003-10-17 12:30:30-07:00"])
    az, el = study.sun_positions(39.742476, -105.1786, times, altitude=1830.14,
                                 pressure=82000, temperature=11, delta_t=67)
    assert abs(az[0] - 194.34024) < 0.01
    assert abs((90 - el[0]) - 50.11162) < 0.01
    # Noon at the June solstice on the Tropic of Cancer: the sun near the zenith.
    _, el = study.sun_positions(23.44, 0.0, pd.DatetimeIndex(["2026-06-21 12:00Z"]))
    assert el[0] > 88.0


def test_sun_positions_refuse_what_has_no_instant_or_place():
    with pytest.raises(ValueError, match="time zone"):
        study.sun_positions(48.0, 2.0, pd.DatetimeIndex(["2026-06-21 12:00"]))
    with pytest.raises(ValueError, match="latitude 91"):
        study.sun_positions(91, 2.0, pd.DatetimeIndex(["2026-06-21 12:00Z"]))
    with pytest.raises(ValueError, match="not after its start"):
        study.sun_steps(48.0, 2.0, "2026-06-22", "2026-06-21")
    with pytest.raises(ValueError, match="3 weights for 24 steps"):
        study.sun_steps(48.0, 2.0, "2026-06-21", "2026-06-22", weights=[1, 2, 3])


def test_the_first_and_last_daylight_steps_see_the_part_of_the_sun_above_the_horizon():
    # Minute steps through sunrise and sunset in Paris: a sensor on open ground sees the part
    # of the sun's (square) disk above its plane, (e + r) / 2r for a centre at elevation e
    # within the radius r of the horizon; steps wholly below it are night and count nothing.
    scene, r = open_ground(), 0.265
    sensor = dict(points=[[0.0, 0.0, 0.0]], normals=[0.0, 1.0, 0.0])
    for start, end in (("2026-03-20 05:40", "2026-03-20 06:10"),
                       ("2026-03-20 17:50", "2026-03-20 18:20")):
        steps = study.sun_steps(48.85, 2.35, start, end, step_minutes=1, timezone="UTC")
        e = steps.elevation_deg
        assert e.min() < -r and e.max() > r, "the steps cross the horizon"
        across = (e > -r) & (e < r)
        assert across.sum() >= 2
        want = np.clip((e + r) / (2 * r), 0.0, 1.0).sum() / 60.0
        got = study.sun_hours(scene, 48.85, 2.35, start, end, step_minutes=1,
                              samples=1024, **sensor)
        # 32 rows of samples: each partial step within 1/32 of its share.
        assert abs(got[0] - want) <= across.sum() / 32 / 60 + 1e-9, (got, want)
        assert got[0] < (e > -r).sum() / 60.0


def test_a_study_s_sum_does_not_depend_on_its_runs_and_night_costs_nothing():
    scene = pb.Scene.load(FIXTURES / "sun.toml").with_size(40, 30)
    args = (scene, 48.85, 2.35, "2026-06-21", "2026-06-22")
    a = study.sun_hours(*args, timezone="Europe/Paris", samples=16, chunk_steps=24)
    b = study.sun_hours(*args, timezone="Europe/Paris", samples=16, chunk_steps=5)
    assert a.shape == (30, 40) and a.dtype == np.float64
    # Summed in the steps' order either way; runs of 5 add the runs' sums, so allow rounding.
    assert np.allclose(a, b, atol=1e-12)
    assert a.max() == pytest.approx(16.0)  # 16 hourly daylight steps at the solstice
    assert a.min() >= 0.0
    # A night: nothing rendered, zeros of the image's shape.
    seen = []
    night = study.sun_hours(scene, 48.85, 2.35, "2026-12-21 20:00", "2026-12-21 23:00",
                            timezone="Europe/Paris", progress=seen.append)
    assert night.shape == (30, 40) and not night.any() and seen == []
    # Weights multiply each step's hours.
    w = np.full(24, 2.0)
    doubled = study.sun_hours(*args, timezone="Europe/Paris", samples=16, weights=w)
    assert np.array_equal(doubled, 2.0 * a)
    # Again on the scene, whose renderer kept what the studies share: the same bits.
    again = study.sun_hours(*args, timezone="Europe/Paris", samples=16, chunk_steps=24)
    assert np.array_equal(again, a)


def test_sensor_points_over_a_day_against_the_reference():
    scene = pb.Scene.load(FIXTURES / "sun.toml")
    x, z = np.meshgrid(np.linspace(-2, 3, 12), np.linspace(-2, 3, 12))
    grid = np.column_stack([x.ravel(), np.zeros(x.size), z.ravel()])
    kw = dict(timezone="Europe/Paris", samples=64, points=grid, normals=[0, 1, 0])
    exact = study.sun_hours(scene, 48.85, 2.35, "2026-06-21", "2026-06-22", **kw)
    rays = study.sun_hours(scene, 48.85, 2.35, "2026-06-21", "2026-06-22",
                           technique="reference", **kw)
    assert exact.shape == (144,)
    assert exact.min() < 12 and exact.max() == pytest.approx(16.0)  # the cow shades some
    assert np.abs(exact - rays).max() < 0.05 * 16


def test_a_scene_pickles_to_the_same_pixels():
    import pickle

    scene = pb.Scene.load(FIXTURES / "spot.toml").with_size(40, 30)
    back = pickle.loads(pickle.dumps(scene))
    assert repr(back) == repr(scene)
    for t in ("hard", "depth-complexity"):
        assert np.array_equal(back.render(t, samples=16, backend="cpu"),
                              scene.render(t, samples=16, backend="cpu"))
    ground = pickle.loads(pickle.dumps(open_ground()))
    assert ground.triangle_count == 2


def test_a_batch_writes_each_output_whole_records_failures_and_resumes(tmp_path):
    spot = FIXTURES / "spot.toml"
    small = pb.Scene.load(spot).with_size(24, 18)
    jobs = [
        {"scene": small, "technique": "hard", "backend": "cpu", "name": "spot-hard"},
        {"scene": str(tmp_path / "missing.toml"), "technique": "hard", "name": "missing"},
        {"scene": small, "technique": "depth-complexity", "samples": 16, "backend": "cpu"},
    ]
    out = tmp_path / "out"
    records = batch.run(jobs, out)
    assert [r["status"] for r in records] == ["done", "failed", "done"]
    assert "FileNotFoundError" in records[1]["error"] and "missing.toml" in records[1]["error"]
    v = pb.read_exr(out / "spot-hard.exr")["V"]
    assert np.array_equal(v, small.render("hard", backend="cpu"))
    assert sorted(p.name for p in out.iterdir()) == [
        "00002-scene-depth-complexity.exr", "manifest.jsonl", "spot-hard.exr"]
    manifest = [json.loads(line) for line in (out / batch.MANIFEST).read_text().splitlines()]
    assert [m["status"] for m in manifest] == ["done", "failed", "done"]
    # Again: the done jobs are skipped, the failed one is tried again.
    again = batch.run(jobs, out)
    assert [r["status"] for r in again] == ["skipped", "failed", "skipped"]
    # A crash left a cut line and lost an output: that job is done again.
    (out / "spot-hard.exr").unlink()
    with open(out / batch.MANIFEST, "a") as f:
        f.write('{"name": "spot-h')
    third = batch.run(jobs, out)
    assert [r["status"] for r in third] == ["done", "failed", "skipped"]
    assert np.array_equal(pb.read_exr(out / "spot-hard.exr")["V"], v)
    with pytest.raises(ValueError, match="same name"):
        batch.run([jobs[0], jobs[0]], out)
    with pytest.raises(ValueError, match="unknown keys"):
        batch.run([{"scene": small, "samplez": 4}], out)


def test_bad_studies_are_refused_with_what_is_wrong(tmp_path):
    import pickle

    scene = open_ground()
    day = (scene, 48.85, 2.35, "2026-06-21", "2026-06-22")
    with pytest.raises(ValueError, match="angular"):
        study.sun_hours(*day, angular_size_deg=0.0)
    with pytest.raises(ValueError, match="finite"):
        study.sun_hours(*day, weights=[np.nan] * 24)
    with pytest.raises(ValueError, match=r"shape \(n, 3\)"):
        study.sun_hours(*day, points=[[0.0, 0.0]], normals=[0, 1, 0])
    with pytest.raises(ValueError, match="normal"):
        study.sun_hours(*day, points=[[0.0, 0.0, 0.0]], normals=[0, 0, 0])
    with pytest.raises(ValueError, match="points and normals together"):
        study.sun_hours(*day, points=[[0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="2 points and 3 normals"):
        study.sun_hours(*day, points=[[0.0, 0.0, 0.0]] * 2, normals=[[0, 1, 0]] * 3)
    with pytest.raises(ValueError, match="engine"):
        study.sun_hours(*day, engine="spark")
    with pytest.raises(ValueError, match="samples"):
        study.sun_hours(*day, samples=10)
    # A scene whose shadow-map parameters are its own does not pickle silently without them.
    text = (FIXTURES / "spot.toml").read_text().replace(
        '"../meshes/', f'"{(FIXTURES.parent / "meshes").resolve()}/')
    (tmp_path / "s.toml").write_text(text + "\n[shadow_map]\nresolution = 512\n")
    tuned = pb.Scene.load(tmp_path / "s.toml")
    with pytest.raises(ValueError, match="shadow-map parameters"):
        pickle.dumps(tuned)
    with pytest.raises(ValueError, match="unit"):
        pb.write_colour_map(tmp_path / "m.png", np.ones((3, 4)), unit="kWh")
    with pytest.raises(ValueError, match="from 0 up"):
        pb.write_colour_map(tmp_path / "m.png", -np.ones((3, 4)))
    assert not (tmp_path / "m.png").exists()
    pb.write_colour_map(tmp_path / "m.png", np.arange(12.0).reshape(3, 4))
    assert (tmp_path / "m.png").read_bytes()[:4] == b"\x89PNG"


def test_the_ray_engine_without_ray_says_how_to_install_it(monkeypatch):
    import builtins

    real = builtins.__import__

    def no_ray(name, *args, **kwargs):
        if name == "ray" or name.startswith("ray."):
            raise ImportError("No module named 'ray'")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_ray)
    monkeypatch.delitem(__import__("sys").modules, "ray", raising=False)
    with pytest.raises(ImportError, match=r"penumbra\[ray\]"):
        study.sun_hours(open_ground(), 48.85, 2.35, "2026-06-21 10:00", "2026-06-21 12:00",
                        engine="ray")
