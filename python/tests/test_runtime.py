"""How renders behave in a Python program: off the GIL (two threads render at once), stopped
by Ctrl-C with KeyboardInterrupt, and failing with the exceptions Python programs expect."""

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import penumbra as pb
from conftest import FIXTURES, ROOT


def test_two_threads_render_at_once_and_get_what_one_gets():
    scene = pb.Scene.load(FIXTURES / "spheres-9x9.toml").with_size(160, 120)
    want = scene.render("reference", samples=64, backend="cpu")
    spans, images = {}, {}

    def render(k):
        start = time.perf_counter()
        images[k] = scene.render("reference", samples=64, backend="cpu")
        spans[k] = (start, time.perf_counter())

    threads = [threading.Thread(target=render, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(images[k], want) for k in range(2))
    # The two renders ran at the same time: each began before the other ended.
    (a0, a1), (b0, b1) = spans[0], spans[1]
    assert a0 < b1 and b0 < a1
    # On pools of their own, one thread each: the same pixels.
    assert np.array_equal(scene.render("reference", samples=64, backend="cpu", threads=1), want)
    with pytest.raises(ValueError, match="threads"):
        scene.render("hard", threads=0)


def test_a_long_render_shows_its_progress_on_a_terminal():
    import pty

    script = textwrap.dedent(f"""
        import penumbra as pb
        scene = pb.Scene.load({str(FIXTURES / "spheres-9x9.toml")!r}).with_size(80, 60)
        scene.render("reference", samples=4096, backend="cpu", threads=1)  # seconds
        print("done")
    """)
    main, sub = pty.openpty()
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=sub)
    os.close(sub)
    out, _ = p.communicate(timeout=300)
    shown = b""
    while True:
        try:
            chunk = os.read(main, 4096)
        except OSError:
            break
        if not chunk:
            break
        shown += chunk
    os.close(main)
    assert p.returncode == 0 and out.strip() == b"done"
    assert b"reference" in shown and b"%" in shown, shown


def test_ctrl_c_stops_a_long_render_with_keyboard_interrupt():
    # The reference at 65536 samples over 320 x 240 pixels: minutes of work.
    script = textwrap.dedent(f"""
        import sys, penumbra as pb
        scene = pb.Scene.load({str(FIXTURES / "spheres-9x9.toml")!r})
        print("rendering", flush=True)
        try:
            scene.render("reference", samples=65536, backend="cpu")
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(3)
        print("finished", flush=True)
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "rendering"
    time.sleep(1.0)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    took = time.monotonic() - sent
    assert p.returncode == 3 and out.strip() == "interrupted", out
    # Far sooner than the render would take: the render stopped, not finished.
    assert took < 3, took


def test_errors_are_the_exceptions_python_expects(tmp_path):
    with pytest.raises(FileNotFoundError):
        pb.Scene.load(tmp_path / "missing.toml")
    with pytest.raises(FileNotFoundError):
        pb.read_exr(tmp_path / "missing.exr")
    bad = tmp_path / "bad.toml"
    text = (FIXTURES / "quad-over-plane.toml").read_text().replace("fov_y_deg = 45.0", "fov_y_deg = -5.0")
    bad.write_text(text)
    line = next(k for k, l in enumerate(text.splitlines(), 1) if l.startswith("fov_y_deg"))
    with pytest.raises(ValueError, match=f"bad.toml:{line}:"):
        pb.Scene.load(bad)
    no_mesh = tmp_path / "no-mesh.toml"
    no_mesh.write_text((FIXTURES / "quad-over-plane.toml").read_text())  # ../meshes is not here
    with pytest.raises(FileNotFoundError, match="quad.obj"):
        pb.Scene.load(no_mesh)
    scene = pb.Scene.load(FIXTURES / "quad-over-plane.toml").with_size(8, 6)
    with pytest.raises(ValueError, match="unknown technique"):
        scene.render("soft")
    with pytest.raises(ValueError, match="backend"):
        scene.render("hard", backend="tpu")
    with pytest.raises(ValueError, match="perfect square"):
        scene.render("reference", samples=1000)
    with pytest.raises(ValueError, match="jitter"):
        scene.render("hard", jitter=True)
    with pytest.raises(ValueError):
        pb.write_exr(tmp_path / "v.exr", np.full((4, 4), np.nan))
    assert not (tmp_path / "v.exr").exists()
    with pytest.raises(ValueError, match="2-D"):
        pb.write_exr(tmp_path / "v.exr", np.zeros(5))


def test_the_examples_run(tmp_path):
    examples = sorted((ROOT / "python" / "examples").glob("*.py"))
    assert len(examples) >= 3
    for e in examples:
        r = subprocess.run([sys.executable, str(e), str(tmp_path)], cwd=ROOT, capture_output=True,
                           text=True, env={**os.environ, "PENUMBRA_EXAMPLE_SMALL": "1"})
        assert r.returncode == 0, f"{e.name}: {r.stderr}"


def test_work_beyond_the_memory_is_refused_before_it_starts():
    scene = pb.Scene.load(FIXTURES / "quad-over-plane.toml")
    # Ten billion points that numpy holds in 24 bytes (a view repeating one row).
    huge = np.broadcast_to(np.zeros(3), (10**10, 3))
    with pytest.raises(MemoryError, match="10000000000 points"):
        scene.visibility_at(huge, (0, 1, 0))
    with pytest.raises(MemoryError):
        scene.with_size(200_000, 200_000).render("hard", backend="cpu")


def test_one_scene_serves_threads_that_render_and_query_at_once():
    scene = pb.Scene.load(FIXTURES / "sphere-over-plane.toml").with_size(64, 48)
    p = np.column_stack([np.linspace(-2, 2, 500), np.zeros(500), np.zeros(500)])
    want_image = scene.render("depth-complexity", samples=64, backend="cpu")
    want_points = scene.visibility_at(p, (0, 1, 0), samples=64)
    results, errors = [], []

    def work(k):
        try:
            if k % 2:
                results.append(np.array_equal(scene.render("depth-complexity", samples=64, backend="cpu"), want_image))
            else:
                results.append(np.array_equal(scene.visibility_at(p, (0, 1, 0), samples=64), want_points))
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and results == [True] * 6
