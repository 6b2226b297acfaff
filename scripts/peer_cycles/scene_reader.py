"""Reads a rayproc JSON scene (docs/scene-format.md) into a flat export plan.

The plan holds only world-space data Blender needs: shared meshes, objects (mesh + material +
4x4 matrix), materials (with the emission folded in), lights, camera and render settings.
rayproc's loader is the authority on what a valid scene is; this reader checks only what it
needs and refuses, with a clear message, every feature Cycles cannot be given faithfully.
"""

import json
import math
import os


class UnsupportedScene(Exception):
    """The scene uses something the Cycles export cannot map (or is malformed)."""


# --- small linear algebra on 4x4 row-major matrices (lists of lists) ---------------------------

def identity():
    return [[1.0 if r == c else 0.0 for c in range(4)] for r in range(4)]


def matmul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def translate(t):
    m = identity()
    for r in range(3):
        m[r][3] = float(t[r])
    return m


def scale(s):
    m = identity()
    for r in range(3):
        m[r][r] = float(s[r])
    return m


def rotate(degrees, axis):
    """Rodrigues' rotation, right-handed, as rayproc's Affine::rotate."""
    x, y, z = normalize(axis)
    th = math.radians(degrees)
    c, s, t = math.cos(th), math.sin(th), 1.0 - math.cos(th)
    m = identity()
    m[0][:3] = [t * x * x + c, t * x * y - s * z, t * x * z + s * y]
    m[1][:3] = [t * x * y + s * z, t * y * y + c, t * y * z - s * x]
    m[2][:3] = [t * x * z - s * y, t * y * z + s * x, t * z * z + c]
    return m


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def mul(a, s):
    return [a[i] * s for i in range(3)]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def normalize(v):
    n = math.sqrt(dot(v, v))
    if n == 0:
        raise UnsupportedScene("zero-length direction")
    return [c / n for c in v]


def look_at(eye, target, up):
    """Camera-to-world, camera looking down -z with +y up (rayproc's Affine::lookAt, and
    Blender's camera convention)."""
    w = normalize(sub(eye, target))
    u = normalize(cross(up, w))
    v = cross(w, u)
    m = identity()
    for r in range(3):
        m[r][0], m[r][1], m[r][2], m[r][3] = u[r], v[r], w[r], float(eye[r])
    return m


def frame_from_minus_z(direction, position=(0.0, 0.0, 0.0)):
    """A rotation (plus translation) whose local -z is `direction` (Blender lights shine
    down their -z)."""
    d = normalize(direction)
    helper = [0.0, 1.0, 0.0] if abs(d[1]) < 0.9 else [1.0, 0.0, 0.0]
    return look_at(list(position), add(list(position), d), helper)


# --- the scene file ----------------------------------------------------------------------------

def parse_transform(t, where):
    if isinstance(t, list):
        if len(t) not in (12, 16):
            raise UnsupportedScene(f"{where}: a matrix transform has 12 or 16 numbers")
        m = identity()
        for r in range(3):
            m[r] = [float(x) for x in t[4 * r:4 * r + 4]]
        return m
    if not isinstance(t, dict):
        raise UnsupportedScene(f"{where}: a transform is an array or an object")
    tr, ro, sc = identity(), identity(), identity()
    if "translate" in t:
        tr = translate(t["translate"])
    if "rotate" in t:
        rots = t["rotate"] if isinstance(t["rotate"], list) else [t["rotate"]]
        for r in rots:  # in the order written: the first rotation stands rightmost
            ro = matmul(rotate(r["angle"], r["axis"]), ro)
    if "scale" in t:
        s = t["scale"]
        sc = scale([s, s, s] if isinstance(s, (int, float)) else s)
    return matmul(tr, matmul(ro, sc))


def read_obj(path):
    """Positions, triangles and (only if every corner has one) per-corner normals of an OBJ;
    n-gons are fanned from their first corner, negative indices are relative."""
    if not os.path.isfile(path):
        raise UnsupportedScene(f"OBJ file not found: {path}")
    vs, vns, tris, corner_normals, all_normals = [], [], [], [], True
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vs.append([float(x) for x in parts[1:4]])
            elif parts[0] == "vn":
                vns.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                corners = []
                for c in parts[1:]:
                    fields = c.split("/")
                    vi = int(fields[0])
                    vi = vi - 1 if vi > 0 else len(vs) + vi
                    ni = None
                    if len(fields) >= 3 and fields[2]:
                        ni = int(fields[2])
                        ni = ni - 1 if ni > 0 else len(vns) + ni
                    corners.append((vi, ni))
                for k in range(1, len(corners) - 1):
                    tri = (corners[0], corners[k], corners[k + 1])
                    tris.append([c[0] for c in tri])
                    if any(c[1] is None for c in tri):
                        all_normals = False
                    else:
                        corner_normals.extend(vns[c[1]] for c in tri)
    if not tris:
        raise UnsupportedScene(f"OBJ file has no faces: {path}")
    return vs, tris, (corner_normals if all_normals else None)


