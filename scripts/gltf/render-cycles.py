"""Render a reference image of a glTF test scene with Cycles (CPU).

    blender -b --factory-startup OUTDIR/NAME.blend --python scripts/gltf/render-cycles.py -- OUT.exr SPP [options]
    blender -b --factory-startup --python scripts/gltf/render-cycles.py -- OUT.exr SPP --from-glb NAME.glb [options]

The first form renders the scene as make-scenes.py built it. The second
starts from an empty factory scene, imports NAME.glb with Blender's glTF
importer, gives it a constant world and renders through the imported
camera: Cycles then sees what the .glb holds, which is what lucent reads
(the one to compare lucent with: whatever the exporter drops or changes is
missing from both images alike; the .blend render shows what that was).

OUT.exr: linear OpenEXR, RGBA 32-bit float, ZIP. SPP: samples per pixel.

Options:
  --from-glb FILE   import FILE instead of using the open .blend
  --world R,G,B     (or one value) constant world radiance for --from-glb;
                    default: "world" from FILE's sidecar FILE.json, else black
  --size W H        image size for --from-glb; default: the sidecar's, else 320 240
  --threads N       CPU threads (default 0: all)
  --seed N          Cycles' seed (default 0)
  --preview PNG     also write an 8-bit sRGB PNG (view transform Standard)
  --native          keep Cycles' own meaning of spot lights, alpha clip and
                    volume absorption instead of glTF's (see below)
  --lambert         purely diffuse Principled BSDFs (metallic, specular and
                    transmission 0) become Lambertian Diffuse BSDFs, as glTF's
                    diffuse is (Principled v1's is Burley's)
  --gltf-brdf       opaque Principled BSDFs (no transmission, emission,
                    alpha, clearcoat or sheen) become glTF's layering
                    built from Cycles nodes: mix(Lambert(base), GGX(white),
                    Fresnel(ior 1.5)) for the dielectric, GGX(base) for the
                    metal, mixed by metallic (Principled v1 adds its specular
                    to an unweighted Burley diffuse instead)

Render settings (both forms): Cycles on the CPU, SPP samples, no adaptive
sampling, no denoising, box pixel filter 1 px wide (Cycles' narrowest
standard choice: each sample counts only in its own pixel, as lucent's
default box filter), 64 bounces of every kind, no clamping, no glossy
filtering, light threshold 0, caustics on, view transform Standard (EXR
output is linear scene radiance whatever the view transform).

Fix-ups, so that Cycles renders what glTF means (off with --native except
the first two):
  * point/spot lamps get radius 0 and suns angle 0 (glTF lights are
    punctual; Blender's glTF importer leaves its 0.25 m default radius);
  * every Principled BSDF uses single-scattering GGX;
  * spot lamps become point lamps whose emission is the glTF cone profile:
    I x smoothstep(cos outer, cos inner, cos theta), inner = outer x (1 -
    blend), outer = spot_size / 2 (the exporter's mapping). Cycles 3.4's own
    spot also multiplies by cos theta and ramps over a different band;
  * materials with blend_method CLIP (glTF alphaMode MASK): alpha becomes
    1 where alpha >= alpha_threshold, else 0. Cycles ignores blend_method
    and would blend the filtered alpha at the cut-out's edge;
  * Volume Absorption: Cycles absorbs sigma = (1 - Color) x Density, glTF
    (and the exporter, which writes Color as attenuationColor and
    1 / Density as attenuationDistance) means sigma = -ln(Color) x Density;
    the node is rewritten to give glTF's sigma.
"""

import json
import math
import os
import sys
import time

try:
    import bpy
except ImportError:
    sys.exit("render-cycles.py runs inside Blender (Debian: apt-get install -y blender); usage:\n"
             + __doc__)


def fail(msg):
    print(f"render-cycles.py: error: {msg}", file=sys.stderr, flush=True)
    sys.exit(2)


