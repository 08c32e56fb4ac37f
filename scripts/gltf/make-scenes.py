"""Build lucent's glTF reference scenes in Blender and export them.

    blender -b --factory-startup --python scripts/gltf/make-scenes.py -- OUTDIR [NAME ...]

For every scene (all of them, or the NAMEs given) this writes, overwriting:

    OUTDIR/NAME.glb       the scene through Blender's bundled glTF exporter
                          (io_scene_gltf2; GLB, cameras and punctual lights)
    OUTDIR/NAME.blend     the same scene for Cycles (textures packed inside)
    OUTDIR/NAME.json      what the other steps need: image size, the world's
                          constant radiance, the env file (or null)
    OUTDIR/NAME.env.exr   a 16x8 linear OpenEXR, every pixel the world colour
                          x strength, for `lucent render NAME.glb --env ...`;
                          only where the world is not black
    OUTDIR/textures/*.png the generated textures (also packed / embedded)

Scenes: mr-grid, textured, transmission, volume, alpha-mask, emissive, lights,
instances, vertex-colors. Each is built from an empty factory scene with bpy
only, so the output depends on nothing but this file and Blender's version
(written for Blender 3.4, Debian's `blender` package; other versions warn).

Choices made so that a glTF renderer and Cycles see the same thing:
  * the world is a constant colour (no HDR image, so no orientation question);
  * point and spot lamps have radius 0 and the sun angle 0 (glTF lights are
    punctual; Blender's defaults are 0.25 m and 0.53 degrees);
  * every Principled BSDF uses single-scattering GGX (glTF's model);
  * textures are generated in numpy and written as 8-bit PNG: base colour
    sRGB (alpha, where used, in its alpha channel), the normal map its own
    Non-Color PNG.
"""

import colorsys
import json
import math
import os
import sys

try:
    import bpy
    import numpy as np
    from mathutils import Vector
except ImportError:
    sys.exit("make-scenes.py runs inside Blender: "
             "blender -b --factory-startup --python scripts/gltf/make-scenes.py -- OUTDIR "
             "(Debian: apt-get install -y blender)")

WIDTH, HEIGHT = 320, 240
ENV_W, ENV_H = 16, 8


# --------------------------------------------------------------------------
# Scene plumbing
# --------------------------------------------------------------------------

def new_scene():
    """An empty factory scene with lucent-comparable render settings."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # No NAME.blend1 backups when a file is overwritten (idempotent reruns).
    bpy.context.preferences.filepaths.save_version = 0
    sc = bpy.context.scene
    sc.render.engine = 'CYCLES'
    sc.render.resolution_x, sc.render.resolution_y = WIDTH, HEIGHT
    sc.render.resolution_percentage = 100
    sc.render.pixel_aspect_x = sc.render.pixel_aspect_y = 1.0
    sc.view_settings.view_transform = 'Standard'
    return sc


def set_world(sc, colour, strength=1.0):
    """A constant-colour world (Background node), radiance = colour x strength."""
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*colour, 1.0)
    bg.inputs["Strength"].default_value = strength
    sc.world = world
    return [c * strength for c in colour]


def look_at(obj, target):
    """Point the object's -Z (cameras and lamps look down -Z) at target, +Y up."""
    direction = Vector(target) - obj.location
    obj.rotation_euler = direction.to_track_quat('-Z', 'Y').to_euler()


def add_camera(sc, location, target, fov_deg=50.0):
    """A perspective camera; fov_deg is the horizontal angle (sensor fit AUTO,
    320x240 is landscape). The exporter turns it into yfov + aspectRatio."""
    cam = bpy.data.cameras.new("Camera")
    cam.lens_unit = 'FOV'
    cam.angle = math.radians(fov_deg)
    cam.clip_start = 0.05
    cam.clip_end = 1000.0
    obj = bpy.data.objects.new("Camera", cam)
    sc.collection.objects.link(obj)
    obj.location = location
    look_at(obj, target)
    sc.camera = obj
    return obj


