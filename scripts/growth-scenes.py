#!/usr/bin/env python3
"""Writes the scenes that measure how a technique's cost grows with the triangles and with the
light's size: the layout of the scale scene (fixtures/scale/scale.toml: same camera, light,
ground and six mesh placements) with its meshes coarsened or refined, and under smaller and
larger lights.

  tris-10k.toml, tris-50k.toml   each mesh simplified by vertex clustering on a uniform grid:
                                 vertices of a cell merged at their mean, collapsed triangles and
                                 exact duplicates (same three vertices, either orientation)
                                 dropped; the cell size of each mesh found by bisection so that
                                 it keeps its share of the total (the scale scene's proportions)
  tris-200k.toml                 the scale scene's meshes as they are (209,388 triangles)
  tris-1m.toml                   every triangle split into four at its edge midpoints (shared
                                 midpoints, so a watertight mesh stays watertight): 837,546
  light-0.25x.toml, light-1x.toml, light-4x.toml
                                 the 200k scene under lights of sides 1.25, 5 (the scale scene's)
                                 and 20: same centre, normal and tangent
  light-low.toml                 the 200k scene under a light of the scale scene's area, 10 x 2.5,
                                 low beside the group (its centre 2.5 above the ground, aimed 12
                                 degrees down), whose plane crosses the ground: long shadows, and
                                 receivers reaching beyond the view and behind the light
  wide-ground.toml               the 200k scene on a ground 20 times as wide, 400 x 400 (a
                                 user's ground often reaches far beyond the view)
  lights-3.toml                  the 200k scene under three lights (`[[light]]`): the scale
                                 scene's, a 2 x 3 fill light beside the group and a 3 x 1 rim
                                 light behind it, each rendered alone into its channel

The ground quad stays two triangles. The meshes the scenes name are written next to them
(originals copied byte for byte). Prints the triangles of each scene (the faces of its OBJ files,
a mesh counted once per placement) and, for each light, whether its plane cuts any mesh.

Usage: python3 scripts/growth-scenes.py OUT_DIR
"""
import math
import os
import shutil
import struct
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MESHES = os.path.join(ROOT, "fixtures", "meshes")

HEADER = """\
# {what}
# Layout of the scale scene (fixtures/scale/scale.toml): six public meshes close together on a
# ground, the camera, light and placements unchanged. Written by scripts/growth-scenes.py.
# Meshes from the public collection common-3d-test-models by Alec Jacobson
# (github.com/alecjacobson/common-3d-test-models, data/): nefertiti.obj (Berlin Egyptian
# Museum, via Thingiverse 3974391), beetle-alt.obj (Ivan Sutherland, 1972), cheburashka.obj
# (Ilya Baran), spot.obj (Keenan Crane, CC0), fandisk.obj (Hugues Hoppe).
"""

CAMERA = """\
[camera]
eye = [1.0, 4.6, 6.2]
target = [-0.2, 0.8, -0.4]
up = [0.0, 1.0, 0.0]
fov_y_deg = 45.0
width = 320
height = 240
"""

LIGHT_CENTER = (-1.5, 6.5, 2.5)
LIGHT_NORMAL = (0.20733584922834458, -0.8984553466561598, -0.3870269185595765)
LIGHT_TANGENT = (-0.6832113873158513, 0.1501690414500469, -0.7146128037139579)
LIGHT_SIDE = 5.0

# light-low.toml's light: (centre, normal, tangent along its long side, size).
LOW_LIGHT = ((-7.0, 2.5, 3.0), (0.8740445360226472, -0.21226795874835716, -0.4370222680113236),
             (0.447213595499958, 0.0, 0.894427190999916), (10.0, 2.5))

