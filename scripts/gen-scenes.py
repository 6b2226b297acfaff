#!/usr/bin/env python3
"""Writes the generated scene files that are committed to the repository.

    scenes/instances.json    hierarchy stress: prototype "field" places "row" 50 times, each
                             row places "tree" 50 times (2,500 trees, plus rocks), with
                             rotations and non-uniform scales at both levels
    scenes/meshes/torus.obj  a low-poly torus with normals and uvs, written as quads, for
                             scenes/materials.json
    scenes/caustic-pool.json a small square light above a slab of water with a wavy top over
                             a white floor: a caustic (light -> refraction -> diffuse) test
    scenes/meshes/wavy-water.obj  that slab: a smooth-shaded wavy height field, closed
    scenes/caustic-box.json  a pool: a box whose floor and lower walls lie under an open wavy
                             water surface, lit from above by a small light and seen through
                             the water (the floor is inside the medium: L S D paths end there)
    scenes/meshes/wavy-surface.obj  that surface: the same waves, one open height field

The output is deterministic (fixed random seed), so re-running the script reproduces the
committed files exactly. Usage: scripts/gen-scenes.py [--out-dir scenes]
"""

import argparse
import json
import math
import pathlib
import random

ROW_LENGTH = 50   # trees per row
ROW_COUNT = 50    # rows per field
SPACING = 2.0     # metres between trees and between rows


def r4(x):
    """Rounds to 4 decimals so that the JSON stays small and diffs stay readable."""
    v = round(x, 4)
    return 0.0 if v == 0 else v


def cone_mesh(segments, radius, y0, y1):
    """A closed cone: apex at (0, y1, 0), base circle of `radius` at height y0."""
    positions = [[0.0, y1, 0.0], [0.0, y0, 0.0]]  # apex, base centre
    for i in range(segments):
        a = 2 * math.pi * i / segments
        positions.append([r4(radius * math.cos(a)), y0, r4(-radius * math.sin(a))])
    indices = []
    for i in range(segments):
        a, b = 2 + i, 2 + (i + 1) % segments
        indices.append([0, a, b])  # side, facing outwards
        indices.append([1, b, a])  # base, facing down
    return {"positions": positions, "indices": indices}


def box_mesh(hx, y0, y1, hz):
    """An axis-aligned box [-hx, hx] x [y0, y1] x [-hz, hz], outward-facing triangles."""
    p = [[x, y, z] for y in (y0, y1) for z in (-hz, hz) for x in (-hx, hx)]
    # Corner index = 4*top + 2*front + right.
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    indices = []
    for a, b, c, d in quads:
        indices += [[a, b, c], [a, c, d]]
    return {"positions": p, "indices": indices}


def instance(prototype, translate, yaw, scale):
    return {
        "type": "instance",
        "prototype": prototype,
        "transform": {
            "translate": [r4(t) for t in translate],
            "rotate": {"angle": r4(yaw), "axis": [0, 1, 0]},
            "scale": [r4(s) for s in scale],
        },
    }