def parse_args(argv):
    opts = {"out": None, "spp": None, "glb": None, "world": None, "size": None,
            "threads": 0, "seed": 0, "preview": None, "native": False,
            "lambert": False, "gltf_brdf": False}
    pos = []
    i = 0
    try:
        while i < len(argv):
            a = argv[i]
            if a == "--from-glb":
                opts["glb"] = os.path.abspath(argv[i + 1]); i += 2
            elif a == "--world":
                vals = [float(v) for v in argv[i + 1].split(",")]
                if len(vals) == 1:
                    vals *= 3
                if len(vals) != 3:
                    fail("--world takes R,G,B or one value")
                opts["world"] = vals; i += 2
            elif a == "--size":
                opts["size"] = (int(argv[i + 1]), int(argv[i + 2])); i += 3
            elif a == "--threads":
                opts["threads"] = int(argv[i + 1]); i += 2
            elif a == "--seed":
                opts["seed"] = int(argv[i + 1]); i += 2
            elif a == "--preview":
                opts["preview"] = os.path.abspath(argv[i + 1]); i += 2
            elif a == "--native":
                opts["native"] = True; i += 1
            elif a == "--lambert":
                opts["lambert"] = True; i += 1
            elif a == "--gltf-brdf":
                opts["gltf_brdf"] = True; i += 1
            elif a in ("-h", "--help"):
                print(__doc__); sys.exit(0)
            elif a.startswith("--"):
                fail(f"unknown option {a}")
            else:
                pos.append(a); i += 1
    except (IndexError, ValueError):
        fail(f"bad or missing value after {argv[i]}")
    if len(pos) != 2:
        fail("need OUT.exr and SPP\n" + __doc__)
    opts["out"] = os.path.abspath(pos[0])
    try:
        opts["spp"] = int(pos[1])
    except ValueError:
        fail(f"SPP must be a whole number, got {pos[1]!r}")
    if opts["spp"] < 1:
        fail("SPP must be at least 1")
    return opts


# --------------------------------------------------------------------------
# Scene set-up
# --------------------------------------------------------------------------

def sidecar(glb):
    path = os.path.splitext(glb)[0] + ".json"
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    return {}


def import_glb(opts):
    """Empty factory scene + the .glb through Blender's importer + a world."""
    if not os.path.isfile(opts["glb"]):
        fail(f"no such file: {opts['glb']}")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    # Debian's Blender 3.4 runs on the system numpy (1.24), which dropped the
    # alias np.bool that the 3.4 importer still uses (gltf2_blender_mesh.py,
    # shade-smooth flags): put the alias back (it was the builtin bool).
    import numpy
    if "bool" not in numpy.__dict__:
        numpy.bool = bool
    result = bpy.ops.import_scene.gltf(filepath=opts["glb"], import_shading='NORMALS')
    if result != {'FINISHED'}:
        fail(f"importing {opts['glb']} failed: {result}")
    cams = sorted((o for o in sc.objects if o.type == 'CAMERA'), key=lambda o: o.name)
    if not cams:
        fail(f"{opts['glb']} has no camera")
    sc.camera = cams[0]
    meta = sidecar(opts["glb"])
    world = opts["world"] if opts["world"] is not None else meta.get("world")
    if world is None:
        print("render-cycles.py: no --world and no sidecar: black world", flush=True)
        world = [0.0, 0.0, 0.0]
    w = bpy.data.worlds.new("World")
    w.use_nodes = True
    bg = w.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*world, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    sc.world = w
    if opts["size"]:
        size = opts["size"]
    elif "width" in meta:
        size = (meta["width"], meta["height"])
    else:
        size = (320, 240)
    sc.render.resolution_x, sc.render.resolution_y = size
    print(f"render-cycles.py: imported {opts['glb']}: camera {sc.camera.name!r}, "
          f"world {world}, {size[0]}x{size[1]}", flush=True)
    return sc


def configure(sc, opts):
    """Cycles settings for an unbiased, unfiltered, unclamped reference."""
    sc.render.engine = 'CYCLES'
    cy = sc.cycles
    cy.device = 'CPU'
    cy.samples = opts["spp"]
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = opts["seed"]
    cy.use_animated_seed = False
    cy.pixel_filter_type = 'BOX'
    cy.filter_width = 1.0
    cy.max_bounces = 64
    cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 64
    cy.volume_bounces = 64
    cy.transparent_max_bounces = 64
    cy.sample_clamp_direct = 0.0          # 0 = no clamping
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0                  # "filter glossy" off
    cy.caustics_reflective = cy.caustics_refractive = True
    cy.light_sampling_threshold = 0.0     # sample every light, however dim
    cy.film_exposure = 1.0
    sc.render.film_transparent = False
    sc.render.use_motion_blur = False
    sc.render.resolution_percentage = 100
    sc.render.pixel_aspect_x = sc.render.pixel_aspect_y = 1.0
    sc.render.use_compositing = False
    sc.render.use_sequencer = False
    sc.render.threads_mode = 'FIXED' if opts["threads"] > 0 else 'AUTO'
    if opts["threads"] > 0:
        sc.render.threads = opts["threads"]
    sc.view_settings.view_transform = 'Standard'
    sc.view_settings.look = 'None'
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    if sc.camera is not None and sc.camera.data.dof.use_dof:
        sc.camera.data.dof.use_dof = False
    im = sc.render.image_settings
    im.file_format = 'OPEN_EXR'
    im.color_mode = 'RGBA'
    im.color_depth = '32'
    im.exr_codec = 'ZIP'