def uv_sphere(segments=128, rings=64):
    """A unit UV sphere; its vertex normals are the exact sphere normals."""
    pos = [[0.0, 1.0, 0.0]]
    for r in range(1, rings):
        th = math.pi * r / rings
        for s in range(segments):
            ph = 2.0 * math.pi * s / segments
            pos.append([round(math.sin(th) * math.cos(ph), 7), round(math.cos(th), 7),
                        round(-math.sin(th) * math.sin(ph), 7)])
    pos.append([0.0, -1.0, 0.0])
    bottom = len(pos) - 1

    def ring(r, s):
        return 1 + (r - 1) * segments + (s % segments)

    tris = []
    for s in range(segments):
        tris.append([0, ring(1, s), ring(1, s + 1)])
        for r in range(1, rings - 1):
            a, b, c, d = ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)
            tris.append([a, b, c])
            tris.append([a, c, d])
        tris.append([ring(rings - 1, s), bottom, ring(rings - 1, s + 1)])
    return pos, tris, None, [list(p) for p in pos]


def disk_fan(radius, center, normal, segments=256):
    n = normalize(normal)
    helper = [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0]
    t = normalize(cross(helper, n))
    b = cross(n, t)
    pos = [list(map(float, center))]
    for s in range(segments):
        a = 2.0 * math.pi * s / segments
        pos.append(add(center, add(mul(t, radius * math.cos(a)), mul(b, radius * math.sin(a)))))
    # (t, b, n) is right-handed, so counter-clockwise in (t, b) faces along n.
    tris = [[0, 1 + s, 1 + (s + 1) % segments] for s in range(segments)]
    return pos, tris


def rectangle_corners(node):
    c = node.get("center", [0, 0, 0])
    w, h = node["size"]
    n = normalize(node.get("normal", [0, 1, 0]))
    up = node.get("up")
    if up is None:
        up = [0, 0, -1] if abs(n[1]) > 0.999 else [0, 1, 0]
    v = normalize(sub(up, mul(n, dot(up, n))))  # the height direction, in the plane
    u = cross(v, n)                                # the width: cross(up, normal)
    hu, hv = mul(u, 0.5 * w), mul(v, 0.5 * h)
    # u x v = n, so this order faces along n.
    return [sub(sub(c, hu), hv), sub(add(c, hu), hv), add(add(c, hu), hv), add(sub(c, hu), hv)]


def is_closed(tris):
    """Every edge shared by exactly two triangles (a watertight mesh)."""
    edges = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            e = (min(a, b), max(a, b))
            edges[e] = edges.get(e, 0) + 1
    return all(c == 2 for c in edges.values())


SHAPES = {"mesh", "obj", "quad", "rectangle", "sphere", "disk"}
REFUSED_SHAPES = {"grid": "procedural grids (export the grid as an OBJ mesh instead)"}


