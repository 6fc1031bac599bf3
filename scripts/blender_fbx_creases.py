# Run by scripts/blender_crease_check.sh inside Blender:
#   blender -b --factory-startup --python-exit-code 1 \
#     --python scripts/blender_fbx_creases.py -- CAGE.fbx VERTICES FACES CREASES
# Imports a cage written by `sdcb cage -o CAGE.fbx` with Blender's FBX
# importer (subdivision data on) and prints what Blender made of it: the
# mesh's vertex, edge and face counts, the edges with crease >= 0.99, the
# Subdivision Surface modifier. Then evaluates that modifier (3 levels) and
# measures, at every cage vertex with three or more creased edges (a corner:
# with infinitely sharp creases its limit position is the vertex itself),
# the distance to Blender's subdivided mesh, in percent of the cage's
# largest bounding-box side. Exits 1 unless the counts equal the expected
# ones and those corners stay where they are (within 1e-3 %).
import sys

import bpy
from mathutils import kdtree

args = sys.argv[sys.argv.index("--") + 1:]
path = args[0]
expected = {"vertices": int(args[1]), "faces": int(args[2]),
            "creased edges": int(args[3])}

bpy.ops.wm.read_factory_settings(use_empty=True)
result = bpy.ops.import_scene.fbx(filepath=path, use_subsurf=True)
meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
if result != {"FINISHED"} or len(meshes) != 1:
    print("blender: import of %s gave %s and %d meshes" % (path, result, len(meshes)))
    sys.exit(1)
obj = meshes[0]
mesh = obj.data
creased = [e for e in mesh.edges if e.crease >= 0.99]
found = {"vertices": len(mesh.vertices), "faces": len(mesh.polygons),
         "creased edges": len(creased)}
print("blender: imported %s: %d vertices, %d edges, %d faces; %d edges with "
      "crease >= 0.99 (crease values %s); modifiers %s" % (
          path, len(mesh.vertices), len(mesh.edges), len(mesh.polygons),
          len(creased), sorted({round(e.crease, 4) for e in mesh.edges}),
          [m.type for m in obj.modifiers]))

# Blender's limit surface at the corners.
subsurf = [m for m in obj.modifiers if m.type == "SUBSURF"]
modifier = subsurf[0] if subsurf else obj.modifiers.new("Subdivision", "SUBSURF")
modifier.levels = 3
world = obj.matrix_world
cage_points = [world @ v.co for v in mesh.vertices]
side = max(max(p[c] for p in cage_points) - min(p[c] for p in cage_points)
           for c in range(3))
crease_count = [0] * len(mesh.vertices)
for e in creased:
    for v in e.vertices:
        crease_count[v] += 1
corners = [i for i, n in enumerate(crease_count) if n >= 3]


def corner_distance_percent():
    """Farthest corner from Blender's subdivided mesh, % of the cage's size."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    limit = evaluated.to_mesh()
    tree = kdtree.KDTree(len(limit.vertices))
    for i, v in enumerate(limit.vertices):
        tree.insert(world @ v.co, i)
    tree.balance()
    moved = max((tree.find(cage_points[i])[2] for i in corners), default=0.0)
    count = len(limit.vertices)
    evaluated.to_mesh_clear()
    return 100.0 * moved / side, count


moved_percent, count = corner_distance_percent()
print("blender: subdivision surface, %d levels: %d vertices; %d corners (3 or "
      "more creased edges), the farthest %.3g %% of the cage's size from "
      "Blender's subdivided mesh" % (modifier.levels, count, len(corners),
                                     moved_percent))
# The same without the creases: what they hold in place.
for e in mesh.edges:
    e.crease = 0.0
mesh.update()
print("blender: without the creases the farthest corner is %.3g %% away"
      % corner_distance_percent()[0])

ok = found == expected and (not corners or moved_percent < 1e-3)
if found != expected:
    print("blender: expected %s, found %s" % (expected, found))
if not ok:
    print("blender_fbx_creases: Blender's import does not match the cage")
    sys.exit(1)
print("blender_fbx_creases: ok")
