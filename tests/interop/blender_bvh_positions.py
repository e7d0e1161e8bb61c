# Joint world positions of BVH files as Blender's importer reads them (Debian's blender, headless).
# Prints "FILE JOINT FRAME X Y Z" lines in file units and file axes (the importer turns Y-up files
# Z-up: file (x, y, z) is Blender (x, -z, y)).
#   usage: blender -b --factory-startup --python blender_bvh_positions.py -- MAX_FRAMES FILE.bvh...
import builtins
import sys

import bpy

# Blender 3.4's importer opens files with mode 'rU', which Python 3.11 refuses: drop the 'U'.
_open = builtins.open
builtins.open = lambda f, mode='r', *a, **k: _open(f, mode.replace('U', ''), *a, **k)

args = sys.argv[sys.argv.index('--') + 1:]
max_frames = int(args[0])
for path in args[1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_anim.bvh(filepath=path, global_scale=1.0, frame_start=1, use_fps_scale=False,
                            update_scene_fps=False, update_scene_duration=True, rotate_mode='NATIVE')
    arm = [o for o in bpy.data.objects if o.type == 'ARMATURE'][0]
    scene = bpy.context.scene
    frames = min(max_frames, scene.frame_end - scene.frame_start + 1)
    out = []
    for f in range(frames):
        scene.frame_set(scene.frame_start + f)
        for bone in arm.pose.bones:
            p = arm.matrix_world @ bone.head
            out.append(f'{path} {bone.name} {f} {p.x:.6f} {p.z:.6f} {-p.y:.6f}')
    print('\n'.join(out), flush=True)