class Reader:
    def __init__(self, path):
        self.path = path
        self.folder = os.path.dirname(os.path.abspath(path))
        try:
            with open(path, encoding="utf-8") as f:
                self.doc = json.load(f)
        except json.JSONDecodeError as e:
            raise UnsupportedScene(f"{path}: not valid JSON: {e}")
        self.meshes = {}          # mesh key -> mesh data
        self.objects = []
        self.used_materials = {}  # plan material key -> material data
        self.obj_cache = {}

    def material_key(self, node, where):
        emission = node.get("emission", [0, 0, 0])
        emits = max(emission) > 0
        name = node.get("material")
        if name is None:
            if not emits:
                raise UnsupportedScene(f"{where}: a shape needs a material unless it emits")
            name = "__emitter_black"
            base = {"type": "diffuse", "color": [0, 0, 0]}
        else:
            mats = self.doc.get("materials", {})
            if name not in mats:
                raise UnsupportedScene(f"{where}: unknown material {name!r}")
            base = dict(mats[name])
        if not emits:
            key = name
        else:
            two = bool(node.get("two_sided", False))
            key = f"{name}+emit({','.join(f'{e:g}' for e in emission)}){'2s' if two else ''}"
        if key not in self.used_materials:
            m = material_plan(base, f"/materials/{name}")
            m["name"] = name
            if emits:
                m["emission"] = [float(e) for e in emission]
                m["two_sided"] = bool(node.get("two_sided", False))
            self.used_materials[key] = m
        return key

    def add_mesh(self, key, positions, tris, corner_normals=None, vertex_normals=None):
        """Shading normals come per face corner (OBJ) or per vertex (meshes, spheres)."""
        if key not in self.meshes:
            self.meshes[key] = {"positions": positions, "triangles": tris,
                                "corner_normals": corner_normals,
                                "vertex_normals": vertex_normals}
        return key

    def shape(self, node, matrix, where, proto):
        kind = node["type"]
        name = node.get("name", kind)
        # Meshes of a prototype are shared by all its instances; keyed by the node itself.
        key = f"{kind}:{where}" if proto is None else f"{kind}:{proto}:{where}"
        m = matrix
        if kind == "mesh":
            idx = node["indices"]
            if idx and not isinstance(idx[0], list):
                if len(idx) % 3:
                    raise UnsupportedScene(f"{where}/indices: not a multiple of 3")
                idx = [idx[i:i + 3] for i in range(0, len(idx), 3)]
            normals = node.get("normals")
            vertex = [normalize(n) for n in normals] if normals else None
            self.add_mesh(key, [list(map(float, p)) for p in node["positions"]], idx, None, vertex)
        elif kind == "obj":
            path = node["file"]
            path = path if os.path.isabs(path) else os.path.join(self.folder, path)
            key = "obj:" + os.path.normpath(path)  # nodes naming one file share one mesh
            if key not in self.meshes:
                self.add_mesh(key, *read_obj(path))
        elif kind in ("quad", "rectangle"):
            corners = node["corners"] if kind == "quad" else rectangle_corners(node)
            self.add_mesh(key, [list(map(float, c)) for c in corners], [[0, 1, 2], [0, 2, 3]])
        elif kind == "sphere":
            key = "__uv_sphere"
            if key not in self.meshes:
                self.add_mesh(key, *uv_sphere())
            c, r = node.get("center", [0, 0, 0]), float(node["radius"])
            m = matmul(matrix, matmul(translate(c), scale([r, r, r])))
        elif kind == "disk":
            self.add_mesh(key, *disk_fan(float(node["radius"]), node.get("center", [0, 0, 0]),
                                         node.get("normal", [0, 1, 0])))
        material = self.material_key(node, where)
        self.objects.append({"name": name, "mesh": key, "material": material, "matrix": m})
        if "emission" in self.used_materials[material] and not node.get("two_sided", False):
            self.back_cover(name, key, m)

    def back_cover(self, name, key, matrix):
        """rayproc's emitters emit from their front only. Cycles' mesh emission is two-sided,
        and a strength driven by the Backfacing output is not honoured when Cycles samples the
        light (measured: docs/peer-cycles.md). So an open emitter gets a black, non-emitting
        copy of itself a hair behind its back: what the back would emit is absorbed there, and
        nothing else can reach the back. Closed emitters (spheres) need none: their back faces
        only their inside."""
        mesh = self.meshes[key]
        if key == "__uv_sphere" or is_closed(mesh["triangles"]):
            return
        cover = key + "#back"
        if cover not in self.meshes:
            pos, tris = mesh["positions"], mesh["triangles"]
            normals = [[0.0, 0.0, 0.0] for _ in pos]
            for t in tris:  # area-weighted vertex normals of the front side
                n = cross(sub(pos[t[1]], pos[t[0]]), sub(pos[t[2]], pos[t[0]]))
                for i in t:
                    normals[i] = add(normals[i], n)
            lo = [min(p[k] for p in pos) for k in range(3)]
            hi = [max(p[k] for p in pos) for k in range(3)]
            eps = 1e-4 * max(1e-3, math.sqrt(dot(sub(hi, lo), sub(hi, lo))))
            moved = [sub(p, mul(normalize(n), eps)) if dot(n, n) > 0 else list(p)
                     for p, n in zip(pos, normals)]
            self.add_mesh(cover, moved, tris)
        if "__back_cover" not in self.used_materials:
            self.used_materials["__back_cover"] = {"type": "diffuse", "color": [0, 0, 0],
                                                   "name": "__back_cover"}
        self.objects.append({"name": name + " (back cover)", "mesh": cover,
                             "material": "__back_cover", "matrix": matrix})

    def node(self, node, matrix, where, proto=None, depth=0):
        if depth > 256:
            raise UnsupportedScene(f"{where}: nesting deeper than 256 levels (instance cycle?)")
        if not isinstance(node, dict) or "type" not in node:
            raise UnsupportedScene(f"{where}: a node is an object with a \"type\"")
        if "transform" in node:
            matrix = matmul(matrix, parse_transform(node["transform"], where + "/transform"))
        kind = node["type"]
        if kind == "group":
            for i, child in enumerate(node.get("children", [])):
                self.node(child, matrix, f"{where}/children/{i}", proto, depth + 1)
        elif kind == "instance":
            name = node["prototype"]
            protos = self.doc.get("prototypes", {})
            if name not in protos:
                raise UnsupportedScene(f"{where}/prototype: unknown prototype {name!r}")
            p = protos[name]
            pm = matmul(matrix, parse_transform(p["transform"], f"/prototypes/{name}/transform")) \
                if "transform" in p else matrix
            for i, child in enumerate(p.get("children", [])):
                self.node(child, pm, f"/prototypes/{name}/children/{i}", name, depth + 1)
        elif kind in SHAPES:
            self.shape(node, matrix, where, proto)
        elif kind in REFUSED_SHAPES:
            raise UnsupportedScene(f"{where}: the Cycles export does not support "
                                   f"{REFUSED_SHAPES[kind]}")
        else:
            raise UnsupportedScene(f"{where}: unknown node type {kind!r}")