# lights-3.toml's lights: (name, centre, normal, tangent, size).
THREE_LIGHTS = [
    ("key", LIGHT_CENTER, LIGHT_NORMAL, LIGHT_TANGENT, (LIGHT_SIDE, LIGHT_SIDE)),
    ("fill", (4.0, 5.0, 1.0), (-0.6, -0.8, 0.0), (0.0, 0.0, 1.0), (2.0, 3.0)),
    ("rim", (0.0, 4.0, -6.0), (0.0, -0.5547001962252291, 0.8320502943378437), (1.0, 0.0, 0.0),
     (3.0, 1.0)),
]

# (obj, scale, rotate_axis_angle or None, translate): the scale scene's [[mesh]] entries after
# the ground, in its order.
PLACEMENTS = [
    ("nefertiti", 0.006, (1.0, 0.0, 0.0, -90.0), (0.0, 1.504, -0.5)),
    ("beetle-alt", 2.2, (0.0, 1.0, 0.0, 30.0), (-2.0, 0.392, 0.6)),
    ("beetle-alt", 2.2, (0.0, 1.0, 0.0, -70.0), (1.9, 0.392, -0.9)),
    ("cheburashka", 1.6, None, (-1.0, -0.106, 1.4)),
    ("spot", 1.0, (0.0, 1.0, 0.0, -30.0), (1.2, 0.757, 1.6)),
    ("fandisk", 0.5, (1.0, 0.0, 0.0, 90.0), (-3.6, 0.02, -9.8)),
]
GROUND = 2  # quad.obj at scale 20: two triangles


def f32(x):
    """x rounded to the nearest 32-bit float, as the scene loader reads it (with -0 as 0)."""
    return struct.unpack("f", struct.pack("f", x))[0] + 0.0


def read_obj(name):
    """The mesh of fixtures/meshes/NAME.obj: welded positions (bit-identical f32 positions are one
    vertex, as the loader welds them) and triangles (polygons fanned) as index triples."""
    index_of = {}
    positions = []
    file_to_welded = []
    triangles = []
    with open(os.path.join(MESHES, name + ".obj")) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                p = tuple(f32(float(c)) for c in parts[1:4])
                if p not in index_of:
                    index_of[p] = len(positions)
                    positions.append(p)
                file_to_welded.append(index_of[p])
            elif parts[0] == "f":
                n = len(file_to_welded)
                idx = []
                for token in parts[1:]:
                    i = int(token.split("/")[0])
                    idx.append(file_to_welded[i - 1 if i > 0 else n + i])
                for k in range(1, len(idx) - 1):
                    triangles.append((idx[0], idx[k], idx[k + 1]))
    return positions, triangles


def cluster(positions, triangles, cell):
    """Vertex clustering on a grid of side `cell` anchored at the mesh's lowest corner: the cell
    of each vertex, the triangles over cells with collapsed ones and duplicates dropped."""
    lo = [min(p[k] for p in positions) for k in range(3)]
    keys = {}
    cell_of = []
    for x, y, z in positions:
        key = (math.floor((x - lo[0]) / cell), math.floor((y - lo[1]) / cell),
               math.floor((z - lo[2]) / cell))
        cell_of.append(keys.setdefault(key, len(keys)))
    seen = set()
    out = []
    for a, b, c in triangles:
        a, b, c = cell_of[a], cell_of[b], cell_of[c]
        if a == b or b == c or a == c:
            continue
        s = tuple(sorted((a, b, c)))
        if s in seen:
            continue
        seen.add(s)
        out.append((a, b, c))
    return cell_of, len(keys), out


def simplify(positions, triangles, target):
    """The clustering whose triangle count is nearest `target`: bisection on the cell size, in
    log scale between a thousandth and the whole of the bounding box's diagonal."""
    diag = math.dist([min(p[k] for p in positions) for k in range(3)],
                     [max(p[k] for p in positions) for k in range(3)])
    lo, hi = math.log(diag * 1e-3), math.log(diag)
    best = None
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        cell_of, cells, tris = cluster(positions, triangles, math.exp(mid))
        if best is None or abs(len(tris) - target) < abs(len(best[2]) - target):
            best = (cell_of, cells, tris, math.exp(mid))
        if len(tris) == target or abs(len(tris) - target) <= 0.002 * target:
            break
        if len(tris) > target:
            lo = mid
        else:
            hi = mid
    cell_of, cells, tris, cell = best
    sums = [[0.0, 0.0, 0.0, 0] for _ in range(cells)]
    for p, c in zip(positions, cell_of):
        s = sums[c]
        s[0] += p[0]
        s[1] += p[1]
        s[2] += p[2]
        s[3] += 1
    means = [(s[0] / s[3], s[1] / s[3], s[2] / s[3]) for s in sums]
    return compact(means, tris), cell