# --------------------------------------------------------------------------
# glTF fix-ups
# --------------------------------------------------------------------------

def punctual_lights(sc, log):
    for obj in sc.objects:
        if obj.type != 'LIGHT':
            continue
        light = obj.data
        if light.type in ('POINT', 'SPOT') and light.shadow_soft_size != 0.0:
            log.append(f"light {obj.name}: radius {light.shadow_soft_size:g} -> 0")
            light.shadow_soft_size = 0.0
        elif light.type == 'SUN' and light.angle != 0.0:
            log.append(f"light {obj.name}: sun angle {light.angle:g} -> 0")
            light.angle = 0.0


def ggx_everywhere(log):
    for mat in bpy.data.materials:
        if not mat.node_tree:
            continue
        for node in mat.node_tree.nodes:
            if node.type == 'BSDF_PRINCIPLED' and node.distribution != 'GGX':
                log.append(f"material {mat.name}: {node.distribution} -> GGX")
                node.distribution = 'GGX'


def principled_nodes():
    """(material, nodes, links, node) for every Principled BSDF of the file."""
    for mat in bpy.data.materials:
        if not mat.node_tree:
            continue
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        for node in list(nodes):
            if node.type == 'BSDF_PRINCIPLED':
                yield mat, nodes, links, node


def lambert_diffuse(log):
    """Principled BSDFs that are purely diffuse (metallic, specular and
    transmission 0, unlinked) -> Cycles' Diffuse BSDF at roughness 0, which
    is Lambert, as glTF's diffuse is; Principled v1's diffuse is Burley's,
    brighter at grazing angles."""
    for mat, nodes, links, node in principled_nodes():
        zero = all(not node.inputs[k].is_linked and node.inputs[k].default_value == 0.0
                   for k in ("Metallic", "Specular", "Transmission"))
        if not zero:
            continue
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Roughness"].default_value = 0.0
        base = node.inputs["Base Color"]
        if base.is_linked:
            links.new(base.links[0].from_socket, diffuse.inputs["Color"])
        else:
            diffuse.inputs["Color"].default_value = base.default_value
        if node.inputs["Normal"].is_linked:
            links.new(node.inputs["Normal"].links[0].from_socket, diffuse.inputs["Normal"])
        for link in list(node.outputs["BSDF"].links):
            links.new(diffuse.outputs["BSDF"], link.to_socket)
        log.append(f"material {mat.name}: Principled (diffuse only) -> Lambert")


