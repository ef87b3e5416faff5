"""Cycles' true displacement of a height image on scenes/uv_sphere.obj, for a side-by-side check of
meso's displacement reference (docs/validation.md, "Against Cycles"). Run with Blender 3.x:

  blender -b --factory-startup -P tools/cycles_uv_sphere.py -- HEIGHT.png DICING_RATE SAMPLES OUT.exr

The scene is the one docs/validation.md describes, in Blender's axes (meso's y up is Blender's z):
the sphere drawn as a Catmull-Clark surface with linear uv (Cycles' adaptive subdivision, diced at
DICING_RATE pixels), the image repeated 4 times per unit of uv (bilinear texels, non-colour),
displaced along the normal by 0.01 * (h - mean h), a grey Lambertian surface (albedo 0.8) under a
sun of strength pi (so that a facing facet gets 0.8, as meso's kd = 0.8 with intensity 1) along
meso's direction (-0.5, -0.55, -0.6), no ambient and no bounces, camera at meso's (0, 1.2, 3.2)
looking at the centre with a 40 degree vertical field of view, 320 x 240, one-pixel box filter,
transparent film (alpha marks the sphere's pixels)."""
import math
import os
import sys

import bpy
import mathutils

argv = sys.argv[sys.argv.index("--") + 1:]
if len(argv) != 4:
    sys.exit(__doc__)
height, rate, samples, out = argv[0], float(argv[1]), int(argv[2]), os.path.abspath(argv[3])
repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
scene = bpy.context.scene
bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.delete()
bpy.ops.wm.obj_import(filepath=os.path.join(repo, "scenes", "uv_sphere.obj"),
                      forward_axis="NEGATIVE_Z", up_axis="Y")
obj = bpy.context.selected_objects[0]
for p in obj.data.polygons:
    p.use_smooth = True
scene.render.engine = "CYCLES"
cycles = scene.cycles
cycles.feature_set = "EXPERIMENTAL"  # adaptive subdivision
cycles.device = "CPU"
cycles.samples = samples
cycles.use_denoising = False
cycles.use_adaptive_sampling = False
cycles.max_bounces = 0  # direct light only, as meso's local model
cycles.filter_type = "BOX"
cycles.filter_width = 1.0
cycles.seed = 1
cycles.dicing_rate = rate
cycles.max_subdivisions = 16
subd = obj.modifiers.new("subd", "SUBSURF")
subd.subdivision_type = "CATMULL_CLARK"
subd.uv_smooth = "NONE"  # linear uv inside each face, as meso's limit surface
obj.cycles.use_adaptive_subdivision = True

image = bpy.data.images.load(os.path.abspath(height))
image.colorspace_settings.name = "Non-Color"
px = image.pixels[:]  # RGBA floats; the height is the mean of R, G and B (grey images: the grey)
channels = image.channels
midlevel = sum(sum(px[i:i + 3]) / 3.0 for i in range(0, len(px), channels)) / (len(px) // channels)

mat = bpy.data.materials.new("relief")
mat.use_nodes = True
nodes, links = mat.node_tree.nodes, mat.node_tree.links
nodes.clear()
output = nodes.new("ShaderNodeOutputMaterial")
bsdf = nodes.new("ShaderNodeBsdfDiffuse")
bsdf.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
coords = nodes.new("ShaderNodeTexCoord")
mapping = nodes.new("ShaderNodeMapping")
mapping.inputs["Scale"].default_value = (4.0, 4.0, 1.0)
tex = nodes.new("ShaderNodeTexImage")
tex.image = image
tex.interpolation = "Linear"
tex.extension = "REPEAT"
disp = nodes.new("ShaderNodeDisplacement")
disp.inputs["Midlevel"].default_value = midlevel
disp.inputs["Scale"].default_value = 0.01
links.new(coords.outputs["UV"], mapping.inputs["Vector"])
links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
links.new(tex.outputs["Color"], disp.inputs["Height"])
links.new(disp.outputs["Displacement"], output.inputs["Displacement"])
mat.cycles.displacement_method = "DISPLACEMENT"
obj.data.materials.clear()
obj.data.materials.append(mat)

world = bpy.data.worlds.new("black")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
scene.world = world
sun = bpy.data.lights.new("sun", "SUN")
sun.energy = math.pi
sun.angle = 0.0
sun_object = bpy.data.objects.new("sun", sun)
scene.collection.objects.link(sun_object)
direction = mathutils.Vector((-0.5, 0.6, -0.55)).normalized()  # meso's (-0.5, -0.55, -0.6)
sun_object.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
camera = bpy.data.cameras.new("camera")
camera.sensor_fit = "VERTICAL"
camera.angle_y = math.radians(40.0)
camera_object = bpy.data.objects.new("camera", camera)
scene.collection.objects.link(camera_object)
camera_object.location = (0.0, -3.2, 1.2)  # meso's (0, 1.2, 3.2)
camera_object.rotation_euler = (-camera_object.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = camera_object
scene.render.resolution_x, scene.render.resolution_y = 320, 240
scene.render.resolution_percentage = 100
scene.render.film_transparent = True
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