def add_light(sc, name, kind, location, energy, colour=(1, 1, 1), target=None, **props):
    """A punctual lamp: radius/angle 0 so that it is the same light as glTF's."""
    light = bpy.data.lights.new(name, kind)
    light.energy = energy
    light.color = colour
    if kind == 'SUN':
        light.angle = 0.0
    else:
        light.shadow_soft_size = 0.0
    for key, value in props.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    sc.collection.objects.link(obj)
    obj.location = location
    if target is not None:
        look_at(obj, target)
    return obj


def principled(name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.5, **inputs):
    """A node material with one Principled BSDF (GGX), inputs by socket name.
    IOR 1.5 (Blender's default is 1.45): glTF's default, so the exporter
    writes KHR_materials_ior only where a scene asks for another index."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.distribution = 'GGX'
    bsdf.inputs["IOR"].default_value = 1.5
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    for key, value in inputs.items():
        bsdf.inputs[key].default_value = value
    return mat


def assign(obj, mat):
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    return obj


def active():
    return bpy.context.view_layer.objects.active


def add_plane(size, location=(0, 0, 0), rotation=(0, 0, 0), name="Plane", uv_scale=1.0):
    bpy.ops.mesh.primitive_plane_add(size=size, location=location, rotation=rotation)
    obj = active()
    obj.name = obj.data.name = name
    if uv_scale != 1.0:  # repeat the texture uv_scale times across the plane
        for loop_uv in obj.data.uv_layers.active.data:
            loop_uv.uv = loop_uv.uv * uv_scale
    return obj


def add_sphere(radius, location, name="Sphere", segments=64, rings=32):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=location,
                                         segments=segments, ring_count=rings)
    obj = active()
    obj.name = obj.data.name = name
    bpy.ops.object.shade_smooth()
    return obj


def add_cube(size, location, rotation=(0, 0, 0), name="Cube"):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location, rotation=rotation)
    obj = active()
    obj.name = obj.data.name = name
    return obj


# --------------------------------------------------------------------------
# Generated textures (numpy -> Blender image -> PNG file -> reloaded, packed)
# --------------------------------------------------------------------------

def save_png(outdir, name, rgba, colorspace):
    """Write rgba (H x W x 4 floats in [0, 1], row 0 = bottom = v 0, as Blender
    stores images) to OUTDIR/textures/NAME.png and return the image reloaded
    from that file and packed into the .blend (the exporter embeds it)."""
    h, w, _ = rgba.shape
    texdir = os.path.join(outdir, "textures")
    os.makedirs(texdir, exist_ok=True)
    path = os.path.join(texdir, name + ".png")
    tmp = bpy.data.images.new(name + "-tmp", w, h, alpha=True)
    tmp.pixels.foreach_set(np.ascontiguousarray(rgba, dtype=np.float32).ravel())
    tmp.filepath_raw = path
    tmp.file_format = 'PNG'
    tmp.save()
    bpy.data.images.remove(tmp)
    img = bpy.data.images.load(path)
    img.name = name
    img.colorspace_settings.name = colorspace
    img.pack()
    return img


def checker_gradient(size=128, cells=8):
    """Base colour: a checker of a hue ramp (u: red -> blue, v: dark -> light)
    and light grey. Values are sRGB-encoded (the PNG's meaning)."""
    v, u = np.mgrid[0:size, 0:size] / (size - 1.0)
    ramp = np.stack([0.9 - 0.7 * u, 0.25 + 0.5 * v, 0.1 + 0.8 * u], axis=-1)
    grey = np.full_like(ramp, 0.85)
    iu = (np.arange(size) * cells // size)
    odd = (iu[None, :] + iu[:, None]) % 2 == 1
    rgb = np.where(odd[..., None], grey, ramp)
    return np.concatenate([rgb, np.ones((size, size, 1))], axis=-1)


def checker(size=64, cells=8, a=0.85, b=0.15):
    """A plain two-grey checker (sRGB-encoded values a and b)."""
    iu = (np.arange(size) * cells // size)
    odd = (iu[None, :] + iu[:, None]) % 2 == 1
    rgb = np.where(odd[..., None], b, a) * np.ones((size, size, 3))
    return np.concatenate([rgb, np.ones((size, size, 1))], axis=-1)


def bump_normal_map(size=128, cells=4, height=0.15):
    """Tangent-space normal map (OpenGL convention, as glTF and Blender: +x
    along +u, +y along +v) of smooth round domes, cos^2 profile, `cells` x
    `cells` of them over the texture, heights in UV units."""
    t = (np.arange(size) + 0.5) / size
    v, u = np.meshgrid(t, t, indexing="ij")  # row index = v (bottom row first)
    cu = (u * cells) % 1.0 - 0.5             # position within a cell
    cv = (v * cells) % 1.0 - 0.5
    d = np.hypot(cu, cv)
    radius = 0.4
    inside = d < radius
    # h = height cos^2(pi d / 2R); dh/dd = -height (pi / 2R) sin(pi d / R)
    dh_dd = np.where(inside, -height * (math.pi / (2 * radius)) * np.sin(math.pi * d / radius), 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        dd_du = np.where(d > 0, cu / d, 0.0) * cells  # d(d)/du, per unit of u
        dd_dv = np.where(d > 0, cv / d, 0.0) * cells
    n = np.stack([-dh_dd * dd_du, -dh_dd * dd_dv, np.ones_like(d)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return np.concatenate([n * 0.5 + 0.5, np.ones((size, size, 1))], axis=-1)


def leaf_alpha(size=256):
    """RGBA leaf: a pointed ellipse (two intersecting circles) with a round
    hole, green, alpha exactly 0 or 1 (so MASK and blending agree away from
    the filtered edge). The colour continues under alpha 0 (no dark fringe)."""
    t = (np.arange(size) + 0.5) / size
    y, x = np.meshgrid(t, t, indexing="ij")
    x, y = x - 0.5, y - 0.5
    # vesica: inside both circles of radius r centred at (+-c, 0), pointing along y
    r, c = 0.46, 0.2
    leaf = ((x - c) ** 2 + y ** 2 < r * r) & ((x + c) ** 2 + y ** 2 < r * r)
    hole = (x ** 2 + (y - 0.12) ** 2) < 0.06 ** 2
    vein = (np.abs(x) < 0.012) & leaf
    alpha = (leaf & ~hole).astype(float)
    g = 0.55 + 0.25 * (y + 0.5)
    rgb = np.stack([0.25 * np.ones_like(g), g, 0.12 * np.ones_like(g)], axis=-1)
    rgb[vein] = (0.75, 0.85, 0.35)
    return np.concatenate([rgb, alpha[..., None]], axis=-1)


def textured_material(name, base_img, normal_img=None, normal_strength=1.0):
    """Principled with an image base colour (UV map, linear filtering, repeat),
    optionally a tangent-space normal map; the exporter maps both to glTF."""
    mat = principled(name, roughness=0.5)
    nt = mat.node_tree
    bsdf = nt.nodes["Principled BSDF"]
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = base_img
    tex.interpolation = 'Linear'
    tex.extension = 'REPEAT'
    tex.location = (-400, 300)
    nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    if normal_img is not None:
        ntex = nt.nodes.new("ShaderNodeTexImage")
        ntex.image = normal_img
        ntex.interpolation = 'Linear'
        ntex.location = (-600, -200)
        nmap = nt.nodes.new("ShaderNodeNormalMap")
        nmap.space = 'TANGENT'
        nmap.inputs["Strength"].default_value = normal_strength
        nmap.location = (-250, -200)
        nt.links.new(ntex.outputs["Color"], nmap.inputs["Color"])
        nt.links.new(nmap.outputs["Normal"], bsdf.inputs["Normal"])
    return mat, tex


def gltf_output_group():
    """The exporter's 'glTF Material Output' node group (the one its importer
    makes): KHR_materials_volume is written only with its Thickness input."""
    name = "glTF Material Output"
    group = bpy.data.node_groups.get(name)
    if group is None:
        group = bpy.data.node_groups.new(name, 'ShaderNodeTree')
        group.inputs.new("NodeSocketFloat", "Occlusion")
        group.inputs.new("NodeSocketFloat", "Thickness").default_value = 0.0
        group.nodes.new("NodeGroupOutput")
        group.nodes.new("NodeGroupInput")
    return group


def glass(name, roughness, ior=1.5, thickness=None, attenuation=None):
    """Principled transmission 1 (white, so untinted). With thickness, the
    glTF volume settings node; with attenuation=(colour, distance), a Volume
    Absorption node with Color = colour and Density = 1 / distance, which is
    how the 3.4 exporter reads attenuationColor / attenuationDistance."""
    mat = principled(name, base=(1, 1, 1), roughness=roughness, IOR=ior, Transmission=1.0)
    nt = mat.node_tree
    if thickness is not None:
        node = nt.nodes.new("ShaderNodeGroup")
        node.node_tree = gltf_output_group()
        node.inputs["Thickness"].default_value = thickness
        node.location = (0, -400)
    if attenuation is not None:
        colour, distance = attenuation
        absorb = nt.nodes.new("ShaderNodeVolumeAbsorption")
        absorb.inputs["Color"].default_value = (*colour, 1.0)
        absorb.inputs["Density"].default_value = 1.0 / distance
        absorb.location = (0, -250)
        nt.links.new(absorb.outputs["Volume"], nt.nodes["Material Output"].inputs["Volume"])
    return mat


# --------------------------------------------------------------------------
# The scenes. Each returns the world radiance (r, g, b); Blender is Z-up.
# --------------------------------------------------------------------------

def scene_mr_grid(sc, outdir):
    """5x5 smooth spheres: metallic 0..1 left to right, roughness 0.05..1 top
    to bottom, orange base; grey floor; world 1.0 only."""
    world = set_world(sc, (1.0, 1.0, 1.0), 1.0)
    assign(add_plane(20, name="Floor"), principled("Floor", base=(0.5, 0.5, 0.5), roughness=0.5))
    n = 5
    for j in range(n):          # row: roughness, top row smoothest
        for i in range(n):      # column: metallic
            metallic = i / (n - 1)
            roughness = 0.05 + 0.95 * j / (n - 1)
            s = add_sphere(0.4, (i - 2.0, 0.0, 4.6 - j), name=f"Sphere_m{i}_r{j}")
            assign(s, principled(f"M{metallic:.2f}_R{roughness:.3f}", base=(0.8, 0.3, 0.1),
                                 metallic=metallic, roughness=roughness))
    add_camera(sc, (0.0, -11.0, 2.9), (0.0, 0.0, 2.6), fov_deg=38)
    return world


def scene_textured(sc, outdir):
    """A plane and a cube with a checker/gradient base colour and a bumpy
    normal map; a sun and world 0.3."""
    world = set_world(sc, (1.0, 1.0, 1.0), 0.3)
    base = save_png(outdir, "textured-basecolor", checker_gradient(), 'sRGB')
    normal = save_png(outdir, "textured-normal", bump_normal_map(), 'Non-Color')
    mat, _ = textured_material("Textured", base, normal)
    assign(add_plane(6, name="Plane"), mat)
    assign(add_cube(1.5, (0.2, 0.3, 0.75), rotation=(0, 0, math.radians(30)), name="Cube"), mat)
    sun = add_light(sc, "Sun", 'SUN', (0, 0, 5), 3.0)
    sun.rotation_euler = (math.radians(40), 0.0, math.radians(-30))  # 50 deg elevation
    add_camera(sc, (3.6, -4.8, 3.4), (0.0, 0.2, 0.4), fov_deg=50)
    return world


def _checker_floor(outdir, repeats=4):
    img = save_png(outdir, "checker", checker(), 'sRGB')
    mat, _ = textured_material("CheckerFloor", img)
    return assign(add_plane(12, name="Floor", uv_scale=repeats), mat)


def scene_transmission(sc, outdir):
    """A clear and a frosted glass sphere (IOR 1.5) on a checker floor, world
    1.0. No KHR_materials_volume: glTF calls this thin-walled; Cycles
    refracts through solid spheres (see the report)."""
    world = set_world(sc, (1.0, 1.0, 1.0), 1.0)
    _checker_floor(outdir)
    assign(add_sphere(0.8, (-1.0, 0.0, 0.8), name="Glass"), glass("Glass", 0.0))
    assign(add_sphere(0.8, (1.0, 0.0, 0.8), name="Frosted"), glass("Frosted", 0.3))
    add_camera(sc, (0.0, -5.5, 2.4), (0.0, 0.0, 0.7), fov_deg=45)
    return world


def scene_volume(sc, outdir):
    """As transmission, with KHR_materials_volume: clear solid glass
    (thickness only), orange absorbing glass and a frosted blue IOR 1.33 one."""
    world = set_world(sc, (1.0, 1.0, 1.0), 1.0)
    _checker_floor(outdir)
    assign(add_sphere(0.6, (-1.4, 0.0, 0.6), name="Clear"), glass("Clear", 0.0, thickness=1.2))
    assign(add_sphere(0.6, (0.0, 0.0, 0.6), name="Amber"),
           glass("Amber", 0.0, thickness=1.2, attenuation=((0.9, 0.5, 0.2), 0.5)))
    assign(add_sphere(0.6, (1.4, 0.0, 0.6), name="Ice"),
           glass("Ice", 0.3, ior=1.33, thickness=1.2, attenuation=((0.4, 0.7, 0.95), 0.8)))
    add_camera(sc, (0.0, -5.5, 2.4), (0.0, 0.0, 0.6), fov_deg=45)
    return world


def scene_alpha_mask(sc, outdir):
    """A leaf cut out by alpha (blend_method CLIP -> alphaMode MASK, cutoff
    0.5) standing over a floor; its shadow from a sun; world 0.25."""
    world = set_world(sc, (1.0, 1.0, 1.0), 0.25)
    assign(add_plane(10, name="Floor"), principled("Floor", base=(0.8, 0.8, 0.8), roughness=0.6))
    img = save_png(outdir, "leaf", leaf_alpha(), 'sRGB')
    mat, tex = textured_material("Leaf", img)
    mat.node_tree.links.new(tex.outputs["Alpha"], mat.node_tree.nodes["Principled BSDF"].inputs["Alpha"])
    mat.blend_method = 'CLIP'
    mat.shadow_method = 'CLIP'
    mat.alpha_threshold = 0.5
    mat.use_backface_culling = False          # -> doubleSided: true
    leaf = add_plane(2.4, (0.0, 0.0, 1.4), rotation=(math.radians(80), 0, math.radians(10)), name="Leaf")
    assign(leaf, mat)
    sun = add_light(sc, "Sun", 'SUN', (0, 0, 5), 2.5)
    # travelling away from the camera (+y) and down: the shadow lies behind the leaf
    sun.rotation_euler = (math.radians(50), 0.0, math.radians(-25))
    add_camera(sc, (2.2, -5.0, 2.8), (0.0, 0.6, 0.6), fov_deg=50)
    return world


def scene_emissive(sc, outdir):
    """A dark room: floor and back wall, an emissive quad (strength 5) and an
    emissive sphere, a diffuse cube; world black."""
    world = set_world(sc, (0.0, 0.0, 0.0), 1.0)
    white = principled("White", base=(0.8, 0.8, 0.8), roughness=0.7)
    assign(add_plane(10, name="Floor"), white)
    assign(add_plane(10, (0, 3.0, 5.0), rotation=(math.radians(90), 0, 0), name="BackWall"), white)
    panel = principled("Panel", base=(0.0, 0.0, 0.0), roughness=0.5,
                       **{"Emission": (1.0, 0.85, 0.6, 1.0), "Emission Strength": 5.0})
    assign(add_plane(1.0, (-0.8, 1.0, 2.2), rotation=(math.radians(60), 0, 0), name="Panel"), panel)
    bpy.data.objects["Panel"].scale = (2.0, 0.6, 1.0)
    ball = principled("Glow", base=(0.0, 0.0, 0.0), roughness=0.5,
                      **{"Emission": (0.2, 0.5, 1.0, 1.0), "Emission Strength": 5.0})
    assign(add_sphere(0.35, (1.3, -0.2, 0.35), name="GlowBall"), ball)
    assign(add_cube(0.8, (0.0, -0.4, 0.4), rotation=(0, 0, math.radians(20)), name="Cube"), white)
    add_camera(sc, (0.0, -6.0, 2.2), (0.0, 0.5, 1.0), fov_deg=50)
    return world


def scene_lights(sc, outdir):
    """Point, spot (60 degree cone, blend 0.3) and sun over a white diffuse
    floor with a few diffuse objects; world black."""
    world = set_world(sc, (0.0, 0.0, 0.0), 1.0)
    white = principled("White", base=(0.8, 0.8, 0.8), roughness=1.0, Specular=0.0)
    assign(add_plane(40, name="Floor"), white)
    assign(add_cube(0.8, (-1.6, 0.6, 0.4), rotation=(0, 0, math.radians(25)), name="Cube"), white)
    assign(add_sphere(0.5, (0.4, 1.2, 0.5), name="Ball"), white)
    bpy.ops.mesh.primitive_cylinder_add(radius=0.3, depth=1.4, location=(1.9, 0.0, 0.7))
    assign(active(), white).name = "Pillar"
    add_light(sc, "Point", 'POINT', (-1.5, -0.5, 2.5), 400.0, colour=(1.0, 0.8, 0.6))
    add_light(sc, "Spot", 'SPOT', (1.2, 0.2, 3.5), 600.0, colour=(0.6, 0.8, 1.0),
              target=(1.0, 0.6, 0.0), spot_size=math.radians(60), spot_blend=0.3)
    sun = add_light(sc, "Sun", 'SUN', (0, 0, 6), 1.0)
    sun.rotation_euler = (math.radians(50), 0.0, math.radians(120))
    add_camera(sc, (0.0, -6.5, 4.0), (0.0, 0.4, 0.5), fov_deg=55)
    return world


def scene_vertex_colors(sc, outdir):
    """A smooth sphere painted by vertex colours (a hue ramp around z,
    lighter towards the top; glTF's COLOR_0 times a white base colour) over a
    floor whose checker is looked up through a second UV map (TEXCOORD_1:
    the first map scaled 3x and turned 30 degrees); a sun and world 0.3."""
    world = set_world(sc, (1.0, 1.0, 1.0), 0.3)
    sphere = add_sphere(1.0, (0.0, 0.0, 1.0), name="Painted")
    mesh = sphere.data
    # Byte colours on face corners: what the 3.4 exporter writes as COLOR_0.
    layer = mesh.vertex_colors.new(name="Col")
    for poly in mesh.polygons:
        for li in poly.loop_indices:
            x, y, z = mesh.vertices[mesh.loops[li].vertex_index].co
            hue = (math.atan2(y, x) / (2.0 * math.pi)) % 1.0
            r, g, b = colorsys.hsv_to_rgb(hue, 0.8, 0.35 + 0.3 * (z + 1.0))
            layer.data[li].color = (r, g, b, 1.0)
    painted = principled("Painted", base=(1.0, 1.0, 1.0), roughness=0.4)
    nt = painted.node_tree
    vc = nt.nodes.new("ShaderNodeVertexColor")
    vc.layer_name = "Col"
    vc.location = (-400, 300)
    nt.links.new(vc.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
    assign(sphere, painted)

    img = save_png(outdir, "checker", checker(), 'sRGB')
    floor_mat, tex = textured_material("DetailFloor", img)
    uvmap = floor_mat.node_tree.nodes.new("ShaderNodeUVMap")
    uvmap.uv_map = "Detail"
    uvmap.location = (-650, 300)
    floor_mat.node_tree.links.new(uvmap.outputs["UV"], tex.inputs["Vector"])
    floor = assign(add_plane(8, name="Floor"), floor_mat)
    detail = floor.data.uv_layers.new(name="Detail")
    c, s = math.cos(math.radians(30.0)), math.sin(math.radians(30.0))
    for first, second in zip(floor.data.uv_layers["UVMap"].data, detail.data):
        u, v = first.uv
        second.uv = (3.0 * (c * u - s * v), 3.0 * (s * u + c * v))
    floor.data.uv_layers.active = floor.data.uv_layers["UVMap"]
    sun = add_light(sc, "Sun", 'SUN', (0, 0, 5), 3.0)
    sun.rotation_euler = (math.radians(40), 0.0, math.radians(-30))
    add_camera(sc, (3.4, -4.6, 3.2), (0.0, 0.0, 0.8), fov_deg=50)
    return world


def scene_instances(sc, outdir):
    """One mesh used by several objects (linked duplicates: obj.data shared)
    inside a nested, rotated and scaled hierarchy; a second mesh twice."""
    world = set_world(sc, (1.0, 1.0, 1.0), 0.5)
    assign(add_plane(14, name="Floor"), principled("Floor", base=(0.6, 0.6, 0.6), roughness=0.8))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=0.35)
    gem_src = active()
    gem_mesh = gem_src.data
    gem_mesh.name = "Gem"
    assign(gem_src, principled("Gem", base=(0.2, 0.6, 0.3), metallic=0.0, roughness=0.3))
    bpy.data.objects.remove(gem_src)          # keep only the mesh; objects below share it
    bpy.ops.mesh.primitive_torus_add(major_radius=0.35, minor_radius=0.1)
    ring_src = active()
    ring_mesh = ring_src.data
    ring_mesh.name = "Ring"
    assign(ring_src, principled("Ring", base=(0.9, 0.7, 0.3), metallic=1.0, roughness=0.25))
    bpy.data.objects.remove(ring_src)

    def obj(name, mesh, parent=None, loc=(0, 0, 0), rot=(0, 0, 0), scale=(1, 1, 1)):
        o = bpy.data.objects.new(name, mesh)   # mesh=None: an empty
        sc.collection.objects.link(o)
        o.parent = parent                      # no parent inverse: local = TRS
        o.location, o.rotation_euler, o.scale = loc, [math.radians(a) for a in rot], scale
        return o

    root = obj("Root", None, loc=(0, 0.5, 0.8), rot=(0, 0, 30), scale=(1.3, 1.3, 1.3))
    obj("GemA", gem_mesh, root, loc=(-1.2, 0, 0))
    obj("GemB", gem_mesh, root, loc=(0, 0, 0), rot=(20, 0, 45), scale=(1.0, 1.0, 1.8))
    arm = obj("Arm", None, root, loc=(1.2, 0, 0), rot=(0, 0, -60), scale=(0.7, 0.7, 0.7))
    obj("GemC", gem_mesh, arm, loc=(0, 0.8, 0))
    obj("RingA", ring_mesh, arm, loc=(0, -0.8, 0), rot=(90, 0, 0))
    obj("GemD", gem_mesh, None, loc=(-2.2, -1.2, 0.35))
    obj("RingB", ring_mesh, None, loc=(2.0, -1.3, 0.1), rot=(0, 0, 10))
    sun = add_light(sc, "Sun", 'SUN', (0, 0, 6), 2.0)
    sun.rotation_euler = (math.radians(35), 0.0, math.radians(40))
    add_camera(sc, (0.0, -6.0, 3.2), (0.0, 0.0, 0.6), fov_deg=50)
    return world


SCENES = {
    "mr-grid": scene_mr_grid,
    "textured": scene_textured,
    "transmission": scene_transmission,
    "volume": scene_volume,
    "alpha-mask": scene_alpha_mask,
    "emissive": scene_emissive,
    "lights": scene_lights,
    "instances": scene_instances,
    "vertex-colors": scene_vertex_colors,
}


# --------------------------------------------------------------------------
# Output
# --------------------------------------------------------------------------

def write_exr(path, rgb):
    """Write rgb (H x W x 3, row 0 = top) as an uncompressed scanline OpenEXR
    with 32-bit float R, G, B channels. Written by hand because Blender's
    Image.save() of a generated float image stores display-encoded (sRGB)
    values in 3.4 (0.3 came back as 0.584), and an env map must be linear."""
    import struct
    rgb = np.asarray(rgb, dtype="<f4")
    h, w, _ = rgb.shape

    def attr(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value

    channels = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "BGR") + b"\0"
    window = struct.pack("<4i", 0, 0, w - 1, h - 1)
    header = (struct.pack("<ii", 20000630, 2)
              + attr("channels", "chlist", channels)
              + attr("compression", "compression", b"\0")
              + attr("dataWindow", "box2i", window)
              + attr("displayWindow", "box2i", window)
              + attr("lineOrder", "lineOrder", b"\0")
              + attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
              + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
              + attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
              + b"\0")
    line_bytes = 3 * 4 * w
    first = len(header) + 8 * h
    offsets = struct.pack(f"<{h}Q", *(first + y * (8 + line_bytes) for y in range(h)))
    blocks = b"".join(struct.pack("<ii", y, line_bytes)
                      + rgb[y, :, 2].tobytes() + rgb[y, :, 1].tobytes() + rgb[y, :, 0].tobytes()
                      for y in range(h))
    with open(path, "wb") as f:
        f.write(header + offsets + blocks)


def write_env(path, radiance):
    """ENV_W x ENV_H linear float OpenEXR, every pixel = radiance; read back
    through Blender's own EXR reader to check it opens and holds the values."""
    write_exr(path, np.broadcast_to(np.asarray(radiance, dtype=np.float32), (ENV_H, ENV_W, 3)))
    check = bpy.data.images.load(path)
    got = np.empty(ENV_W * ENV_H * 4, dtype=np.float32)
    check.pixels.foreach_get(got)
    size = tuple(check.size)
    bpy.data.images.remove(check)
    if size != (ENV_W, ENV_H) or not np.allclose(got.reshape(-1, 4)[:, :3], radiance, rtol=1e-6, atol=1e-7):
        raise RuntimeError(f"{path}: read back {size} {got[:3]}, wrote {radiance}")


def export(sc, outdir, name, world):
    glb = os.path.join(outdir, name + ".glb")
    blend = os.path.join(outdir, name + ".blend")
    env = os.path.join(outdir, name + ".env.exr")
    bpy.ops.object.select_all(action='DESELECT')
    bpy.ops.export_scene.gltf(
        filepath=glb, export_format='GLB',
        export_cameras=True, export_lights=True,
        convert_lighting_mode='SPEC',  # the default: W -> lm with 683 lm/W
        export_yup=True, export_apply=True,
        export_animations=False, export_extras=False,
        export_image_format='AUTO',    # PNG stays PNG
        use_selection=False)
    has_env = any(c > 0.0 for c in world)
    if has_env:
        write_env(env, world)
    elif os.path.exists(env):
        os.remove(env)                 # a stale one from an older version
    with open(os.path.join(outdir, name + ".json"), "w") as f:
        json.dump({"name": name, "width": WIDTH, "height": HEIGHT,
                   "world": world, "env": os.path.basename(env) if has_env else None,
                   "blender": bpy.app.version_string}, f, indent=1)
        f.write("\n")
    bpy.ops.wm.save_as_mainfile(filepath=blend, check_existing=False)
    print(f"make-scenes: {name}: {glb} ({os.path.getsize(glb)} bytes), {blend}"
          + (f", {env}" if has_env else ", world black: no env file"), flush=True)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv or argv[0].startswith("-"):
        sys.exit(__doc__)
    outdir = os.path.abspath(argv[0])
    names = argv[1:] or list(SCENES)
    unknown = [n for n in names if n not in SCENES]
    if unknown:
        sys.exit(f"make-scenes.py: unknown scene(s) {unknown}; known: {list(SCENES)}")
    if bpy.app.version[:2] != (3, 4):
        print(f"make-scenes.py: WARNING: written for Blender 3.4, this is "
              f"{bpy.app.version_string}; exporter options and units may differ", flush=True)
    os.makedirs(outdir, exist_ok=True)
    for name in names:
        sc = new_scene()
        world = SCENES[name](sc, outdir)
        export(sc, outdir, name, world)


if __name__ == "__main__":
    try:
        main()
    except SystemExit:
        raise
    except BaseException:
        import traceback
        traceback.print_exc()
        sys.exit(1)   # Blender would otherwise exit 0 after a failing --python script
