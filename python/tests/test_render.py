"""Renders from Python are the command's: the same pixels, bit for bit, for every technique
that runs on the CPU on every fixture; several lights come back as a dict in the file's order."""

import subprocess

import numpy as np
import pytest

import penumbra as pb
from conftest import FIXTURES, fixture_names, small_scene

CPU_TECHNIQUES = ["reference", "hard-reference", "depth-complexity", "hard", "wedges", "wedges-blend"]


@pytest.mark.parametrize("name", fixture_names())
def test_render_is_the_commands_exr_bit_for_bit(name, cli, tmp_path):
    scene_file = small_scene(FIXTURES / f"{name}.toml", tmp_path, 48, 36)
    scene = pb.Scene.load(scene_file)
    assert (scene.height, scene.width) == (36, 48)
    for t in CPU_TECHNIQUES:
        out = tmp_path / f"{t}.exr"
        subprocess.run(
            [cli, "render", str(scene_file), "--technique", t, "--backend", "cpu",
             "--samples", "16", "--out", str(out)],
            check=True, capture_output=True,
        )
        want = pb.read_exr(out)
        got = scene.render(t, samples=16, backend="cpu")
        if len(want) == 1:
            got = {"V": got}
        else:
            got = {f"{k}.V": v for k, v in got.items()}
        assert list(got) == list(want), t
        for k in want:
            assert got[k].dtype == np.float32 and got[k].shape == (36, 48)
            assert np.array_equal(got[k], want[k]), f"{name} {t} {k}"


def test_several_lights_are_a_dict_in_file_order_and_one_can_be_asked_for():
    scene = pb.Scene.load(FIXTURES / "two-lights.toml").with_size(40, 30)
    assert scene.light_names == ["key", "fill"]
    both = scene.render("hard", backend="cpu")
    assert list(both) == ["key", "fill"]
    fill = scene.render("hard", backend="cpu", light="fill")
    assert np.array_equal(fill, both["fill"])
    assert not np.array_equal(both["key"], both["fill"])
    with pytest.raises(ValueError, match='"key", "fill"'):
        scene.render("hard", light="rim")


def test_images_round_trip_through_exr_files(tmp_path):
    scene = pb.Scene.load(FIXTURES / "two-lights.toml").with_size(40, 30)
    both = scene.render("hard", backend="cpu")
    pb.write_exr(tmp_path / "v.exr", both)
    back = pb.read_exr(tmp_path / "v.exr")
    assert list(back) == ["key.V", "fill.V"]
    assert np.array_equal(back["key.V"], both["key"])
    one = both["key"][::2, ::3]  # a strided view
    pb.write_exr(tmp_path / "one.exr", one)
    assert np.array_equal(pb.read_exr(tmp_path / "one.exr")["V"], one)


def test_compare_measures_against_the_reference():
    scene = pb.Scene.load(FIXTURES / "sphere-over-plane.toml").with_size(64, 48)
    exact = scene.render("depth-complexity", samples=256, backend="cpu")
    wedges = scene.render("wedges-blend", backend="cpu")
    c = pb.compare(wedges, exact)
    assert c["pixels"] == 64 * 48 and c["penumbra_pixels"] > 0
    assert 0 < c["mae"] < 0.05 and c["max"] <= 1
    same = pb.compare(exact, exact)
    assert same["mae"] == 0 and same["equal"] == 1
    with pytest.raises(ValueError):
        pb.compare(exact, exact[:, :10])
