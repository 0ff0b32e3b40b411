"""Renders the default avatar's OBJ poses (from `examples/dump_avatar.rs`)
headless with Blender as a Python module (`pip install bpy`):

    python3 sim-data/tools/render_avatar.py OBJ_DIR PNG_DIR [pose ...]

For each pose it writes front, three-quarter and side views, and close-ups
of the eyes and the mouth. Workbench engine, a colour per part. The PNGs
and OBJs are for looking at, never for committing.
"""
import math
import os
import sys

import bpy
from mathutils import Vector

COLOURS = {
    "skin": (0.85, 0.66, 0.55, 1),
    "ears": (0.82, 0.62, 0.52, 1),
    "sockets": (0.55, 0.30, 0.30, 1),
    "mouthCavity": (0.45, 0.18, 0.20, 1),
    "eyeLeft": (0.95, 0.95, 0.97, 1),
    "eyeRight": (0.95, 0.95, 0.97, 1),
    "eyeLeftIris": (0.25, 0.35, 0.55, 1),
    "eyeRightIris": (0.25, 0.35, 0.55, 1),
    "teethUpper": (0.97, 0.95, 0.85, 1),
    "teethLower": (0.97, 0.95, 0.85, 1),
    "gumsUpper": (0.85, 0.40, 0.45, 1),
    "gumsLower": (0.85, 0.40, 0.45, 1),
    "tongue": (0.80, 0.25, 0.30, 1),
}

# Views in ARKit coordinates (+x person's left, +y up, +z out of the face):
# (name, camera position, target, orthographic scale).
VIEWS = [
    ("front", (0.0, 0.0, 0.8), (0.0, -0.03, 0.0), 0.42),
    ("three_quarter", (0.55, 0.08, 0.55), (0.0, -0.03, -0.03), 0.42),
    ("side", (0.8, 0.0, -0.04), (0.0, -0.03, -0.04), 0.42),
    ("back", (0.0, 0.1, -0.8), (0.0, -0.03, -0.04), 0.42),
    ("eyes", (0.06, 0.06, 0.5), (0.0, 0.028, 0.0), 0.10),
    ("mouth", (0.08, -0.03, 0.5), (0.0, -0.05, 0.0), 0.09),
]


def blender(p):
    """ARKit (x, y, z) to Blender's z-up frame as the OBJ importer maps it."""
    return Vector((p[0], -p[2], p[1]))


def render(obj_path, out_dir, pose):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=obj_path)
    for ob in bpy.context.scene.objects:
        ob.color = COLOURS.get(ob.name, (0.5, 0.5, 0.5, 1))
        for poly in ob.data.polygons:
            poly.use_smooth = True
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "OBJECT"
    scene.display.shading.show_backface_culling = False
    scene.render.resolution_x = 800
    scene.render.resolution_y = 800
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "ORTHO"
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    for name, pos, target, scale in VIEWS:
        cam.location = blender(pos)
        direction = blender(target) - cam.location
        cam.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
        cam_data.ortho_scale = scale
        cam_data.clip_start = 0.01
        cam_data.clip_end = 5.0
        scene.render.filepath = os.path.join(out_dir, f"{pose}_{name}.png")
        bpy.ops.render.render(write_still=True)


def main():
    obj_dir, out_dir = sys.argv[1], sys.argv[2]
    poses = sys.argv[3:] or sorted(f[:-4] for f in os.listdir(obj_dir) if f.endswith(".obj"))
    os.makedirs(out_dir, exist_ok=True)
    for pose in poses:
        render(os.path.join(obj_dir, pose + ".obj"), out_dir, pose)


if __name__ == "__main__":
    main()