def material_plan(m, where):
    kind = m.get("type")
    if kind == "diffuse":
        return {"type": "diffuse", "color": m.get("color", [0.5, 0.5, 0.5])}
    if kind == "mirror":
        return {"type": "mirror", "color": m.get("color", [1, 1, 1])}
    if kind == "dielectric":
        return {"type": "dielectric", "color": m.get("color", [1, 1, 1]),
                "ior": float(m.get("ior", 1.5))}
    if kind == "glossy":
        return {"type": "glossy", "color": m.get("color", [1, 1, 1]),
                "roughness": float(m.get("roughness", 0.2))}
    raise UnsupportedScene(f"{where}: unknown material type {kind!r}")


def light_plan(light, where):
    kind = light.get("type")
    name = light.get("name", kind)
    if kind == "point":
        return {"type": "point", "name": name, "position": light["position"],
                "intensity": light["intensity"]}
    if kind == "spot":
        cone = float(light.get("cone_angle", 30))
        falloff = float(light.get("falloff_angle", 5))
        return {"type": "spot", "name": name,
                "matrix": frame_from_minus_z(light["direction"], light["position"]),
                "intensity": light["intensity"], "cone_angle": cone, "falloff_angle": falloff}
    if kind == "directional":
        return {"type": "sun", "name": name, "matrix": frame_from_minus_z(light["direction"]),
                "irradiance": light["irradiance"]}
    if kind == "environment":
        return {"type": "environment", "name": name, "radiance": light["radiance"]}
    raise UnsupportedScene(f"{where}: unknown light type {kind!r}")


def read_scene(path, width=None, height=None, spp=None, max_depth=None, seed=None, threads=None):
    """The export plan of a rayproc JSON scene, with the command line's settings winning over
    the scene's render block (as in `rayproc render`)."""
    if path.endswith(".pbrt"):
        raise UnsupportedScene(f"{path}: pbrt scenes are not supported by the Cycles export; "
                               "use the JSON version of the scene")
    r = Reader(path)
    doc = r.doc
    nodes = doc.get("nodes")
    if not isinstance(nodes, list) or not nodes:
        raise UnsupportedScene(f"{path}: /nodes: required and non-empty")
    for i, n in enumerate(nodes):
        r.node(n, identity(), f"/nodes/{i}")

    cam = doc.get("camera", {})
    if float(cam.get("aperture", 0)) > 0:
        raise UnsupportedScene(f"{path}: /camera/aperture: only pinhole cameras are exported "
                               "(the thin lens is not mapped to Cycles' depth of field)")
    res = cam.get("resolution", [512, 512])
    render = doc.get("render", {})
    lights, world = [], [0.0, 0.0, 0.0]
    for i, l in enumerate(doc.get("lights", [])):
        lp = light_plan(l, f"/lights/{i}")
        if lp["type"] == "environment":
            world = [float(x) for x in lp["radiance"]]
        else:
            lights.append(lp)
    return {
        "scene": os.path.abspath(path),
        "camera": {"matrix": look_at(cam.get("position", [0, 0, 5]), cam.get("look_at", [0, 0, 0]),
                                     cam.get("up", [0, 1, 0])),
                   "fov_y": float(cam.get("fov", 40))},
        "render": {
            "width": int(width or res[0]), "height": int(height or res[1]),
            "spp": int(spp or render.get("spp", 64)),
            # rayproc's path mode defaults to 64 bounces (PathSettings::maxDepth)
            "max_depth": int(max_depth or render.get("max_depth", 64)),
            "seed": int(seed if seed is not None else render.get("seed", 0)),
            "threads": int(threads or os.cpu_count() or 1),
        },
        "meshes": r.meshes,
        "materials": r.used_materials,
        "objects": r.objects,
        "lights": lights,
        "world": world,
    }
