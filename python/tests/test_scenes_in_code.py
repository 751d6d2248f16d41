"""Scenes built in Python: from numpy arrays (any dtype, any strides), trimesh meshes, lights
given by vectors or by angles, meshes with transforms."""

import numpy as np
import pytest
import trimesh

import penumbra as pb

QUAD_V = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], dtype=float)
QUAD_F = np.array([[0, 2, 1], [0, 3, 2]])


def ground():
    return pb.Mesh(QUAD_V * 6, QUAD_F, name="ground")


def camera():
    return pb.Camera(eye=(0, 4, 6), target=(0, 0, 0), up=(0, 1, 0), fov_y_deg=45, width=64, height=48)


def lamp(name=None):
    return pb.RectLight(center=(0, 5, 0), normal=(0, -1, 0), tangent=(1, 0, 0), size=(2, 1), name=name)


def ball():
    return trimesh.creation.icosphere(subdivisions=2, radius=0.6).apply_translation([0, 1, 0])


def test_a_scene_from_arrays_renders_a_shadow():
    scene = pb.Scene(camera(), lamp(), [ground(), pb.Mesh.from_trimesh(ball())])
    v = scene.render("depth-complexity", samples=64, backend="cpu")
    assert v.shape == (48, 64) and v.dtype == np.float32
    assert v.min() == 0 and v[0, 0] == 1
    assert ((v > 0) & (v < 1)).sum() > 20


def test_arrays_of_any_dtype_and_strides_give_the_same_mesh():
    tm = ball()
    want = pb.Scene(camera(), lamp(), [ground(), pb.Mesh(tm.vertices, tm.faces)]).render("hard", backend="cpu")
    v32 = np.asarray(tm.vertices, dtype=np.float32).astype(np.float64)  # what float32 keeps
    wide = np.zeros((len(tm.vertices), 6))
    wide[:, ::2] = tm.vertices  # every other column: a non-contiguous view
    for vertices, faces in [
        (wide[:, ::2], tm.faces.astype(np.uint32)),
        (tm.vertices.tolist(), tm.faces.tolist()),
        (np.asfortranarray(tm.vertices), np.asfortranarray(tm.faces.astype(np.int32))),
    ]:
        got = pb.Scene(camera(), lamp(), [ground(), pb.Mesh(vertices, faces)]).render("hard", backend="cpu")
        assert np.array_equal(got, want)
    assert pb.Mesh(v32, tm.faces).triangle_count == len(tm.faces)
    m = pb.Mesh.from_trimesh(tm, name="ball")
    assert m.name == "ball" and m.vertices.shape == tm.vertices.shape


def test_a_transform_places_a_mesh_as_its_moved_vertices_do():
    tm = ball()
    t = np.eye(4)
    t[:3, 3] = [0.5, 0.2, -0.3]
    moved = tm.copy().apply_transform(t)
    a = pb.Scene(camera(), lamp(), [ground(), (pb.Mesh.from_trimesh(tm), t)]).render("hard", backend="cpu")
    b = pb.Scene(camera(), lamp(), [ground(), pb.Mesh.from_trimesh(moved)]).render("hard", backend="cpu")
    assert (a != b).mean() < 0.01


def test_lights_by_angles_and_targets_are_the_lights_of_their_vectors():
    sun = pb.DistantLight.sun(azimuth_deg=135, elevation_deg=30, angular_size_deg=0.53)
    d = np.array(sun.direction)
    az, el = np.radians(135), np.radians(30)
    assert np.allclose(d, [np.cos(el) * np.sin(az), np.sin(el), -np.cos(el) * np.cos(az)])
    up = np.array([0.0, 1.0, 0.0]) - d * d[1]
    explicit = pb.DistantLight(direction=d, tangent=up / np.linalg.norm(up), angular_size=(0.53, 0.53))
    a = pb.Scene(camera(), sun, [ground(), pb.Mesh.from_trimesh(ball())]).render("hard", backend="cpu")
    b = pb.Scene(camera(), explicit, [ground(), pb.Mesh.from_trimesh(ball())]).render("hard", backend="cpu")
    assert np.array_equal(a, b) and a.min() == 0
    aimed = pb.RectLight.aimed(center=(0, 5, 0), target=(0, 0, 0), size=(2, 2))
    assert np.allclose(aimed.normal, (0, -1, 0))


def test_several_lights_render_to_a_dict_in_their_order():
    sun = pb.DistantLight.sun(135, 30, name="sun")
    scene = pb.Scene(camera(), [lamp("lamp"), sun], [ground(), pb.Mesh.from_trimesh(ball())])
    v = scene.render("hard", backend="cpu")
    assert list(v) == ["lamp", "sun"]
    unnamed = pb.Scene(camera(), [lamp(), pb.DistantLight.sun(135, 30)], [ground()])
    assert unnamed.light_names == ["light0", "light1"]


@pytest.mark.parametrize(
    "make, words",
    [
        (lambda: pb.RectLight((0, 5, 0), (0, 0, 0), (1, 0, 0), (1, 1)), "normal"),
        (lambda: pb.RectLight((0, 5, 0), (0, -1, 0), (1, 0, 0), (-1, 1)), "size"),
        (lambda: pb.DistantLight.sun(135, 95), "elevation"),
        (lambda: pb.Camera(eye=(0, 0, 0), target=(0, 0, 0)), "target"),
        (lambda: pb.Camera(eye=(0, 1, 0), target=(0, 0, 0), width=0), "image size 0x240"),
        (lambda: pb.Mesh(QUAD_V, [[0, 1, 9]]), "9"),
        (lambda: pb.Mesh(QUAD_V, [[0, 1, -1]]), "-1"),
        (lambda: pb.Mesh(QUAD_V[:, :2], QUAD_F), "(n, 3)"),
        (lambda: pb.Mesh(QUAD_V, QUAD_F.astype(float)), "integers"),
        (lambda: pb.Mesh([[0, 0, np.nan], [1, 0, 0], [0, 0, 1]], [[0, 1, 2]]), "finite"),
        (lambda: pb.Scene(camera(), [], [ground()]), "light"),
        (lambda: pb.Scene(camera(), [lamp("a"), lamp("A")], [ground()]), "case"),
        (lambda: pb.Scene(camera(), lamp(), [(ground(), np.eye(3))]), "4 x 4"),
        (lambda: pb.Scene(camera(), "lamp", [ground()]), "RectLight"),
    ],
)
def test_bad_values_raise_value_error_naming_the_field(make, words):
    with pytest.raises(ValueError) as e:
        make()
    assert words in str(e.value)
