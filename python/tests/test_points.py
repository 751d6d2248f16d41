"""Visibility at sensor points: the command's values, the pixels' values where sensors stand
on pixels' surface points, and exact depth complexity against many rays on real meshes."""

import re
import subprocess

import numpy as np
import pytest

import penumbra as pb
from conftest import FIXTURES, ROOT

MESHFILES = ROOT / "fixtures" / "meshfiles"


def floor_grid(n, half):
    x, z = np.meshgrid(np.linspace(-half, half, n), np.linspace(-half, half, n))
    return np.stack([x.ravel(), np.zeros(n * n), z.ravel()], axis=1)


def test_sensors_are_the_commands_points(cli, tmp_path):
    scene_file = FIXTURES / "two-lights.toml"
    scene = pb.Scene.load(scene_file)
    p = floor_grid(12, 3.0)
    rows = np.hstack([p, np.tile([0.0, 1.0, 0.0], (len(p), 1))])
    np.save(tmp_path / "p.npy", rows)
    for technique in ["depth-complexity", "reference"]:
        subprocess.run(
            [cli, "points", str(scene_file), "--points", str(tmp_path / "p.npy"), "--out",
             str(tmp_path / "v.npy"), "--samples", "64", "--technique", technique],
            check=True, capture_output=True,
        )
        want = np.load(tmp_path / "v.npy")
        got = scene.visibility_at(p, (0, 1, 0), samples=64, technique=technique)
        assert list(got) == ["key", "fill"] and want.shape == (len(p), 2)
        assert np.array_equal(got["key"], want[:, 0]) and np.array_equal(got["fill"], want[:, 1])
        assert ((want > 0) & (want < 1)).any() and (want == 1).any()


def test_inputs_of_any_precision_and_strides_give_the_same_values():
    scene = pb.Scene.load(FIXTURES / "sphere-over-plane.toml")
    p = floor_grid(20, 2.0)
    want = scene.visibility_at(p, np.tile([0.0, 1.0, 0.0], (len(p), 1)), samples=64)
    assert want.dtype == np.float32 and want.shape == (len(p),)
    wide = np.zeros((len(p), 6))
    wide[:, 1::2] = p
    f32 = p.astype(np.float32)
    for points, normals in [
        (wide[:, 1::2], (0, 1, 0)),
        (np.asfortranarray(p), np.array([0, 2, 0], dtype=np.int32)),
        (p.tolist(), [0.0, 1.0, 0.0]),
    ]:
        assert np.array_equal(scene.visibility_at(points, normals, samples=64), want)
    # float32 rounds the points: the same values but for points on a shadow's very edge.
    assert (scene.visibility_at(f32, (0, 1, 0), samples=64) != want).mean() < 0.02


def test_sensors_at_the_pixels_points_see_what_the_pixels_see():
    # quad-over-plane seen at 40 x 30: a 2 x 2 quad 1 above a 20 x 20 floor. Sensor k takes
    # the samples of pixel k, so the query is every pixel's floor point in pixel order.
    scene = pb.Scene.load(FIXTURES / "quad-over-plane.toml").with_size(40, 30)
    image = scene.render("reference", samples=64, backend="cpu")
    eye = np.array([0.0, 6.0, 7.0])
    f = -eye / np.linalg.norm(eye)
    r = np.cross(f, [0.0, 1.0, 0.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    t = np.tan(np.radians(45) / 2)
    j, i = np.mgrid[0:30, 0:40]
    d = (f + ((2 * (i + 0.5) / 40 - 1) * t * 40 / 30)[..., None] * r
         + ((1 - 2 * (j + 0.5) / 30) * t)[..., None] * u).reshape(-1, 3)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    floor = eye - (eye[1] / d[:, 1:2]) * d
    at_quad = eye + ((eye[1] - 1) / -d[:, 1:2]) * d
    sees_floor = ~((np.abs(at_quad[:, 0]) <= 1.01) & (np.abs(at_quad[:, 2]) <= 1.01))
    v = scene.visibility_at(floor, (0, 1, 0), samples=64, technique="reference")
    jittered = scene.visibility_at(floor, (0, 1, 0), samples=64, jitter=True)
    pixels = image.ravel()
    assert sees_floor.sum() > 1000 and ((pixels > 0) & (pixels < 1) & sees_floor).sum() > 20
    assert (v[sees_floor] == pixels[sees_floor]).mean() > 0.99
    assert (jittered[sees_floor] == pixels[sees_floor]).mean() > 0.99


def test_counted_sensors_on_real_meshes_agree_with_many_rays():
    # A glTF cow and a PLY scan of 268,686 triangles under a large light: points on the floor
    # around them and on the meshes, facing up.
    scene = pb.Scene.load(MESHFILES / "igea-and-spot.toml")
    rng = np.random.default_rng(7)
    p = np.column_stack([rng.uniform(-4, 2, 400), np.zeros(400), rng.uniform(-3, 2, 400)])
    counted = scene.visibility_at(p, (0, 1, 0), samples=1024)
    cast = scene.visibility_at(p, (0, 1, 0), samples=4096, technique="reference")
    assert ((cast > 0.02) & (cast < 0.98)).sum() > 20
    assert np.abs(counted - cast).mean() < 0.01


def test_bad_points_raise_value_error():
    scene = pb.Scene.load(FIXTURES / "quad-over-plane.toml")
    for points, normals, words in [
        (np.zeros((3, 2)), (0, 1, 0), "(n, 3)"),
        (np.zeros((3, 3)), np.zeros((2, 3)), "3 points and 2 normals"),
        (np.zeros((3, 3)), (0, 0, 0), "sensor 0: normal"),
        ([[0, 0, np.nan]], (0, 1, 0), "sensor 0: point"),
        (np.array([["a", "b", "c"]]), (0, 1, 0), "numbers"),
    ]:
        with pytest.raises(ValueError, match=re.escape(words)):
            scene.visibility_at(points, normals)
    with pytest.raises(ValueError, match="wedges"):
        scene.visibility_at(np.zeros((1, 3)), (0, 1, 0), technique="wedges")