def gltf_brdf(log):
    """Opaque Principled BSDFs -> glTF 2.0's Appendix B layering, from
    Cycles nodes: the dielectric is Lambert(base) and GGX(white) mixed by a
    Fresnel of index 1.5 (Cycles' dielectric Fresnel at N.V, where glTF's
    Schlick uses V.H: close for the 4% of index 1.5), the metal a GGX of the
    base colour, the two mixed by metallic. Roughness is glTF's (Cycles
    squares it as glTF does)."""
    for mat, nodes, links, node in principled_nodes():
        inp = node.inputs
        plain = all(not inp[k].is_linked and inp[k].default_value == 0.0
                    for k in ("Transmission", "Clearcoat", "Sheen"))
        # Emission and alpha stay the Principled BSDF's business.
        emits = inp["Emission"].is_linked or any(v > 0 for v in inp["Emission"].default_value[:3])
        emits = emits and (inp["Emission Strength"].is_linked or inp["Emission Strength"].default_value > 0)
        cut = inp["Alpha"].is_linked or inp["Alpha"].default_value < 1.0
        if not plain or emits or cut:
            continue

        def feed(src, dst):
            if src.is_linked:
                links.new(src.links[0].from_socket, dst)
            else:
                dst.default_value = src.default_value

        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Roughness"].default_value = 0.0
        feed(inp["Base Color"], diffuse.inputs["Color"])
        spec = nodes.new("ShaderNodeBsdfGlossy")
        spec.distribution = 'GGX'
        spec.inputs["Color"].default_value = (1, 1, 1, 1)
        metal = nodes.new("ShaderNodeBsdfGlossy")
        metal.distribution = 'GGX'
        feed(inp["Base Color"], metal.inputs["Color"])
        for g in (spec, metal):
            feed(inp["Roughness"], g.inputs["Roughness"])
        fresnel = nodes.new("ShaderNodeFresnel")
        fresnel.inputs["IOR"].default_value = 1.5
        if inp["Normal"].is_linked:
            for n in (diffuse, spec, metal, fresnel):
                links.new(inp["Normal"].links[0].from_socket, n.inputs["Normal"])
        dielectric = nodes.new("ShaderNodeMixShader")
        links.new(fresnel.outputs["Fac"], dielectric.inputs["Fac"])
        links.new(diffuse.outputs["BSDF"], dielectric.inputs[1])
        links.new(spec.outputs["BSDF"], dielectric.inputs[2])
        whole = nodes.new("ShaderNodeMixShader")
        feed(inp["Metallic"], whole.inputs["Fac"])
        links.new(dielectric.outputs["Shader"], whole.inputs[1])
        links.new(metal.outputs["BSDF"], whole.inputs[2])
        for link in list(node.outputs["BSDF"].links):
            links.new(whole.outputs["Shader"], link.to_socket)
        log.append(f"material {mat.name}: Principled -> glTF layering (Lambert, GGX, Fresnel 1.5)")


def gltf_spots(sc, log):
    """Spot lamp -> point lamp with the glTF cone as a node profile. In a
    lamp's shader, Texture Coordinate > Normal is the direction from the lamp
    to the shaded point in the lamp's object space; the cone axis is -Z."""
    for obj in sc.objects:
        if obj.type != 'LIGHT' or obj.data.type != 'SPOT':
            continue
        light = obj.data
        if light.use_nodes:
            fail(f"spot {obj.name} already has a node tree; use --native")
        outer = light.spot_size / 2
        inner = outer * (1.0 - light.spot_blend)
        cos_outer, cos_inner = math.cos(outer), math.cos(inner)
        if cos_inner - cos_outer < 1e-6:      # a hard edge: keep the map defined
            cos_inner = cos_outer + 1e-6
        light.type = 'POINT'
        light.shadow_soft_size = 0.0
        light.use_nodes = True
        nt = light.node_tree
        emission = next(n for n in nt.nodes if n.type == 'EMISSION')
        coord = nt.nodes.new("ShaderNodeTexCoord")
        split = nt.nodes.new("ShaderNodeSeparateXYZ")
        negate = nt.nodes.new("ShaderNodeMath")
        negate.operation = 'MULTIPLY'
        negate.inputs[1].default_value = -1.0
        ramp = nt.nodes.new("ShaderNodeMapRange")
        ramp.interpolation_type = 'SMOOTHSTEP'
        ramp.clamp = True
        ramp.inputs["From Min"].default_value = cos_outer
        ramp.inputs["From Max"].default_value = cos_inner
        ramp.inputs["To Min"].default_value = 0.0
        ramp.inputs["To Max"].default_value = 1.0
        nt.links.new(coord.outputs["Normal"], split.inputs["Vector"])
        nt.links.new(split.outputs["Z"], negate.inputs[0])
        nt.links.new(negate.outputs["Value"], ramp.inputs["Value"])
        nt.links.new(ramp.outputs["Result"], emission.inputs["Strength"])
        log.append(f"light {obj.name}: spot -> point with glTF cone "
                   f"(inner {math.degrees(inner):.2f}, outer {math.degrees(outer):.2f} deg, "
                   f"smoothstep in cos)")