def compact(positions, triangles):
    """Drops the vertices no triangle uses and renumbers the others."""
    new = {}
    kept = []
    out = []
    for t in triangles:
        r = []
        for i in t:
            if i not in new:
                new[i] = len(kept)
                kept.append(positions[i])
            r.append(new[i])
        out.append(tuple(r))
    return kept, out


def subdivide(positions, triangles):
    """Each triangle split into four at its edge midpoints, one midpoint per edge, orientation
    kept: (a, b, c) -> (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)."""
    positions = list(positions)
    mid = {}

    def m(i, j):
        key = (i, j) if i < j else (j, i)
        if key not in mid:
            p, q = positions[i], positions[j]
            mid[key] = len(positions)
            positions.append(tuple(0.5 * (p[k] + q[k]) for k in range(3)))
        return mid[key]

    out = []
    for a, b, c in triangles:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return positions, out


def zero_area(positions, triangles):
    """Triangles the loader would drop: zero cross product of their edges after f32 rounding."""
    n = 0
    for a, b, c in triangles:
        p, q, r = ([f32(x) for x in positions[i]] for i in (a, b, c))
        u = [q[k] - p[k] for k in range(3)]
        v = [r[k] - p[k] for k in range(3)]
        if (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0]) == (0.0, 0.0, 0.0):
            n += 1
    return n


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def write_obj(path, comment, positions, triangles):
    lines = ["# " + comment + "\n"]
    lines += ["v %.9g %.9g %.9g\n" % p for p in positions]
    lines += ["f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in triangles]
    write_atomic(path, "".join(lines))


def fmt(v):
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def scene_text(what, mesh_file, side, light=None, ground=20.0, lights=None):
    """The scene under the scale scene's light with sides `side`, or under `light` (centre,
    normal, tangent, size), or under the named `lights` (name, centre, normal, tangent, size),
    on the unit quad scaled by `ground`."""
    centre, normal, tangent, size = light or (LIGHT_CENTER, LIGHT_NORMAL, LIGHT_TANGENT,
                                              (side, side))
    text = HEADER.format(what=what) + "\n" + CAMERA + "\n"
    if lights is None:
        text += ("[light]\ncenter = %s\nnormal = %s\ntangent = %s\nsize = [%r, %r]\n"
                 % (fmt(centre), fmt(normal), fmt(tangent), size[0], size[1]))
    for k, (name, centre, normal, tangent, size) in enumerate(lights or []):
        text += ("%s[[light]]\nname = \"%s\"\ncenter = %s\nnormal = %s\ntangent = %s\n"
                 "size = [%r, %r]\n" % ("\n" if k else "", name, fmt(centre), fmt(normal),
                                        fmt(tangent), size[0], size[1]))
    text += '\n[[mesh]]\nobj = "quad.obj"\nscale = %r\ntranslate = [0.0, 0.0, 0.0]\n' % ground
    for name, scale, rot, tr in PLACEMENTS:
        text += '\n[[mesh]]\nobj = "%s"\nscale = %r\n' % (mesh_file[name], scale)
        if rot is not None:
            text += "rotate_axis_angle = %s\n" % fmt(rot)
        text += "translate = %s\n" % fmt(tr)
    return text


def rotate(axis, deg, p):
    """Rodrigues' rotation of p about the unit `axis` by `deg` degrees."""
    n = math.sqrt(sum(a * a for a in axis))
    k = [a / n for a in axis]
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    kxp = (k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0])
    kdp = sum(k[i] * p[i] for i in range(3))
    return tuple(p[i] * c + kxp[i] * s + k[i] * kdp * (1 - c) for i in range(3))


