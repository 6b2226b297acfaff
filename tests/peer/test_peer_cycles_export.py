#!/usr/bin/env python3
"""scripts/peer-cycles without Blender: the generated Blender script of the Cornell box holds
the expected objects, materials, camera and Cycles settings; unsupported scenes are refused;
a missing blender is reported with the way to install it. Run by ctest (peer_cycles_export)."""

import ast
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOL = os.path.join(ROOT, "scripts", "peer-cycles")


def run(*args, env=None):
    return subprocess.run([sys.executable, TOOL, *args], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, env=env)


def export(scene, *extra):
    """(script text, embedded plan) of `scene`."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "scene.py")
        p = run("export", scene, "-o", out, "--image", "/tmp/x.exr", *extra)
        if p.returncode != 0:
            raise AssertionError(f"export failed: {p.stderr}")
        with open(out, encoding="utf-8") as f:
            text = f.read()
    tree = ast.parse(text)  # the script must at least be valid Python
    for node in tree.body:
        if isinstance(node, ast.Assign) and node.targets[0].id == "PLAN_JSON":
            return text, json.loads(ast.literal_eval(node.value))
    raise AssertionError("no PLAN_JSON in the generated script")


def apply(m, p):
    return [sum(m[r][c] * p[c] for c in range(3)) + m[r][3] for r in range(3)]


def tri_normal(pos, t):
    a, b, c = (pos[i] for i in t)
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


class CornellBox(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.text, cls.plan = export(os.path.join(ROOT, "scenes", "cornell-box.json"),
                                    "--width", "96", "--height", "80", "--spp", "32",
                                    "--max-depth", "7", "--threads", "3", "--seed", "5")

    def test_objects_and_materials(self):
        names = sorted(o["name"] for o in self.plan["objects"])
        self.assertEqual(names, sorted(["Floor", "Ceiling", "BackWall", "RightWall", "LeftWall",
                                        "ShortBox", "TallBox", "Light",
                                        "Light (back cover)"]))
        by_name = {o["name"]: o for o in self.plan["objects"]}
        self.assertEqual(len(self.plan["meshes"][by_name["TallBox"]["mesh"]]["triangles"]), 12)
        left = self.plan["materials"][by_name["LeftWall"]["material"]]
        self.assertEqual(left, {"type": "diffuse", "color": [0.63, 0.065, 0.05],
                                "name": "LeftWall"})
        light = self.plan["materials"][by_name["Light"]["material"]]
        self.assertEqual(light["emission"], [17, 12, 4])
        self.assertFalse(light["two_sided"])
        self.assertEqual(self.plan["lights"], [])
        self.assertEqual(self.plan["world"], [0, 0, 0])

    def test_light_faces_down(self):
        # rayproc emits from the front of the quad only: its winding must survive the export.
        light = next(o for o in self.plan["objects"] if o["name"] == "Light")
        mesh = self.plan["meshes"][light["mesh"]]
        for t in mesh["triangles"]:
            n = tri_normal(mesh["positions"], t)
            self.assertLess(n[1], 0)
            self.assertAlmostEqual(n[0], 0)
            self.assertAlmostEqual(n[2], 0)

    def test_light_back_cover(self):
        # Cycles emits from both sides: a black cover a hair above the downward-facing light
        # absorbs what its back would emit.
        by_name = {o["name"]: o for o in self.plan["objects"]}
        cover = by_name["Light (back cover)"]
        self.assertEqual(self.plan["materials"][cover["material"]]["color"], [0, 0, 0])
        self.assertNotIn("emission", self.plan["materials"][cover["material"]])
        light = self.plan["meshes"][by_name["Light"]["mesh"]]["positions"]
        for p, q in zip(light, self.plan["meshes"][cover["mesh"]]["positions"]):
            self.assertAlmostEqual(q[0], p[0])
            self.assertAlmostEqual(q[2], p[2])
            self.assertGreater(q[1] - p[1], 0)
            self.assertLess(q[1] - p[1], 1e-3)
        # Closed emitters (the glowing sphere of materials.json) need no cover: tested there.

    def test_camera(self):
        cam = self.plan["camera"]
        self.assertEqual(cam["fov_y"], 19.5)
        m = cam["matrix"]
        self.assertEqual(apply(m, [0, 0, 0]), [0, 1, 6.8])
        # Blender cameras look down their -z: towards look_at [0, 1, 0].
        forward = [-m[r][2] for r in range(3)]
        for a, b in zip(forward, [0, 0, -1]):
            self.assertAlmostEqual(a, b)
        self.assertAlmostEqual(m[1][1], 1.0)  # up stays +y

    def test_render_settings(self):
        self.assertEqual(self.plan["render"], {"width": 96, "height": 80, "spp": 32,
                                               "max_depth": 7, "seed": 5, "threads": 3})
        for line in ["SPOT_COSINE_FIX = True", 'c.device = "CPU"', "c.use_adaptive_sampling = False",
                     "c.use_denoising = False", 'c.pixel_filter_type = "BOX"',
                     "c.filter_width = 1.0", 'c.max_bounces = R["max_depth"]',
                     "c.sample_clamp_indirect = 0.0", "c.blur_glossy = 0.0",
                     'rs.image_settings.file_format = "OPEN_EXR"',
                     'rs.image_settings.color_depth = "32"',
                     'scene.view_settings.view_transform = "Standard"']:
            self.assertIn(line, self.text)


class OtherScenes(unittest.TestCase):
    def test_materials_scene(self):
        _, plan = export(os.path.join(ROOT, "scenes", "materials.json"))
        types = sorted(l["type"] for l in plan["lights"])
        self.assertEqual(types, ["point", "spot", "sun"])
        spot = next(l for l in plan["lights"] if l["type"] == "spot")
        # Blender lights shine down their -z: the spot's -z column is its direction.
        d = [-spot["matrix"][r][2] for r in range(3)]
        n = math.sqrt(0.55 ** 2 + 0.6 ** 2 + 0.55 ** 2)
        for a, b in zip(d, [0.55 / n, -0.6 / n, -0.55 / n]):
            self.assertAlmostEqual(a, b)
        self.assertEqual(apply(spot["matrix"], [0, 0, 0]), [-4, 5, 4])
        self.assertEqual(plan["world"], [0.08, 0.1, 0.14])
        kinds = {m["type"] for m in plan["materials"].values()}
        self.assertEqual(kinds, {"diffuse", "mirror", "dielectric", "glossy"})
        torus = next(o for o in plan["objects"] if o["name"] == "torus")
        self.assertEqual(len(plan["meshes"][torus["mesh"]]["triangles"]), 2 * 288)
        # Five spheres share one unit sphere mesh, placed by their matrices.
        spheres = [o for o in plan["objects"] if o["mesh"] == "__uv_sphere"]
        self.assertEqual(len(spheres), 6)
        self.assertFalse(any(o["name"].endswith("(back cover)") and "sphere" in o["name"]
                             for o in plan["objects"]))
        self.assertIn("area light (back cover)", [o["name"] for o in plan["objects"]])
        self.assertNotIn("disk (back cover)", [o["name"] for o in plan["objects"]])
        glow = next(o for o in spheres if o["name"] == "glowing sphere")
        self.assertEqual([round(x, 6) for x in apply(glow["matrix"], [0, 1, 0])], [0.8, 0.4, 1.6])

    def test_instances_and_rotation_order(self):
        scene = {
            "materials": {"w": {"type": "diffuse"}},
            "prototypes": {"p": {"transform": {"translate": [0, 0, 1]}, "children": [
                {"type": "quad", "material": "w",
                 "corners": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]}]}},
            "nodes": [{"type": "instance", "prototype": "p", "transform": {
                "translate": [10, 0, 0],
                "rotate": [{"angle": 90, "axis": [0, 0, 1]}, {"angle": 90, "axis": [1, 0, 0]}]}},
                {"type": "instance", "prototype": "p"}]}
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            json.dump(scene, f)
        try:
            _, plan = export(f.name)
        finally:
            os.unlink(f.name)
        a, b = plan["objects"]
        self.assertEqual(a["mesh"], b["mesh"])  # instances share the mesh
        # The first rotation acts first: x -> y (about z), then y -> z (about x); the
        # prototype's own translate (0, 0, 1) comes before both.
        got = apply(a["matrix"], [1, 0, 0])
        want = [10, -1, 1]  # (1,0,1) -> z-rot -> (0,1,1) -> x-rot -> (0,-1,1) -> +10 x
        for g, w in zip(got, want):
            self.assertAlmostEqual(g, w, places=6)

    def test_refusals(self):
        p = run("export", os.path.join(ROOT, "scenes", "million.json"), "-o", os.devnull)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("does not support procedural grids", p.stderr)
        scene = {"camera": {"aperture": 0.1},
                 "nodes": [{"type": "sphere", "emission": [1, 1, 1], "radius": 1}]}
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            json.dump(scene, f)
        try:
            p = run("export", f.name, "-o", os.devnull)
        finally:
            os.unlink(f.name)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("only pinhole cameras", p.stderr)

    def test_missing_blender_says_how_to_install(self):
        env = dict(os.environ, PATH=os.path.join(ROOT, "no-such-dir"))
        env.pop("BLENDER", None)
        with tempfile.TemporaryDirectory() as tmp:
            p = run("render", os.path.join(ROOT, "scenes", "cornell-box.json"),
                    "-o", os.path.join(tmp, "x.exr"), env=env)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("apt-get install --no-install-recommends blender", p.stderr)


class TimeToTarget(unittest.TestCase):
    def test_interpolates_log_log(self):
        sys.dont_write_bytecode = True
        sys.path.insert(0, os.path.join(ROOT, "scripts"))
        from peer_cycles import runner
        # relMSE halves when the time doubles: 0.01 lies at sqrt(2) * 2 between (2, 0.02)
        # and (4, 0.005).
        pts = [(1.0, 0.04), (2.0, 0.02), (4.0, 0.005)]
        self.assertAlmostEqual(runner.time_at(pts, 0.01), 2.0 * math.sqrt(2.0))
        self.assertEqual(runner.time_at(pts, 0.05), 1.0)
        self.assertIsNone(runner.time_at(pts, 0.001))


if __name__ == "__main__":
    unittest.main()