def alpha_clip(log):
    """blend_method CLIP: alpha -> (alpha >= threshold), for Cycles."""
    for mat in bpy.data.materials:
        if mat.blend_method != 'CLIP' or not mat.node_tree:
            continue
        nt = mat.node_tree
        for node in [n for n in nt.nodes if n.type == 'BSDF_PRINCIPLED']:
            sock = node.inputs["Alpha"]
            cut = mat.alpha_threshold
            if not sock.is_linked:
                sock.default_value = 1.0 if sock.default_value >= cut else 0.0
            else:
                source = sock.links[0].from_socket
                below = nt.nodes.new("ShaderNodeMath")
                below.operation = 'LESS_THAN'         # 1 where alpha < cutoff
                below.inputs[1].default_value = cut
                keep = nt.nodes.new("ShaderNodeMath")
                keep.operation = 'SUBTRACT'           # 1 - (alpha < cutoff)
                keep.inputs[0].default_value = 1.0
                nt.links.new(source, below.inputs[0])
                nt.links.new(below.outputs[0], keep.inputs[1])
                nt.links.new(keep.outputs[0], sock)
            log.append(f"material {mat.name}: alpha clipped at {cut:g}")


def gltf_absorption(log):
    """Volume Absorption: make sigma = -ln(Color) x Density per channel.
    Cycles gives (1 - C') x D'; with m = max_c(-ln C): C' = 1 + ln(C) / m,
    D' = m x D keeps every C' in [0, 1]."""
    for mat in bpy.data.materials:
        if not mat.node_tree:
            continue
        for node in mat.node_tree.nodes:
            if node.type != 'VOLUME_ABSORPTION':
                continue
            col, den = node.inputs["Color"], node.inputs["Density"]
            if col.is_linked or den.is_linked:
                log.append(f"material {mat.name}: textured absorption left as Cycles'")
                continue
            c = [min(max(v, 1e-6), 1.0) for v in col.default_value[:3]]
            sigma = [max(-math.log(v), 0.0) for v in c]
            m = max(sigma)
            d = den.default_value
            if m == 0.0 or d == 0.0:
                # Nothing absorbs (the importer adds such a node for a volume
                # with thickness only): drop it, Cycles renders faster.
                for link in list(node.outputs["Volume"].links):
                    mat.node_tree.links.remove(link)
                log.append(f"material {mat.name}: zero absorption: volume shader unlinked")
                continue
            new_c = [1.0 - s / m for s in sigma]
            den.default_value = d * m
            col.default_value = (*new_c, 1.0)
            log.append(f"material {mat.name}: absorption colour {c} density {d:g} -> "
                       f"colour {[round(v, 6) for v in new_c]} density {den.default_value:g} "
                       f"(sigma {[round(s * d, 6) for s in sigma]} per unit)")


# --------------------------------------------------------------------------

def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    opts = parse_args(argv)
    if opts["glb"]:
        sc = import_glb(opts)
        source = opts["glb"]
    else:
        if not bpy.data.filepath:
            fail("no .blend open and no --from-glb; usage:\n" + __doc__)
        sc = bpy.context.scene
        source = bpy.data.filepath
    if sc.camera is None:
        fail(f"{source}: the scene has no camera")
    configure(sc, opts)
    log = []
    punctual_lights(sc, log)
    ggx_everywhere(log)
    if not opts["native"]:
        gltf_spots(sc, log)
        alpha_clip(log)
        gltf_absorption(log)
    if opts["lambert"]:
        lambert_diffuse(log)
    if opts["gltf_brdf"]:
        gltf_brdf(log)
    for line in log:
        print("render-cycles.py: fix-up: " + line, flush=True)
    os.makedirs(os.path.dirname(opts["out"]), exist_ok=True)
    sc.render.filepath = opts["out"]
    sc.render.use_file_extension = False
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - t0
    if not os.path.isfile(opts["out"]):
        fail(f"Cycles wrote no {opts['out']}")
    if opts["preview"]:
        im = sc.render.image_settings
        im.file_format, im.color_mode, im.color_depth = 'PNG', 'RGB', '8'
        bpy.data.images["Render Result"].save_render(opts["preview"], scene=sc)
    print(f"render-cycles.py: {source} -> {opts['out']}: {sc.render.resolution_x}x"
          f"{sc.render.resolution_y}, {opts['spp']} spp, render {seconds:.1f} s", flush=True)


if __name__ == "__main__":
    try:
        main()
    except SystemExit:
        raise
    except BaseException:
        import traceback
        traceback.print_exc()
        sys.exit(1)
