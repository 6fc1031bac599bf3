# Run by scripts/blender_cage_check.sh inside Blender:
#   blender -b --factory-startup --python scripts/blender_subsurf_limit.py -- CAGE.obj OUT.obj LEVELS
# Imports a cage OBJ as a mesh (coordinates kept as they are), adds a
# Subdivision Surface modifier (Catmull-Clark, LEVELS levels, "use limit
# surface" as Blender's default) and writes the evaluated mesh -- Blender's
# limit positions -- as OBJ (triangles), in the cage's coordinates. Prints
# how far the imported cage moved from the file (should be 0).
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
cage_path, out_path, levels = args[0], args[1], int(args[2])

bpy.ops.wm.read_factory_settings(use_empty=True)
# forward Y, up Z: Blender's own axes, so no rotation is applied.
bpy.ops.wm.obj_import(filepath=cage_path, forward_axis="Y", up_axis="Z")
obj = bpy.context.selected_objects[0]

# The imported cage against the file's vertices.
file_vertices = []
with open(cage_path) as f:
    for line in f:
        if line.startswith("v "):
            file_vertices.append(tuple(float(x) for x in line.split()[1:4]))
world = obj.matrix_world
imported = [world @ v.co for v in obj.data.vertices]
moved = max(
    max(abs(a - b) for a, b in zip(p, q)) for p, q in zip(imported, file_vertices)
) if len(imported) == len(file_vertices) else float("inf")
print("blender: imported %d vertices, %d faces (file: %d vertices); largest "
      "coordinate change %.3g" % (len(obj.data.vertices), len(obj.data.polygons),
                                  len(file_vertices), moved))

modifier = obj.modifiers.new("Subdivision", "SUBSURF")
modifier.subdivision_type = "CATMULL_CLARK"
modifier.levels = levels
modifier.render_levels = levels
print("blender: subdivision surface modifier, levels %d, use_limit_surface %s, "
      "quality %d" % (levels, modifier.use_limit_surface, modifier.quality))

evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
mesh = evaluated.to_mesh()
with open(out_path, "w") as out:
    for v in mesh.vertices:
        p = world @ v.co
        out.write("v %.9g %.9g %.9g\n" % (p.x, p.y, p.z))
    for poly in mesh.polygons:
        corners = list(poly.vertices)
        for k in range(1, len(corners) - 1):
            out.write("f %d %d %d\n" % (corners[0] + 1, corners[k] + 1,
                                        corners[k + 1] + 1))
print("blender: wrote %d limit vertices, %d polygons to %s"
      % (len(mesh.vertices), len(mesh.polygons), out_path))
evaluated.to_mesh_clear()
