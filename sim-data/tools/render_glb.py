"""Renders a GLB headless with Blender as a Python module (`pip install bpy`),
in the GLB's own materials and normals, to judge how an avatar looks:

    python3 sim-data/tools/render_glb.py GLB PNG_DIR [SHAPE=WEIGHT ...]

It writes front, three-quarter and side views and close-ups of the eyes and
the mouth, framed on the eyeballs (their midpoint, and the distance between
them as the unit), so avatars in other units frame alike (glTF is +y up; the importer turns it to
Blender's +z up). With SHAPE=WEIGHT arguments (ARKit names, e.g.
`jawOpen=1`), every mesh's shape key of that name is set first and the
file names carry the pose. Cycles on the CPU (24 samples), a dim grey
sky and a sun from above the camera, a little to the right. The PNGs are
for looking at, never for committing.
"""
import os
import sys

import bpy
from mathutils import Vector

# Views: (name, direction from the target to the camera in glTF axes,
# target's offset from the eyes' midpoint in glTF axes, size of the view),
# lengths in units of the distance between the eyeballs' centres.
VIEWS = [
    ("front", (0, 0, 1), (0, -0.45, -1), 4.2),
    ("three_quarter", (0.7, 0.1, 0.7), (0, -0.45, -1), 4.2),
    ("side", (1, 0, 0), (0, -0.45, -1), 4.2),
    ("eyes", (0.15, 0.1, 1), (0, 0, 0), 1.7),
    ("mouth", (0.2, -0.05, 1), (0, -1.2, 0), 1.3),
]


def gltf_to_blender(v):
    """glTF (x, y, z), +y up, to Blender's (x, -z, y), +z up."""
    return Vector((v[0], -v[2], v[1]))


def set_pose(pose):
    for ob in bpy.context.scene.objects:
        keys = getattr(ob.data, "shape_keys", None)
        if keys is None:
            continue
        for block in keys.key_blocks:
            if block.name in pose:
                block.value = pose[block.name]


def eye_frame():
    """The eyes' midpoint (Blender axes) and the distance between the
    centres of the meshes named like eyes; the bounding box's top quarter
    stands in when there are none."""
    centres = []
    for ob in bpy.context.scene.objects:
        if ob.type == "MESH" and "eye" in ob.name.lower():
            corners = [ob.matrix_world @ Vector(c) for c in ob.bound_box]
            centres.append(sum(corners, Vector()) / 8)
    if len(centres) == 2:
        return (centres[0] + centres[1]) / 2, (centres[0] - centres[1]).length
    corners = [
        ob.matrix_world @ Vector(c)
        for ob in bpy.context.scene.objects
        if ob.type == "MESH"
        for c in ob.bound_box
    ]
    lo = Vector(min(c[i] for c in corners) for i in range(3))
    hi = Vector(max(c[i] for c in corners) for i in range(3))
    return Vector(((lo.x + hi.x) / 2, lo.y, hi.z - (hi.z - lo.z) / 4)), (hi.x - lo.x) / 4


def render(glb, out_dir, pose):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=glb)
    set_pose(pose)
    scene = bpy.context.scene
    # Cycles on the CPU: the only engine that renders the materials' node
    # trees (vertex tints included) without a GPU.
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 24
    scene.cycles.use_denoising = False
    world = bpy.data.worlds.new("studio")
    world.color = (0.25, 0.25, 0.27)
    scene.world = world
    sun = bpy.data.objects.new("key", bpy.data.lights.new("key", "SUN"))
    sun.data.energy = 3.5
    sun.rotation_euler = (1.0, 0.0, 0.35)
    scene.collection.objects.link(sun)
    scene.render.resolution_x = 600
    scene.render.resolution_y = 600
    middle, unit = eye_frame()
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "ORTHO"
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    tag = "_".join(f"{k}{v:g}" for k, v in sorted(pose.items())) or "rest"
    for name, direction, offset, size in VIEWS:
        target = middle + unit * gltf_to_blender(offset)
        d = gltf_to_blender(direction).normalized()
        cam.location = target + d * (20 * unit)
        cam.rotation_euler = (-d).to_track_quat("-Z", "Y").to_euler()
        cam_data.ortho_scale = size * unit
        cam_data.clip_start = 0.01 * unit
        cam_data.clip_end = 100 * unit
        scene.render.filepath = os.path.join(out_dir, f"{tag}_{name}.png")
        bpy.ops.render.render(write_still=True)


def main():
    glb, out_dir = sys.argv[1], sys.argv[2]
    pose = {}
    for arg in sys.argv[3:]:
        name, _, weight = arg.partition("=")
        pose[name] = float(weight or 1)
    os.makedirs(out_dir, exist_ok=True)
    render(os.path.abspath(glb), out_dir, pose)


if __name__ == "__main__":
    main()
