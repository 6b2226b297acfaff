"""Turns an export plan (scene_reader.read_scene) into a self-contained Blender Python script.

The script is the builder below with the plan embedded as JSON: it empties Blender's scene,
builds meshes, materials, lights, world and camera, sets Cycles up to match rayproc's path mode
(see docs/peer-cycles.md for the mapping and its approximations), renders one frame to a
linear float EXR and prints one line `PEER_CYCLES_TIMES {json}` with its own timings.
"""

import json

BUILDER = r'''
import json, math, sys, time
import bpy

PLAN = json.loads(PLAN_JSON)
OUTPUT = OUTPUT_PATH
SPOT_COSINE_FIX = True
t_start = time.perf_counter()

# An empty file: no default cube, lamp, camera or grey world.
bpy.ops.wm.read_homefile(use_empty=True)
scene = bpy.context.scene


def matrix(rows):
    from mathutils import Matrix
    return Matrix([list(r) for r in rows])


def norm_color(c):
    """Blender colours stay in [0, 1] for lights; the scale goes into the strength."""
    m = max(c)
    return ([x / m for x in c], m) if m > 0 else ([0.0, 0.0, 0.0], 0.0)


# --- meshes: one datablock per rayproc mesh, shared by every object placing it ---------------
meshes = {}
for key, m in PLAN["meshes"].items():
    me = bpy.data.meshes.new(key)
    me.from_pydata(m["positions"], [], m["triangles"])
    me.materials.append(None)  # one slot; each object fills it (link = OBJECT)
    me.update()
    if m["corner_normals"] is not None or m["vertex_normals"] is not None:
        # Shading normals: smooth faces with custom split normals.
        for p in me.polygons:
            p.use_smooth = True
        me.use_auto_smooth = True
        if m["corner_normals"] is not None:
            me.normals_split_custom_set(m["corner_normals"])
        else:
            me.normals_split_custom_set_from_vertices(m["vertex_normals"])
    meshes[key] = me


# --- materials ---------------------------------------------------------------------------------
def bsdf_node(nt, m):
    t = m["type"]
    if t == "diffuse":
        n = nt.nodes.new("ShaderNodeBsdfDiffuse")
        n.inputs["Color"].default_value = (*m["color"], 1.0)
        n.inputs["Roughness"].default_value = 0.0  # Lambert
        return n.outputs["BSDF"]
    if t == "mirror":
        n = nt.nodes.new("ShaderNodeBsdfGlossy")
        n.distribution = "SHARP"
        n.inputs["Color"].default_value = (*m["color"], 1.0)
        return n.outputs["BSDF"]
    if t == "dielectric":
        n = nt.nodes.new("ShaderNodeBsdfGlass")
        n.distribution = "SHARP"
        n.inputs["Color"].default_value = (*m["color"], 1.0)
        n.inputs["IOR"].default_value = m["ior"]
        return n.outputs["BSDF"]
    if t == "glossy":
        # A GGX metal with F0 = colour (rayproc: Schlick Fresnel with F0 = colour, GGX,
        # alpha = roughness^2; Cycles' Principled squares its roughness the same way).
        n = nt.nodes.new("ShaderNodeBsdfPrincipled")
        n.distribution = "GGX"
        n.inputs["Base Color"].default_value = (*m["color"], 1.0)
        n.inputs["Metallic"].default_value = 1.0
        n.inputs["Roughness"].default_value = m["roughness"]
        n.inputs["Specular"].default_value = 0.5
        n.inputs["Sheen"].default_value = 0.0
        n.inputs["Clearcoat"].default_value = 0.0
        return n.outputs["BSDF"]
    raise ValueError(t)


materials = {}
for key, m in PLAN["materials"].items():
    mat = bpy.data.materials.new(key)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    shader = bsdf_node(nt, m)
    if "emission" in m:
        color, strength = norm_color(m["emission"])
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = (*color, 1.0)
        em.inputs["Strength"].default_value = strength
        # Cycles emits from both sides; one-sided open emitters get a black back cover
        # (scene_reader.Reader.back_cover).
        both = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(shader, both.inputs[0])
        nt.links.new(em.outputs["Emission"], both.inputs[1])
        shader = both.outputs["Shader"]
    nt.links.new(shader, out.inputs["Surface"])
    materials[key] = mat


# --- objects -------------------------------------------------------------------------------------
for o in PLAN["objects"]:
    ob = bpy.data.objects.new(o["name"], meshes[o["mesh"]])
    ob.matrix_world = matrix(o["matrix"])
    # The material is linked to the object, so objects sharing a mesh may differ in it.
    ob.material_slots[0].link = "OBJECT"
    ob.material_slots[0].material = materials[o["material"]]
    scene.collection.objects.link(ob)


# --- lights --------------------------------------------------------------------------------------
for l in PLAN["lights"]:
    t = l["type"]
    if t in ("point", "spot"):
        li = bpy.data.lights.new(l["name"], type="POINT" if t == "point" else "SPOT")
        color, inten = norm_color(l["intensity"])
        li.color = color
        li.energy = 4.0 * math.pi * inten  # Cycles' power P in W: intensity I = P / (4 pi)
        li.shadow_soft_size = 0.0           # a true point
        if t == "spot":
            outer = math.radians(l["cone_angle"] + l["falloff_angle"])
            cos_outer, cos_cone = math.cos(outer), math.cos(math.radians(l["cone_angle"]))
            li.spot_size = 2.0 * outer
            # Cycles smooth-steps over [cos_outer, cos_outer + (1 - cos_outer) * blend].
            li.spot_blend = (cos_cone - cos_outer) / (1.0 - cos_outer)
            if SPOT_COSINE_FIX:
                # Cycles 3.4 also weights a spot by the cosine to its axis; divide it out.
                # The light-space direction of the emitted ray is the Normal texture coordinate.
                li.use_nodes = True
                nt = li.node_tree
                em = nt.nodes["Emission"]
                tc = nt.nodes.new("ShaderNodeTexCoord")
                xyz = nt.nodes.new("ShaderNodeSeparateXYZ")
                nt.links.new(tc.outputs["Normal"], xyz.inputs[0])
                ab = nt.nodes.new("ShaderNodeMath")
                ab.operation = "ABSOLUTE"
                nt.links.new(xyz.outputs["Z"], ab.inputs[0])
                mx = nt.nodes.new("ShaderNodeMath")
                mx.operation = "MAXIMUM"
                mx.inputs[1].default_value = 1e-4
                nt.links.new(ab.outputs["Value"], mx.inputs[0])
                inv = nt.nodes.new("ShaderNodeMath")
                inv.operation = "DIVIDE"
                inv.inputs[0].default_value = 1.0
                nt.links.new(mx.outputs["Value"], inv.inputs[1])
                nt.links.new(inv.outputs["Value"], em.inputs["Strength"])
        ob = bpy.data.objects.new(l["name"], li)
        ob.matrix_world = matrix(l["matrix"]) if t == "spot" else matrix(
            [[1, 0, 0, l["position"][0]], [0, 1, 0, l["position"][1]],
             [0, 0, 1, l["position"][2]], [0, 0, 0, 1]])
    elif t == "sun":
        li = bpy.data.lights.new(l["name"], type="SUN")
        color, e = norm_color(l["irradiance"])
        li.color = color
        li.energy = e   # Cycles' sun strength is irradiance in W/m^2
        li.angle = 0.0  # a true directional light
        ob = bpy.data.objects.new(l["name"], li)
        ob.matrix_world = matrix(l["matrix"])
    else:
        raise ValueError(t)
    li.cycles.cast_shadow = True
    if hasattr(li.cycles, "max_bounces"):
        li.cycles.max_bounces = 1024
    scene.collection.objects.link(ob)


# --- world: rayproc's uniform environment, or black ------------------------------------------
world = bpy.data.worlds.new("world")
world.use_nodes = True
bg = world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (*PLAN["world"], 1.0)
bg.inputs["Strength"].default_value = 1.0
scene.world = world


# --- camera: same eye, axes and vertical field of view ------------------------------------------
cam = bpy.data.cameras.new("camera")
cam.sensor_fit = "VERTICAL"
cam.angle_y = math.radians(PLAN["camera"]["fov_y"])
cam.clip_start = 1e-5
cam.clip_end = 1e8
cam.dof.use_dof = False
cam_ob = bpy.data.objects.new("camera", cam)
cam_ob.matrix_world = matrix(PLAN["camera"]["matrix"])
scene.collection.objects.link(cam_ob)
scene.camera = cam_ob


# --- Cycles settings: rayproc path mode's estimator, as far as Cycles has switches -------------
R = PLAN["render"]
rs = scene.render
rs.engine = "CYCLES"
rs.resolution_x, rs.resolution_y, rs.resolution_percentage = R["width"], R["height"], 100
rs.pixel_aspect_x = rs.pixel_aspect_y = 1.0
rs.threads_mode = "FIXED"
rs.threads = R["threads"]
rs.use_compositing = False
rs.use_sequencer = False
rs.dither_intensity = 0.0
rs.film_transparent = False
rs.image_settings.file_format = "OPEN_EXR"
rs.image_settings.color_depth = "32"
rs.image_settings.exr_codec = "ZIP"
rs.image_settings.color_mode = "RGB"
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0

c = scene.cycles
c.device = "CPU"
c.samples = R["spp"]
c.use_adaptive_sampling = False
c.use_denoising = False
c.seed = R["seed"]
c.use_animated_seed = False
c.max_bounces = R["max_depth"]
c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = R["max_depth"]
c.transparent_max_bounces = R["max_depth"]
c.volume_bounces = 0
c.min_light_bounces = 0
c.min_transparent_bounces = 0
c.sample_clamp_direct = 0.0
c.sample_clamp_indirect = 0.0
c.blur_glossy = 0.0              # "filter glossy" off
c.caustics_reflective = True
c.caustics_refractive = True
c.light_sampling_threshold = 0.0  # every light sample is traced
c.pixel_filter_type = "BOX"       # rayproc: one uniform sample inside the pixel = box, width 1
c.filter_width = 1.0
c.direct_light_sampling_type = "MULTIPLE_IMPORTANCE_SAMPLING"  # NEE + BSDF, MIS (as rayproc)
if hasattr(c, "use_guiding"):     # Blender >= 3.4: path guiding would change the estimator
    c.use_guiding = False
if hasattr(c, "use_light_tree"):  # Blender >= 3.5 only
    c.use_light_tree = False
scene.frame_set(1)
rs.filepath = OUTPUT

t_built = time.perf_counter()
bpy.ops.render.render(write_still=True)
t_done = time.perf_counter()
print("PEER_CYCLES_TIMES " + json.dumps({
    "build_seconds": t_built - t_start,
    "render_call_seconds": t_done - t_built,
    "blender": ".".join(map(str, bpy.app.version)),
}), flush=True)
'''


def blender_script(plan, output_path):
    """The Blender script for `plan`, writing its image to `output_path`."""
    text = json.dumps(plan, separators=(",", ":"))
    return ("# Generated by scripts/peer-cycles from " + plan["scene"] + "\n"
            "# Run: blender -b --factory-startup --python THIS_FILE\n"
            "PLAN_JSON = " + repr(text) + "\n"
            "OUTPUT_PATH = " + repr(output_path) + "\n" + BUILDER)
