# Blender's Decimate modifier (collapse) run headless, a peer in scripts/bench.py (speed, quality):
#   blender -b --factory-startup --python scripts/blender_decimate.py -- IN.glb OUT.glb RATIO
import sys

import bpy
import numpy as np

if "bool" not in np.__dict__:  # Blender 3.4's glTF add-on still uses np.bool (removed in numpy 1.24)
    np.bool = bool

argv = sys.argv[sys.argv.index("--") + 1:]
src, dst, ratio = argv[0], argv[1], float(argv[2])
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=src)
for ob in list(bpy.context.scene.objects):
    if ob.type != "MESH":
        continue
    mod = ob.modifiers.new(name="Decimate", type="DECIMATE")
    mod.decimate_type = "COLLAPSE"
    mod.ratio = ratio
    mod.use_collapse_triangulate = True
bpy.ops.export_scene.gltf(filepath=dst, export_format="GLB", export_apply=True)
