"""Opens a GLB in Blender (as the `bpy` module, headless) and checks what an
artist would see: the meshes, their shape keys in ARKit's exact spelling,
that every key moves something, and that every image opens. With --render DIR it also renders the
head at a few keys to PNGs, for looking at (never committed).

    python3 tests/python/blender_glb.py FILE.glb [--keys 52] [--render DIR]

Exit status 0 when the checks hold; the findings go to stdout as JSON.
"""
import argparse
import json
import math
import sys

import bpy
from mathutils import Vector

ARKIT = [
    "eyeBlinkLeft", "eyeLookDownLeft", "eyeLookInLeft", "eyeLookOutLeft", "eyeLookUpLeft",
    "eyeSquintLeft", "eyeWideLeft", "eyeBlinkRight", "eyeLookDownRight", "eyeLookInRight",
    "eyeLookOutRight", "eyeLookUpRight", "eyeSquintRight", "eyeWideRight", "jawForward",
    "jawLeft", "jawRight", "jawOpen", "mouthClose", "mouthFunnel", "mouthPucker", "mouthLeft",
    "mouthRight", "mouthSmileLeft", "mouthSmileRight", "mouthFrownLeft", "mouthFrownRight",
    "mouthDimpleLeft", "mouthDimpleRight", "mouthStretchLeft", "mouthStretchRight",
    "mouthRollLower", "mouthRollUpper", "mouthShrugLower", "mouthShrugUpper", "mouthPressLeft",
    "mouthPressRight", "mouthLowerDownLeft", "mouthLowerDownRight", "mouthUpperUpLeft",
    "mouthUpperUpRight", "browDownLeft", "browDownRight", "browInnerUp", "browOuterUpLeft",
    "browOuterUpRight", "cheekPuff", "cheekSquintLeft", "cheekSquintRight", "noseSneerLeft",
    "noseSneerRight", "tongueOut",
]

POSES = ["neutral", "jawOpen", "eyeBlinkLeft", "eyeLookOutLeft", "mouthSmileLeft", "tongueOut"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("glb")
    parser.add_argument("--keys", type=int, default=52)
    parser.add_argument("--render")
    args = parser.parse_args()

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=args.glb)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    report = {"file": args.glb, "meshes": [], "problems": []}
    arkit_keys = set()
    for o in meshes:
        keys = o.data.shape_keys.key_blocks if o.data.shape_keys else []
        names = [k.name for k in keys if k.name != "Basis"]
        moving = []
        for k in keys:
            if k.name == "Basis":
                continue
            basis = k.relative_key
            moved = max((a.co - b.co).length for a, b in zip(k.data, basis.data)) if len(k.data) else 0
            if moved > 0:
                moving.append(k.name)
        report["meshes"].append(
            {"name": o.name, "vertices": len(o.data.vertices), "shape_keys": len(names), "moving": len(moving)}
        )
        arkit_keys.update(n for n in names if n in ARKIT)
        for n in names:
            if n not in ARKIT:
                report["problems"].append(f"{o.name}: shape key {n!r} is not in ARKit's spelling")
    # Every image the file has opens (a WebP or PNG Blender cannot read
    # comes in with no pixels).
    report["images"] = [{"name": i.name, "size": list(i.size)} for i in bpy.data.images]
    for i in bpy.data.images:
        if i.size[0] == 0 or i.size[1] == 0:
            report["problems"].append(f"image {i.name!r} did not open")
    missing = [n for n in ARKIT if n not in arkit_keys]
    report["arkit_keys"] = len(arkit_keys)
    if len(arkit_keys) < args.keys:
        report["problems"].append(f"only {len(arkit_keys)} of ARKit's shape keys (missing {missing})")
    if args.render:
        render(meshes, args.render)
    print(json.dumps(report, indent=1))
    sys.exit(1 if report["problems"] else 0)


def render(meshes, out_dir):
    import os

    os.makedirs(out_dir, exist_ok=True)
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "MATERIAL"
    scene.render.resolution_x = 640
    scene.render.resolution_y = 640
    lo = Vector((math.inf,) * 3)
    hi = Vector((-math.inf,) * 3)
    for o in meshes:
        for corner in o.bound_box:
            p = o.matrix_world @ Vector(corner)
            lo = Vector(map(min, lo, p))
            hi = Vector(map(max, hi, p))
    size = hi - lo
    # Frame the face: between the eyeballs if the model has meshes named
    # eye*, else the top of the model; glTF's +Z forward is Blender's -Y.
    eyes = [o for o in meshes if o.name.lower().startswith("eye")]
    if len(eyes) >= 2:
        centres = [sum((o.matrix_world @ v.co for v in o.data.vertices), Vector()) / len(o.data.vertices) for o in eyes[:2]]
        span = (centres[0] - centres[1]).length
        target = (centres[0] + centres[1]) / 2 - Vector((0, 0, 0.8 * span))
        scale = 4.0 * span
    else:
        target = Vector(((lo.x + hi.x) / 2, lo.y, hi.z - 0.25 * size.z))
        scale = 0.5 * max(size.x, size.z)
    camera_data = bpy.data.cameras.new("camera")
    camera_data.type = "ORTHO"
    camera_data.ortho_scale = scale
    camera = bpy.data.objects.new("camera", camera_data)
    scene.collection.objects.link(camera)
    scene.camera = camera
    for view, offset in [("front", Vector((0, -1, 0))), ("three_quarter", Vector((0.7, -0.7, 0.1)))]:
        camera.location = target + offset * 2 * max(size)
        camera.rotation_euler = (target - camera.location).to_track_quat("-Z", "Y").to_euler()
        for pose in POSES:
            for o in meshes:
                if o.data.shape_keys:
                    for k in o.data.shape_keys.key_blocks:
                        k.value = 1.0 if k.name == pose else 0.0
            scene.render.filepath = os.path.join(out_dir, f"{pose}_{view}.png")
            bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    main()
