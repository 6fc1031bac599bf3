# Renders a glTF asset and the asset `sdcb export` wrote back with the same
# camera, lights and resolution (Blender, Cycles on the CPU: headless, no
# GPU, no display), four PNGs into OUT_DIR:
#   input.png, output.png            the assets as imported (their materials
#                                    and textures)
#   input_wire.png, output_wire.png  a grey clay material with the triangles'
#                                    edges drawn (Cycles' Wireframe node)
# and OUT_DIR/counts.txt: "input N" and "output M", the triangles of the
# mesh objects (an instanced mesh counts once per object).
# The camera frames the input's bounding sphere from a 3/4 view (AZIMUTH and
# ELEVATION in degrees, Blender's Z up: glTF's +Y).
#
# usage: blender -b --factory-startup -P bench/render_gltf.py -- \
#          INPUT.glb OUTPUT.glb OUT_DIR [WIDTH HEIGHT SAMPLES AZIMUTH ELEVATION]
import math
import os
import sys

import bpy
import mathutils
import numpy

# Debian 12's Blender 3.4.1 glTF importer still writes `numpy.bool`, which
# numpy 1.24 removed (io_scene_gltf2/blender/imp/gltf2_blender_mesh.py).
if not hasattr(numpy, "bool"):
    numpy.bool = numpy.bool_

args = sys.argv[sys.argv.index("--") + 1:]
input_path, output_path, out_dir = args[0], args[1], args[2]
width, height, samples = (int(a) for a in (args[3:6] if len(args) >= 6 else (480, 360, 64)))
azimuth, elevation = (float(a) for a in (args[6:8] if len(args) >= 8 else (-35.0, 25.0)))


def import_asset(path):
    """Empties the scene, imports PATH, keeps only its meshes (the asset's
    cameras and lights would differ between input and output)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    for obj in list(bpy.data.objects):
        if obj.type in {"CAMERA", "LIGHT"}:
            bpy.data.objects.remove(obj)
    return [o for o in bpy.context.scene.objects if o.type == "MESH"]


def triangles(meshes):
    return sum(len(p.vertices) - 2 for o in meshes for p in o.data.polygons)


def bounding_sphere(meshes):
    corners = [o.matrix_world @ mathutils.Vector(c) for o in meshes for c in o.bound_box]
    lo = mathutils.Vector([min(c[i] for c in corners) for i in range(3)])
    hi = mathutils.Vector([max(c[i] for c in corners) for i in range(3)])
    return (lo + hi) / 2, (hi - lo).length / 2


def set_up_scene(center, radius):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.dither_intensity = 0  # a flat background stays flat (smaller PNGs)
    scene.view_settings.view_transform = "Standard"  # textures' colours as stored

    world = bpy.data.worlds.new("neutral")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.8, 0.8, 0.8, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
    scene.world = world

    az, el = math.radians(azimuth), math.radians(elevation)
    direction = mathutils.Vector((math.cos(el) * math.sin(az), -math.cos(el) * math.cos(az), math.sin(el)))
    camera_data = bpy.data.cameras.new("camera")
    camera_data.lens_unit = "FOV"
    camera_data.sensor_fit = "AUTO"
    camera_data.angle = math.radians(30)  # across the wider side
    narrow = 2 * math.atan(math.tan(camera_data.angle / 2) * min(width, height) / max(width, height))
    camera = bpy.data.objects.new("camera", camera_data)
    camera.location = center + direction * (1.08 * radius / math.sin(narrow / 2))
    camera.rotation_euler = (-direction).to_track_quat("-Z", "Y").to_euler()
    camera_data.clip_start, camera_data.clip_end = radius * 0.01, radius * 100
    scene.collection.objects.link(camera)
    scene.camera = camera

    sun_data = bpy.data.lights.new("sun", "SUN")
    sun_data.energy = 3.0
    sun_data.angle = math.radians(10)
    sun = bpy.data.objects.new("sun", sun_data)
    key = mathutils.Vector((math.sin(az - 0.8), -math.cos(az - 0.8), 1.2))
    sun.rotation_euler = (-key).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(sun)


def clay_with_edges():
    """Light grey diffuse, the triangles' edges dark grey, one pixel wide."""
    material = bpy.data.materials.new("clay_with_edges")
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    clay = nodes.new("ShaderNodeBsdfDiffuse")
    clay.inputs["Color"].default_value = (0.7, 0.7, 0.7, 1)
    edge = nodes.new("ShaderNodeBsdfDiffuse")
    edge.inputs["Color"].default_value = (0.03, 0.03, 0.03, 1)
    wire = nodes.new("ShaderNodeWireframe")
    wire.use_pixel_size = True
    wire.inputs["Size"].default_value = 1.0
    mix = nodes.new("ShaderNodeMixShader")
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(wire.outputs["Fac"], mix.inputs["Fac"])
    links.new(clay.outputs["BSDF"], mix.inputs[1])
    links.new(edge.outputs["BSDF"], mix.inputs[2])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return material


def render(name):
    bpy.context.scene.render.filepath = os.path.join(out_dir, name + ".png")
    bpy.ops.render.render(write_still=True)
    print("render_gltf: wrote", bpy.context.scene.render.filepath)


counts = {}
camera_frame = None
for label, path in (("input", input_path), ("output", output_path)):
    meshes = import_asset(path)
    counts[label] = triangles(meshes)
    if camera_frame is None:
        camera_frame = bounding_sphere(meshes)  # the input's: the same camera for both
    set_up_scene(*camera_frame)
    render(label)
    bpy.context.view_layer.material_override = clay_with_edges()
    render(label + "_wire")

with open(os.path.join(out_dir, "counts.txt"), "w") as f:
    for label, n in counts.items():
        f.write("%s %d\n" % (label, n))
print("render_gltf: triangles", counts)