def instances_scene(rng):
    tree = {
        "children": [
            dict({"type": "mesh", "name": "trunk", "material": "bark"},
                 **box_mesh(0.08, 0.0, 0.7, 0.08)),
            dict({"type": "mesh", "name": "crown", "material": "leaves"},
                 **cone_mesh(7, 0.55, 0.5, 2.0)),
        ]
    }
    rock = {
        "children": [
            {"type": "sphere", "material": "stone", "center": [0, 0, 0], "radius": 0.3,
             "transform": {"scale": [1.0, 0.5, 0.8]}},
        ]
    }
    # A row along x: trees with a random yaw and a slightly stretched or squashed shape.
    row = []
    for i in range(ROW_LENGTH):
        x = (i - (ROW_LENGTH - 1) / 2) * SPACING + rng.uniform(-0.4, 0.4)
        z = rng.uniform(-0.4, 0.4)
        s = rng.uniform(0.7, 1.2)
        row.append(instance("tree", [x, 0, z], rng.uniform(0, 360), [s, s * rng.uniform(0.8, 1.5), s]))
        if i % 5 == 2:
            row.append(instance("rock", [x + 0.9, 0.1, z + 0.7], rng.uniform(0, 360),
                                [rng.uniform(0.6, 1.4)] * 3))
    # A field of rows along z, each turned a little and stretched non-uniformly.
    field = []
    for j in range(ROW_COUNT):
        z = (j - (ROW_COUNT - 1) / 2) * SPACING
        field.append(instance("row", [0, 0, z], rng.uniform(-3, 3),
                              [rng.uniform(0.95, 1.05), rng.uniform(0.8, 1.2), 1.0]))
    return {
        "camera": {"position": [0, 30, 78], "look_at": [0, 0, 5], "up": [0, 1, 0],
                   "fov": 38, "resolution": [960, 540]},
        "materials": {
            "ground": {"type": "diffuse", "color": [0.35, 0.3, 0.22]},
            "bark": {"type": "diffuse", "color": [0.3, 0.18, 0.1]},
            "leaves": {"type": "diffuse", "color": [0.12, 0.4, 0.12]},
            "stone": {"type": "glossy", "color": [0.5, 0.5, 0.52], "roughness": 0.6},
            "gold": {"type": "glossy", "color": [1.0, 0.78, 0.34], "roughness": 0.25},
        },
        "lights": [
            {"type": "directional", "name": "sun", "direction": [-0.4, -1, -0.5],
             "irradiance": [3, 2.8, 2.5]},
            {"type": "environment", "name": "sky", "radiance": [0.25, 0.35, 0.55]},
        ],
        "prototypes": {"tree": tree, "rock": rock, "row": {"children": row},
                       "field": {"children": field}},
        "nodes": [
            {"type": "rectangle", "name": "ground", "material": "ground",
             "center": [0, 0, 0], "size": [140, 140]},
            {"type": "instance", "name": "field", "prototype": "field"},
            {"type": "group", "name": "monument",
             "transform": {"translate": [0, 0, 58]},
             "children": [
                 {"type": "sphere", "material": "gold", "center": [0, 2, 0], "radius": 2},
                 {"type": "instance", "prototype": "tree",
                  "transform": {"translate": [4, 0, 0], "scale": 2.5}},
             ]},
        ],
    }


def dump_compact(obj, indent=0):
    """JSON with one node, material or light per line: readable, and far smaller than
    json.dumps(indent=2). Containers that fit in 100 columns also stay on one line."""
    flat = json.dumps(obj, separators=(", ", ": "))
    if not isinstance(obj, (dict, list)) or len(flat) + 2 * indent <= 100 or \
            (isinstance(obj, dict) and "type" in obj and "children" not in obj):
        return flat
    pad = "  " * (indent + 1)
    if isinstance(obj, list):
        items = [pad + dump_compact(e, indent + 1) for e in obj]
        return "[\n" + ",\n".join(items) + "\n" + "  " * indent + "]"
    items = [f"{pad}{json.dumps(k)}: {dump_compact(v, indent + 1)}" for k, v in obj.items()]
    return "{\n" + ",\n".join(items) + "\n" + "  " * indent + "}"


WAVES = [(0.022, 9.0, 4.1, 0.0), (0.016, -5.3, 10.2, 1.0), (0.010, 13.7, 11.3, 2.0)]


def wave_height(x, z):
    """Height of the water's top above its mean level, and the two slopes."""
    h = dx = dz = 0.0
    for amp, kx, kz, phase in WAVES:
        arg = kx * x + kz * z + phase
        h += amp * math.sin(arg)
        dx += amp * kx * math.cos(arg)
        dz += amp * kz * math.cos(arg)
    return h, dx, dz


def wave_grid(coords, level):
    """The wavy surface's grid over coords x coords at height level + waves: its "v" lines and
    its "vn" lines (the waves' analytic normals), row by row."""
    positions, normals = [], []
    for z in coords:
        for x in coords:
            h, dx, dz = wave_height(x, z)
            positions.append(f"v {x:.5f} {level + h:.5f} {z:.5f}")
            ln = math.sqrt(dx * dx + 1 + dz * dz)
            normals.append(f"vn {-dx / ln:.5f} {1 / ln:.5f} {-dz / ln:.5f}")
    return positions, normals