def placed_extent(positions, scale, rot, tr):
    """(least distance in front of the light's plane, highest y) of the placed mesh."""
    least, top = math.inf, -math.inf
    for p in positions:
        w = tuple(scale * x for x in p)
        if rot is not None:
            w = rotate(rot[:3], rot[3], w)
        w = tuple(w[i] + tr[i] for i in range(3))
        least = min(least, sum((w[i] - LIGHT_CENTER[i]) * LIGHT_NORMAL[i] for i in range(3)))
        top = max(top, w[1])
    return least, top


def main(out):
    os.makedirs(out, exist_ok=True)
    shutil.copyfile(os.path.join(MESHES, "quad.obj"), os.path.join(out, "quad.obj"))
    names = list(dict.fromkeys(p[0] for p in PLACEMENTS))
    uses = {n: sum(1 for p in PLACEMENTS if p[0] == n) for n in names}
    meshes = {n: read_obj(n) for n in names}
    original = GROUND + sum(uses[n] * len(meshes[n][1]) for n in names)

    def report(scene, counts, notes):
        total = GROUND + sum(uses[n] * counts[n] for n in names)
        print("%-17s %9s triangles  (%s)" % (scene, format(total, ","), notes))

    # The originals, byte for byte: tris-200k and the three lights.
    for n in names:
        shutil.copyfile(os.path.join(MESHES, n + ".obj"), os.path.join(out, n + ".obj"))
    same = {n: n + ".obj" for n in names}

    for label, target in (("10k", 10_000), ("50k", 50_000)):
        share = (target - GROUND) / (original - GROUND)
        files, counts, notes = {}, {}, []
        for n in names:
            pos, tris = meshes[n]
            (p, t), cell = simplify(pos, tris, round(share * len(tris)))
            files[n] = "%s-%s.obj" % (n, label)
            counts[n] = len(t)
            degenerate = zero_area(p, t)
            write_obj(os.path.join(out, files[n]),
                      "%s.obj simplified by vertex clustering, cell %.6g: %d triangles"
                      % (n, cell, len(t)), p, t)
            notes.append("%s %s%s" % (n, format(len(t), ","),
                                      ", %d of zero area" % degenerate if degenerate else ""))
        total = GROUND + sum(uses[n] * counts[n] for n in names)
        write_atomic(os.path.join(out, "tris-%s.toml" % label), scene_text(
            "Growth with triangles: the scale scene simplified to %s triangles by vertex "
            "clustering." % format(total, ","), files, LIGHT_SIDE))
        report("tris-%s.toml" % label, counts, "; ".join(notes))

    write_atomic(os.path.join(out, "tris-200k.toml"), scene_text(
        "Growth with triangles: the scale scene as it is, %s triangles." % format(original, ","),
        same, LIGHT_SIDE))
    report("tris-200k.toml", {n: len(meshes[n][1]) for n in names}, "the originals")

    files, counts = {}, {}
    for n in names:
        p, t = subdivide(*meshes[n])
        files[n] = n + "-x4.obj"
        counts[n] = len(t)
        write_obj(os.path.join(out, files[n]),
                  "%s.obj, every triangle split into four at its edge midpoints: %d triangles"
                  % (n, len(t)), p, t)
    total = GROUND + sum(uses[n] * counts[n] for n in names)
    write_atomic(os.path.join(out, "tris-1m.toml"), scene_text(
        "Growth with triangles: the scale scene with every mesh triangle split into four at its "
        "edge midpoints, %s triangles." % format(total, ","), files, LIGHT_SIDE))
    report("tris-1m.toml", counts, "each mesh split once; the ground kept")

    for label, factor in (("0.25x", 0.25), ("1x", 1.0), ("4x", 4.0)):
        write_atomic(os.path.join(out, "light-%s.toml" % label), scene_text(
            "Growth with the light: the scale scene (%s triangles) under a light of side %g, "
            "%g times the scale scene's." % (format(original, ","), factor * LIGHT_SIDE, factor),
            same, factor * LIGHT_SIDE))
        report("light-%s.toml" % label, {n: len(meshes[n][1]) for n in names},
               "light %g x %g" % (factor * LIGHT_SIDE, factor * LIGHT_SIDE))

    write_atomic(os.path.join(out, "light-low.toml"), scene_text(
        "Growth with the light: the scale scene (%s triangles) under a light of its area, 10 x "
        "2.5, low beside the group; its plane crosses the ground." % format(original, ","),
        same, None, LOW_LIGHT))
    report("light-low.toml", {n: len(meshes[n][1]) for n in names}, "light 10 x 2.5, low")
    write_atomic(os.path.join(out, "wide-ground.toml"), scene_text(
        "The scale scene (%s triangles) on a ground 20 times as wide, 400 x 400."
        % format(original, ","), same, LIGHT_SIDE, ground=400.0))
    report("wide-ground.toml", {n: len(meshes[n][1]) for n in names}, "ground 400 x 400")
    write_atomic(os.path.join(out, "lights-3.toml"), scene_text(
        "The scale scene (%s triangles) under three lights: its own, a 2 x 3 fill light beside "
        "the group and a 3 x 1 rim light behind it." % format(original, ","), same, LIGHT_SIDE,
        lights=THREE_LIGHTS))
    report("lights-3.toml", {n: len(meshes[n][1]) for n in names}, "three lights")

    # The light's plane against the meshes (the same plane for every scene but light-low, whose
    # plane crosses the ground, as printed last): the format allows a
    # mesh through it, but then only its part in front can cast a shadow.
    print("\nLight plane (centre %s, normal %s): least distance of each placed mesh in front of it"
          % (fmt(LIGHT_CENTER), fmt(LIGHT_NORMAL)))
    tops = []
    for name, scale, rot, tr in PLACEMENTS:
        least, top = placed_extent(meshes[name][0], scale, rot, tr)
        tops.append(top)
        print("  %-12s %+.3f%s  (top at y = %.3f)"
              % (name, least, "" if least > 0 else "  CUT BY THE PLANE", top))
    ground = min(sum((c[i] - LIGHT_CENTER[i]) * LIGHT_NORMAL[i] for i in range(3))
                 for c in ((-10, 0, -10), (-10, 0, 10), (10, 0, -10), (10, 0, 10)))
    print("  %-12s %+.3f%s" % ("ground", ground, "" if ground > 0 else "  CUT BY THE PLANE"))
    b = (LIGHT_NORMAL[1] * LIGHT_TANGENT[2] - LIGHT_NORMAL[2] * LIGHT_TANGENT[1],
         LIGHT_NORMAL[2] * LIGHT_TANGENT[0] - LIGHT_NORMAL[0] * LIGHT_TANGENT[2],
         LIGHT_NORMAL[0] * LIGHT_TANGENT[1] - LIGHT_NORMAL[1] * LIGHT_TANGENT[0])
    for factor in (0.25, 1.0, 4.0):
        half = 0.5 * factor * LIGHT_SIDE
        low = LIGHT_CENTER[1] - half * (abs(LIGHT_TANGENT[1]) + abs(b[1]))
        print("  light side %-5g lowest corner at y = %.3f (highest mesh top %.3f)"
              % (factor * LIGHT_SIDE, low, max(tops)))
    centre, normal = LOW_LIGHT[0], LOW_LIGHT[1]
    behind = [c for c in ((-10, 0, -10), (-10, 0, 10), (10, 0, -10), (10, 0, 10))
              if sum((c[i] - centre[i]) * normal[i] for i in range(3)) < 0]
    print("light-low's plane: %d of the ground's 4 corners behind it" % len(behind))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