def wavy_water_obj(half=1.0, bottom=0.9, level=1.0, n=64):
    """A closed slab over [-half, half]^2: a flat bottom at y = bottom, a wavy top around
    y = level with analytic vertex normals (smooth refraction, hence sharp caustics), and
    four flat sides whose top edges follow the waves."""
    lines = ["# Wavy water slab written by scripts/gen-scenes.py",
             f"# [-{half}, {half}]^2, bottom y = {bottom}, top y = {level} + waves, "
             f"{n} x {n} top quads", "o water"]
    coords = [-half + 2 * half * i / n for i in range(n + 1)]
    # Top grid: positions 1 .. (n+1)^2 with their normals; then the bottom grid.
    positions, normals = wave_grid(coords, level)
    lines += positions
    for z in coords:
        for x in coords:
            lines.append(f"v {x:.5f} {bottom:.5f} {z:.5f}")
    lines += normals
    flat = {"down": (0, -1, 0), "-x": (-1, 0, 0), "+x": (1, 0, 0), "-z": (0, 0, -1),
            "+z": (0, 0, 1)}
    first_flat = (n + 1) ** 2 + 1
    for i, v in enumerate(flat.values()):
        lines.append(f"vn {v[0]} {v[1]} {v[2]}")
    normal = {k: first_flat + i for i, k in enumerate(flat)}

    def top(i, j):  # column i (x), row j (z), 1-based
        return j * (n + 1) + i + 1

    def bot(i, j):
        return (n + 1) ** 2 + top(i, j)

    for j in range(n):  # top faces wind counter-clockwise seen from above (+y)
        for i in range(n):
            a, b, c, d = top(i, j), top(i, j + 1), top(i + 1, j + 1), top(i + 1, j)
            lines.append(f"f {a}//{a} {b}//{b} {c}//{c} {d}//{d}")
    nd = normal["down"]
    for j in range(n):
        for i in range(n):
            a, b, c, d = bot(i, j), bot(i + 1, j), bot(i + 1, j + 1), bot(i, j + 1)
            lines.append(f"f {a}//{nd} {b}//{nd} {c}//{nd} {d}//{nd}")
    for k in range(n):  # sides, outward
        for side, (t0, t1) in {"-z": ((k, 0), (k + 1, 0)), "+z": ((k + 1, n), (k, n)),
                               "-x": ((0, k + 1), (0, k)), "+x": ((n, k), (n, k + 1))}.items():
            a, b = top(*t0), top(*t1)
            c, d = bot(*t1), bot(*t0)
            m = normal[side]
            lines.append(f"f {a}//{m} {d}//{m} {c}//{m} {b}//{m}")
    return "\n".join(lines) + "\n"


def caustic_pool_scene():
    return {
        "camera": {"position": [0, 3.0, 2.6], "look_at": [0, 0.3, 0], "up": [0, 1, 0],
                   "fov": 42, "resolution": [256, 256]},
        "materials": {
            "floor": {"type": "diffuse", "color": [0.8, 0.8, 0.8]},
            "water": {"type": "dielectric", "ior": 1.33, "color": [1, 1, 1]},
            "lamp": {"type": "diffuse", "color": [0, 0, 0]},
        },
        "nodes": [
            {"type": "quad", "name": "floor", "material": "floor",
             "corners": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]},
            {"type": "obj", "name": "water", "file": "meshes/wavy-water.obj",
             "material": "water"},
            {"type": "quad", "name": "lamp", "material": "lamp", "emission": [30, 30, 30],
             "corners": [[-0.2, 2.6, -0.2], [0.2, 2.6, -0.2], [0.2, 2.6, 0.2],
                         [-0.2, 2.6, 0.2]]},
        ],
    }


def wavy_surface_obj(half=1.0, level=0.8, n=64):
    """An open wavy height field over [-half, half]^2 around y = level, normals up (its
    front side, the outside of the water, is the air above)."""
    lines = ["# Open wavy water surface written by scripts/gen-scenes.py",
             f"# [-{half}, {half}]^2, y = {level} + waves, {n} x {n} quads", "o surface"]
    coords = [-half + 2 * half * i / n for i in range(n + 1)]
    positions, normals = wave_grid(coords, level)
    lines += positions + normals
    for j in range(n):  # counter-clockwise seen from above (+y)
        for i in range(n):
            a = j * (n + 1) + i + 1
            b, c, d = a + n + 1, a + n + 2, a + 1
            lines.append(f"f {a}//{a} {b}//{b} {c}//{c} {d}//{d}")
    return "\n".join(lines) + "\n"


def caustic_box_scene():
    # Walls face inwards; the water fills the box's lower part, its surface meeting the walls.
    h = 1.3
    return {
        "camera": {"position": [0, 2.3, 1.25], "look_at": [0, 0.15, -0.35], "up": [0, 1, 0],
                   "fov": 58, "resolution": [256, 256]},
        "materials": {
            "floor": {"type": "diffuse", "color": [0.8, 0.8, 0.8]},
            "wall": {"type": "diffuse", "color": [0.75, 0.6, 0.45]},
            "water": {"type": "dielectric", "ior": 1.33, "color": [1, 1, 1]},
            "lamp": {"type": "diffuse", "color": [0, 0, 0]},
        },
        "nodes": [
            {"type": "quad", "name": "floor", "material": "floor",
             "corners": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]},
            {"type": "quad", "name": "back", "material": "wall",
             "corners": [[-1, 0, -1], [1, 0, -1], [1, h, -1], [-1, h, -1]]},
            {"type": "quad", "name": "left", "material": "wall",
             "corners": [[-1, 0, -1], [-1, h, -1], [-1, h, 1], [-1, 0, 1]]},
            {"type": "quad", "name": "right", "material": "wall",
             "corners": [[1, 0, -1], [1, 0, 1], [1, h, 1], [1, h, -1]]},
            {"type": "quad", "name": "front", "material": "wall",
             "corners": [[-1, 0, 1], [-1, h, 1], [1, h, 1], [1, 0, 1]]},
            {"type": "obj", "name": "water", "file": "meshes/wavy-surface.obj",
             "material": "water"},
            {"type": "quad", "name": "lamp", "material": "lamp", "emission": [30, 30, 30],
             "corners": [[-0.2, 2.4, -0.2], [0.2, 2.4, -0.2], [0.2, 2.4, 0.2],
                         [-0.2, 2.4, 0.2]]},
        ],
    }


def torus_obj(major=0.5, minor=0.2, nu=24, nv=12):
    """A torus around the y axis as quads, with per-vertex normals and seam-split uvs."""
    lines = ["# Low-poly torus written by scripts/gen-scenes.py",
             f"# major radius {major}, minor radius {minor}, {nu} x {nv} quads", "o torus"]
    for i in range(nu):
        u = 2 * math.pi * i / nu
        for j in range(nv):
            v = 2 * math.pi * j / nv
            x = (major + minor * math.cos(v)) * math.cos(u)
            z = -(major + minor * math.cos(v)) * math.sin(u)
            y = minor * math.sin(v)
            lines.append(f"v {x:.5f} {y:.5f} {z:.5f}")
    for i in range(nu):
        u = 2 * math.pi * i / nu
        for j in range(nv):
            v = 2 * math.pi * j / nv
            lines.append(f"vn {math.cos(v) * math.cos(u):.5f} {math.sin(v):.5f} "
                         f"{-math.cos(v) * math.sin(u):.5f}")
    for i in range(nu + 1):
        for j in range(nv + 1):
            lines.append(f"vt {i / nu:.5f} {j / nv:.5f}")

    def p(i, j):  # 1-based position / normal index
        return (i % nu) * nv + (j % nv) + 1

    def t(i, j):  # 1-based uv index; the seam gets its own uvs
        return i * (nv + 1) + j + 1

    for i in range(nu):
        for j in range(nv):
            corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]  # outward-facing
            lines.append("f " + " ".join(f"{p(a, b)}/{t(a, b)}/{p(a, b)}" for a, b in corners))
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out-dir", default=str(pathlib.Path(__file__).resolve().parent.parent / "scenes"))
    args = parser.parse_args()
    out = pathlib.Path(args.out_dir)
    (out / "meshes").mkdir(parents=True, exist_ok=True)
    (out / "instances.json").write_text(dump_compact(instances_scene(random.Random(1))) + "\n")
    (out / "meshes" / "torus.obj").write_text(torus_obj())
    (out / "caustic-pool.json").write_text(dump_compact(caustic_pool_scene()) + "\n")
    (out / "meshes" / "wavy-water.obj").write_text(wavy_water_obj())
    (out / "caustic-box.json").write_text(dump_compact(caustic_box_scene()) + "\n")
    (out / "meshes" / "wavy-surface.obj").write_text(wavy_surface_obj())
    for name in ("instances.json", "meshes/torus.obj", "caustic-pool.json", "meshes/wavy-water.obj",
                 "caustic-box.json", "meshes/wavy-surface.obj"):
        print(f"wrote {out / name} ({(out / name).stat().st_size} bytes)")


if __name__ == "__main__":
    main()
